// Anisotropic recovery: fits each anisotropic model to noisy synthetic tables of itself, turned
// by several angles about the normal (0° to 135°), and prints the recovered widths and rotation against
// the truth (compared in canonical form: α_x ≤ α_y, φ₀ mod 180°), with the seconds per fit.
// Two sources per case: N random pairs of directions (--samples, noise --noise) and, for
// ggx-aniso, an RGL-format file written with the test writer and read back by the RGL reader
// over its full half/difference grid.
//
//   bench_aniso [--samples 100000] [--noise 0.02] [--threads 1]
#include <CLI/CLI.hpp>
#include <chrono>

#include "aniso_tables.h"
#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/registry.h"
#include "brdffit/rgl.h"

using namespace brdffit;

namespace {

void report(const Model& model, const SampleSet& data, const std::vector<double>& truth, double rotation, int threads) {
  FitOptions options;
  options.threads = threads;
  const FitResult fit = fit_model(model, data, options);
  const int x = model.num_values() - 3;  // widths and φ₀ are each model's last three values
  const test::TangentFrame want = test::canonical_frame(truth[x], truth[x + 1], truth[x + 2]);
  const test::TangentFrame got = test::canonical_frame(fit.values[x], fit.values[x + 1], fit.values[x + 2]);
  fmt::print("{:<24} {:<22} {:>8} {:>6.1f}  {:>8.4g} {:>8.4g} {:>7.2f}  {:>+7.2f}% {:>+7.2f}% {:>6.2f}°  {:>6.1f}\n",
             model.name(), data.source, data.size(), rotation, got.along_x, got.along_y, got.phi0,
             100 * (got.along_x / want.along_x - 1), 100 * (got.along_y / want.along_y - 1),
             test::angle_difference(got.phi0, want.phi0), fit.seconds);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"anisotropic recovery benchmark"};
  size_t samples = 100000;
  double noise = 0.02;
  int threads = 1;
  app.add_option("--samples", samples, "Random pairs per synthetic table");
  app.add_option("--noise", noise, "Relative Gaussian noise on every value");
  app.add_option("--threads", threads, "Threads (0: all cores)");
  CLI11_PARSE(app, argc, argv);
  try {
    const std::vector<test::AnisotropicCase> cases = test::anisotropic_cases();
    fmt::print("{:<24} {:<22} {:>8} {:>6}  {:>8} {:>8} {:>7}  {:>8} {:>8} {:>7}  {:>6}\n", "model", "table", "samples",
               "turned", "width x", "width y", "φ₀ fit", "err x", "err y", "err φ₀", "s");
    fmt::print("(widths: α_x, α_y, or n_u, n_v; canonical form: width x ≤ width y, φ₀ mod 180°)\n");
    uint64_t seed = 0;
    for (const test::AnisotropicCase& c : cases)
      for (double rotation : {0.0, 30.0, 60.0, 90.0, 135.0}) {
        const Model& model = *find_model(c.model);
        const std::vector<double> truth = test::turned_values(model, c.params, c.width_x, c.width_y, rotation);
        SampleSet random = test::anisotropic_samples(model, truth, samples, noise, ++seed);
        random.source = fmt::format("random pairs, {:g}% noise", 100 * noise);
        report(model, random, truth, rotation, threads);
        if (c.model != "ggx-aniso") continue;
        const RglBrdf table = RglBrdf::parse(test::tensor_file_bytes(test::anisotropic_rgl_fields(model, truth, 2)),
                                             "anisotropic RGL file");
        SamplingOptions sampling;
        sampling.max_angle_deg = 80;
        report(model, table.samples(sampling), truth, rotation, threads);
      }
  } catch (const Error& e) {
    fmt::print(stderr, "bench_aniso: {}\n", e.what());
    return 1;
  }
  return 0;
}
