// Two lobes against one: fits FIRST and FIRST+SECOND to each table and prints both errors and
// the seconds per fit. The two-lobe fit is run twice: from the composite's defaults (fit_model
// alone) and from the one-lobe optimum embedded by the composite's exact nesting, whose error is
// never above the one-lobe error. `brdffit fit --models ggx+ggx` (fit_models) does both and
// keeps the better.
//
//   bench_two_lobes TABLE... [--pair ggx+ggx] [--threads 1]
#include <CLI/CLI.hpp>

#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/measured.h"
#include "brdffit/registry.h"

using namespace brdffit;

int main(int argc, char** argv) {
  CLI::App app{"two-lobe benchmark"};
  std::vector<std::string> tables;
  std::string pair = "ggx+ggx";
  int threads = 1;
  app.add_option("tables", tables, "MERL/RGL/CSV tables")->required();
  app.add_option("--pair", pair, "Two-lobe model FIRST+SECOND");
  app.add_option("--threads", threads, "Threads (0: all cores)");
  CLI11_PARSE(app, argc, argv);
  try {
    const Model* outer = find_model(pair);
    if (!outer) fail("unknown model '{}'", pair);
    const Nesting& first_lobe = outer->nestings().front();
    const Model& single = *find_model(first_lobe.inner);
    FitOptions options;
    options.threads = threads;
    fmt::print("{:<28} {:>10} {:>7}  {:>14} {:>7}  {:>14} {:>7}   (cosine metric; seconds)\n", "table", single.name(),
               "s", pair + " default", "s", pair + " nested", "s");
    for (const std::string& path : tables) {
      const SampleSet data = load_samples(path, SamplingOptions{});
      const FitResult one = fit_model(single, data, options);
      const FitResult two = fit_model(*outer, data, options);
      FitOptions nested = options;
      nested.initial_values = embed_values(*outer, first_lobe, single, one.values);
      const FitResult from_one = fit_model(*outer, data, nested);
      const std::string name = path.substr(path.find_last_of('/') + 1);
      fmt::print("{:<28} {:>10.5g} {:>7.2f}  {:>14.5g} {:>7.2f}  {:>14.5g} {:>7.2f}\n", name, one.metrics.cosine,
                 one.seconds, two.metrics.cosine, two.seconds, from_one.metrics.cosine, from_one.seconds);
    }
  } catch (const Error& e) {
    fmt::print(stderr, "bench_two_lobes: {}\n", e.what());
    return 1;
  }
  return 0;
}
