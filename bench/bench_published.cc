// Our fits against published parameters of the literature, on the same tables under the metric
// each publication minimised:
//   Ngan et al. 2005 (ngan_*.fit)          cosine: solid-angle weighted RMS of f·cosθi
//   Löw et al. 2012 E1 (low_*_E1.fit)      cosine
//   Löw et al. 2012 E2 (low_*_E2.fit)      log with Löw's weights (÷ sinθo): BBM's lowLog
//   Bagher et al. 2012 (bagher_sgd.fit)    cosine, and log
//
//   bench_published SHARED_DIR TABLE_DIR [MODEL...]
//
// TABLE_DIR holds the decompressed merl-proxy tables (<material>.binary); SHARED_DIR is
// ../shared. MODEL... limits the rows to these models. Prints one row per material, model and
// metric, as soon as it is measured. A model with approximate nestings (sgd: cook-torrance) is
// also fitted from its inner model's optimum, as `brdffit fit --models cook-torrance,sgd` does;
// seconds include that. Where we lose, the row adds the fit started from the published values.
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>

#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/measured.h"
#include "brdffit/published_fits.h"
#include "brdffit/registry.h"

using namespace brdffit;

namespace {

struct Row {
  const char* model;
  const char* file;
  Metric metric;
  bool low_weighting;  // Löw's measure (SamplingOptions::low_weighting)
};

const std::vector<Row> kRows = {
    {"cook-torrance", "ngan_cooktorrance.fit", Metric::Cosine, false},
    {"ward", "ngan_ward.fit", Metric::Cosine, false},
    {"ashikhmin-shirley", "ngan_ashikhminshirley.fit", Metric::Cosine, false},
    {"lafortune", "ngan_lafortune.fit", Metric::Cosine, false},
    {"low-cook-torrance", "low_cooktorrance_E1.fit", Metric::Cosine, false},
    {"low-cook-torrance", "low_cooktorrance_E2.fit", Metric::Log, true},
    {"low-ashikhmin-shirley", "low_ashikhminshirley_E1.fit", Metric::Cosine, false},
    {"low-ashikhmin-shirley", "low_ashikhminshirley_E2.fit", Metric::Log, true},
    {"low-smooth", "low_lowsmooth_E2.fit", Metric::Log, true},
    {"low-microfacet", "low_lowmicrofacet_E2.fit", Metric::Log, true},
    {"sgd", "bagher_sgd.fit", Metric::Cosine, false},
    {"sgd", "bagher_sgd.fit", Metric::Log, false},
};

// fit_model, plus what the fitter does with a model's approximate nestings when their inner
// model is fitted in the same run: start from the inner optimum mapped (embed_values), keep the
// better. Seconds add up.
FitResult fit_with_nestings(const Model& model, const SampleSet& data, const FitOptions& options) {
  FitResult best = fit_model(model, data, options);
  double seconds = best.seconds;
  for (const Nesting& nesting : model.nestings()) {
    if (nesting.exact) continue;
    const Model& inner = *find_model(nesting.inner);
    const FitResult inner_fit = fit_model(inner, data, options);
    FitOptions from_inner = options;
    from_inner.initial_values = embed_values(model, nesting, inner, inner_fit.values);
    FitResult nested = fit_model(model, data, from_inner);
    seconds += inner_fit.seconds + nested.seconds;
    if (nested.ok && nested.metrics.get(options.metric) < best.metrics.get(options.metric)) best = std::move(nested);
  }
  best.seconds = seconds;
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    fmt::print(stderr, "usage: bench_published SHARED_DIR TABLE_DIR [MODEL...]\n");
    return 2;
  }
  const std::string shared = argv[1], tables = argv[2];
  const std::vector<std::string> only(argv + 3, argv + argc);
  try {
    fmt::print("{:<20} {:<22} {:<28} {:>12} {:>12} {:>8} {:>8}\n", "material", "model", "published (metric)",
               "published", "brdffit", "ratio", "seconds");
    for (const char* material : {"gold-metallic-paint", "blue-acrylic", "red-fabric"}) {
      for (bool low_weighting : {false, true}) {
        SamplingOptions sampling;
        sampling.low_weighting = low_weighting;
        const SampleSet data = load_samples(tables + "/" + material + ".binary", sampling);
        for (const Row& row : kRows) {
          if (row.low_weighting != low_weighting) continue;
          if (!only.empty() && std::find(only.begin(), only.end(), row.model) == only.end()) continue;
          const Model& model = *find_model(row.model);
          const auto fits = read_published_fits(shared + "/reference/published-fits/" + row.file);
          const auto published = to_model_values(model, fits.at(material));
          if (!published) fail("{}: {} has no {} fit to map", row.file, material, row.model);
          const double theirs = evaluate_metrics(model, *published, data).get(row.metric);
          FitOptions options;
          options.metric = row.metric;
          const FitResult ours = fit_with_nestings(model, data, options);
          const double mine = ours.metrics.get(row.metric);
          const std::string label =
              fmt::format("{} ({}{})", row.file, metric_name(row.metric), low_weighting ? ", Löw" : "");
          fmt::print("{:<20} {:<22} {:<28} {:>12.6g} {:>12.6g} {:>8.3f} {:>8.1f}{}", material, row.model, label, theirs,
                     mine, mine / theirs, ours.seconds, ours.ok ? "" : "  " + ours.error);
          if (mine > theirs) {
            // For the fitter's owner: is it the start or the descent? The same fit started from
            // the published values, clamped into our bounds.
            FitOptions from_published = options;
            from_published.initial_values = *published;
            const std::vector<ParamSpec> specs = model.parameters();
            for (size_t i = 0, offset = 0; i < specs.size(); offset += specs[i].channels, ++i)
              for (int c = 0; c < specs[i].channels; ++c)
                from_published.initial_values[offset + c] =
                    std::clamp(from_published.initial_values[offset + c], specs[i].lower, specs[i].upper);
            const FitResult restarted = fit_model(model, data, from_published);
            fmt::print("  (started from the published values: {:.6g}, {:.1f} s)", restarted.metrics.get(row.metric),
                       restarted.seconds);
          }
          fmt::print("\n");
          std::fflush(stdout);
        }
      }
    }
  } catch (const Error& e) {
    fmt::print(stderr, "bench_published: error: {}\n", e.what());
    return 1;
  }
  return 0;
}
