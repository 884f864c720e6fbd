// Our fits against the parameters Ngan et al. 2005 published, on the same tables under the
// same metric (cosine: Ngan's solid-angle weighted RMS of f·cosθi):
//
//   bench_published SHARED_DIR TABLE_DIR
//
// TABLE_DIR holds the decompressed merl-proxy tables (<material>.binary); SHARED_DIR is
// ../shared. Prints one row per material and model.
#include <fmt/format.h>

#include <filesystem>

#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/measured.h"
#include "brdffit/published_fits.h"

using namespace brdffit;

int main(int argc, char** argv) {
  if (argc != 3) {
    fmt::print(stderr, "usage: bench_published SHARED_DIR TABLE_DIR\n");
    return 2;
  }
  const std::string shared = argv[1], tables = argv[2];
  const std::vector<std::pair<const char*, const char*>> models = {{"cook-torrance", "ngan_cooktorrance.fit"},
                                                                   {"ward", "ngan_ward.fit"},
                                                                   {"ashikhmin-shirley", "ngan_ashikhminshirley.fit"},
                                                                   {"lafortune", "ngan_lafortune.fit"}};
  try {
    fmt::print("{:<22} {:<18} {:>12} {:>12} {:>8} {:>8}\n", "material", "model", "published", "brdffit", "ratio",
               "seconds");
    for (const char* material : {"gold-metallic-paint", "blue-acrylic", "red-fabric"}) {
      const SampleSet data = load_samples(tables + "/" + material + ".binary", SamplingOptions{});
      for (const auto& [name, file] : models) {
        const Model& model = *find_model(name);
        const auto fits = read_published_fits(shared + "/reference/published-fits/" + file);
        const auto published = to_model_values(model, fits.at(material));
        if (!published) fail("{}: {} has no {} fit to map", file, material, name);
        const double theirs = evaluate_metrics(model, *published, data).cosine;
        const FitResult ours = fit_model(model, data, FitOptions{});
        fmt::print("{:<22} {:<18} {:>12.6g} {:>12.6g} {:>8.3f} {:>8.2f}{}\n", material, name, theirs,
                   ours.metrics.cosine, ours.metrics.cosine / theirs, ours.seconds, ours.ok ? "" : "  " + ours.error);
      }
    }
  } catch (const Error& e) {
    fmt::print(stderr, "bench_published: error: {}\n", e.what());
    return 1;
  }
  return 0;
}
