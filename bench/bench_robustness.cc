// The fitter's floor on a wide set of materials: every model fitted to every member, and a
// count of what must never happen.
//
//   bench_robustness [--shared DIR] [--merl DIR] [--max-samples N] [--models LIST] [--repeat K]
//
// Members: every registered model baked as a full MERL-format table (90x90x180 bins, through
// write_merl and the MERL reader, so with the same sampling as a measured table) at five
// parameter sets (middle of the ranges; shape parameters near their lower and near their upper
// bounds; dark; metallic: no diffuse, bright lobe), with 1% multiplicative noise; the shared
// RGL files; the decompressed MERL proxies in --merl; the DiLiGenT ball's pixels.
// For every (member, model) it reports:
//   - nesting violations: the model's error above that of a model it contains exactly;
//   - verdicts: poor/failed counts, and whether each poor one is deserved (its error at least
//     1.5x the best model's on that member, i.e. some model describes the data clearly better);
//   - good fits worse than Lambert by more than 5% on any judged metric (cosine, log, relative,
//     l2; must be none), and the worst ratio of a good fit's error to Lambert's;
//   - anisotropic fits of isotropic members whose widths differ by more than 15% (must be none);
//   - seconds per member (all models).
// With --repeat K the first K members are fitted again and every error must be bit-identical.
#include <unistd.h>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <chrono>
#include <filesystem>
#include <map>
#include <optional>
#include <random>

#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/imaging/sphere_fit.h"
#include "brdffit/measured.h"
#include "brdffit/merl.h"
#include "brdffit/registry.h"

using namespace brdffit;
namespace fs = std::filesystem;

namespace {

struct Member {
  std::string name;
  std::function<SampleSet()> load;
};

struct ParameterSet {
  const char* name;
  double shape_t;        // where shape parameters sit in their range (log-spaced where the model says so)
  double diffuse, lobe;  // diffuse and lobe colours as fractions of min(upper, 1)
};

const ParameterSet kParameterSets[] = {
    {"middle", 0.5, 0.5, 0.3}, {"low", 0.03, 0.4, 0.3},     {"high", 0.97, 0.4, 0.3},
    {"dark", 0.5, 0.03, 0.02}, {"metallic", 0.4, 0.0, 0.9},
};

std::vector<double> values_for(const Model& model, const ParameterSet& set) {
  const double tint[3] = {1.0, 0.75, 0.5};
  std::vector<double> values;
  for (const ParamSpec& p : model.parameters())
    for (int c = 0; c < p.channels; ++c) {
      double x;
      if (p.role == Role::DiffuseColour) {
        x = set.diffuse * tint[c] * std::min(p.upper, 1.0);
      } else if (p.role == Role::SpecularColour || (p.role == Role::F0 && p.channels == 3)) {
        x = set.lobe * tint[c] * std::min(p.upper, 1.0);
      } else {
        const double t = set.shape_t;
        x = p.spacing == Spacing::Log && p.lower > 0 ? p.lower * std::pow(p.upper / p.lower, t)
                                                     : p.lower + t * (p.upper - p.lower);
        if (p.integer) x = std::round(x);
      }
      values.push_back(std::clamp(x, p.lower, p.upper));
    }
  return values;
}

SampleSet with_noise(SampleSet set, double noise, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss;
  for (Sample& s : set.samples)
    for (int c = 0; c < 3; ++c) s.value[c] = std::max(0.0, s.value[c] * (1.0 + noise * gauss(rng)));
  return set;
}

std::vector<Member> members(const std::vector<const Model*>& models, const std::string& shared, const std::string& merl,
                            const SamplingOptions& sampling, const fs::path& scratch) {
  std::vector<Member> list;
  uint64_t seed = 1;
  for (const Model* model : models)
    for (const ParameterSet& set : kParameterSets) {
      const std::string name = model->name() + "/" + set.name;
      const fs::path file = scratch / (model->name() + "-" + set.name + ".binary");
      list.push_back({name, [=] {
                        const std::vector<double> values = values_for(*model, set);
                        write_merl(file.string(), [&](const Vec3& l, const Vec3& v) -> Rgb<double> {
                          if (const auto f = model->brdf(values.data(), l, v)) return f->cwiseMax(0.0);
                          return (model->shade(values.data(), l, v) / l.z()).cwiseMax(0.0);
                        });
                        SampleSet samples = with_noise(load_samples(file.string(), sampling), 0.01, seed);
                        fs::remove(file);
                        return samples;
                      }});
      ++seed;
    }
  if (!shared.empty() && fs::is_directory(fs::path(shared) / "data/rgl"))
    for (const auto& entry : fs::directory_iterator(fs::path(shared) / "data/rgl"))
      if (entry.path().extension() == ".bsdf")
        list.push_back(
            {"rgl/" + entry.path().stem().string(), [=] { return load_samples(entry.path().string(), sampling); }});
  if (!merl.empty() && fs::is_directory(merl))
    for (const auto& entry : fs::directory_iterator(merl))
      if (entry.path().extension() == ".binary")
        list.push_back(
            {"merl/" + entry.path().stem().string(), [=] { return load_samples(entry.path().string(), sampling); }});
  const fs::path ball = fs::path(shared) / "data/diligent-ball";
  if (!shared.empty() && fs::is_directory(ball))
    list.push_back({"diligent/ball", [=] {
                      SphereInput input;
                      add_diligent_folder(ball.string(), input);
                      SampleSet samples = observe_sphere(input).samples;
                      apply_sampling_options(samples, SamplingOptions{90.0, 200000, 1});
                      return samples;
                    }});
  return list;
}

constexpr Metric kJudgedMetrics[] = {Metric::Cosine, Metric::Log, Metric::Relative, Metric::L2};

// An anisotropic model's two widths: the parameters just before its frame rotation (Role::Orientation),
// or nothing for an isotropic model.
std::optional<std::pair<double, double>> widths(const Model& model, const FitResult& r) {
  const std::vector<ParamSpec>& params = model.parameters();
  for (size_t i = 2; i < params.size(); ++i)
    if (params[i].role == Role::Orientation)
      return std::pair{r.values[model.offset_of(params[i - 2].name)], r.values[model.offset_of(params[i - 1].name)]};
  return std::nullopt;
}

struct Tally {
  int pairs = 0, nesting_violations = 0, poor = 0, poor_deserved = 0, failed = 0, good_worse_than_lambert = 0;
  int anisotropic_on_isotropic = 0, oriented_on_isotropic = 0;  // fits; of those, width ratio > 1.15
  double worst_good_ratio = 0.0;
  std::string worst_good;
  std::vector<std::string> notes;
};

void judge_member(const std::string& member, bool isotropic, const std::vector<FitResult>& results, Tally& tally) {
  std::map<std::string, const FitResult*> by_name;
  double best = HUGE_VAL;
  for (const FitResult& r : results) {
    by_name[r.model] = &r;
    if (r.ok) best = std::min(best, r.metrics.cosine);
  }
  const FitResult* lambert = by_name.count("lambert") ? by_name["lambert"] : nullptr;
  for (const FitResult& r : results) {
    ++tally.pairs;
    if (r.verdict == Verdict::Failed) {
      ++tally.failed;
      tally.notes.push_back(fmt::format("failed  {} {}: {}", member, r.model, r.error));
      continue;
    }
    for (const Nesting& nesting : find_model(r.model)->nestings()) {
      const auto inner = by_name.find(nesting.inner);
      if (!nesting.exact || inner == by_name.end() || !inner->second->ok) continue;
      if (r.metrics.cosine > inner->second->metrics.cosine * (1.0 + 1e-9)) {
        ++tally.nesting_violations;
        tally.notes.push_back(fmt::format("nesting {} {}: {:.6g} > {} {:.6g}", member, r.model, r.metrics.cosine,
                                          nesting.inner, inner->second->metrics.cosine));
      }
    }
    if (r.verdict == Verdict::Poor) {
      ++tally.poor;
      if (r.metrics.cosine >= 1.5 * best)
        ++tally.poor_deserved;
      else
        tally.notes.push_back(fmt::format("poor?   {} {}: {:.4g} vs best {:.4g}: {}", member, r.model, r.metrics.cosine,
                                          best, r.warnings.empty() ? "" : r.warnings.front()));
    }
    if (r.verdict == Verdict::Good && lambert && lambert->ok && r.model != "lambert") {
      // Worse than Lambert on any judged metric, whichever was minimised.
      double ratio = 0.0;
      const char* worst_metric = "";
      for (const Metric m : kJudgedMetrics)
        if (r.metrics.get(m) / lambert->metrics.get(m) > ratio) {
          ratio = r.metrics.get(m) / lambert->metrics.get(m);
          worst_metric = metric_name(m);
        }
      if (ratio > 1.05) {
        ++tally.good_worse_than_lambert;
        tally.notes.push_back(fmt::format("good>L  {} {}: {} {:.3f}x Lambert's", member, r.model, worst_metric, ratio));
      }
      if (ratio > tally.worst_good_ratio) {
        tally.worst_good_ratio = ratio;
        tally.worst_good = fmt::format("{} {} ({})", member, r.model, worst_metric);
      }
    }
    if (const auto w = widths(*find_model(r.model), r); w && isotropic && r.ok) {
      ++tally.anisotropic_on_isotropic;
      const double ratio = std::max(w->first, w->second) / std::min(w->first, w->second);
      if (ratio > 1.15) {
        ++tally.oriented_on_isotropic;
        tally.notes.push_back(fmt::format("aniso   {} {}: widths {:.4g} and {:.4g} on isotropic data", member, r.model,
                                          w->first, w->second));
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"brdffit robustness: every model on a wide set of materials"};
  std::string shared = "../shared", merl, model_list = "all", only;
  size_t max_samples = 0;
  int repeat = 0;
  app.add_option("--shared", shared, "The shared data folder (RGL files, DiLiGenT ball); '' for none");
  app.add_option("--merl", merl, "A folder of decompressed MERL tables (.binary)");
  app.add_option("--max-samples", max_samples, "Fit a deterministic subset of each member (0: all samples)");
  app.add_option("--models", model_list, "Models to fit, and to bake (default: all)");
  app.add_option("--only", only, "Only members whose name contains this");
  app.add_option("--repeat", repeat, "Fit the first K members twice and require identical errors");
  CLI11_PARSE(app, argc, argv);
  try {
    const std::vector<const Model*> models = parse_model_list(model_list);
    const fs::path scratch = fs::temp_directory_path() / fmt::format("brdffit-robustness-{}", ::getpid());
    fs::create_directories(scratch);
    const SamplingOptions sampling{90.0, max_samples, 1};
    std::vector<Member> list = members(models, shared, merl, sampling, scratch);
    if (!only.empty())
      list.erase(std::remove_if(list.begin(), list.end(),
                                [&](const Member& m) { return m.name.find(only) == std::string::npos; }),
                 list.end());
    Tally tally;
    double total_seconds = 0.0, worst_seconds = 0.0;
    std::vector<std::vector<double>> first_errors;
    fmt::print("{:<34} {:>9} {:>5} {:>5} {:>8}  best\n", "member", "samples", "poor", "fail", "seconds");
    for (size_t i = 0; i < list.size(); ++i) {
      const SampleSet data = list[i].load();
      const auto start = std::chrono::steady_clock::now();
      const std::vector<FitResult> results = fit_models(models, data, FitOptions{});
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      total_seconds += seconds;
      worst_seconds = std::max(worst_seconds, seconds);
      judge_member(list[i].name, data.isotropic, results, tally);
      const FitResult* best = nullptr;
      int poor = 0, failed = 0;
      for (const FitResult& r : results) {
        poor += r.verdict == Verdict::Poor;
        failed += r.verdict == Verdict::Failed;
        if (r.ok && (!best || r.metrics.cosine < best->metrics.cosine)) best = &r;
      }
      fmt::print("{:<34} {:>9} {:>5} {:>5} {:>8.2f}  {} {:.4g}\n", list[i].name, data.size(), poor, failed, seconds,
                 best ? best->model : "-", best ? best->metrics.cosine : NAN);
      if (static_cast<int>(i) < repeat) {
        std::vector<double> errors;
        for (const FitResult& r : results) errors.push_back(r.metrics.cosine);
        first_errors.push_back(errors);
      }
    }
    int repeat_mismatches = 0;
    for (size_t i = 0; i < first_errors.size(); ++i) {
      const std::vector<FitResult> again = fit_models(models, list[i].load(), FitOptions{});
      for (size_t k = 0; k < again.size(); ++k)
        if (!(again[k].metrics.cosine == first_errors[i][k]) &&
            !(std::isnan(again[k].metrics.cosine) && std::isnan(first_errors[i][k])))
          ++repeat_mismatches;
    }
    fs::remove_all(scratch);

    fmt::print("\n");
    for (const std::string& note : tally.notes) fmt::print("{}\n", note);
    fmt::print("\n{} members x {} models = {} pairs\n", list.size(), models.size(), tally.pairs);
    fmt::print("pairs worse than a model they contain exactly: {}\n", tally.nesting_violations);
    fmt::print("poor verdicts: {} ({} deserved: error >= 1.5x the best model's), failed: {}\n", tally.poor,
               tally.poor_deserved, tally.failed);
    fmt::print("good fits worse than Lambert by more than 5% on any of cosine, log, relative, l2: {}\n",
               tally.good_worse_than_lambert);
    fmt::print("anisotropic fits of isotropic members with a width ratio above 1.15: {} of {}\n",
               tally.oriented_on_isotropic, tally.anisotropic_on_isotropic);
    fmt::print("worst ratio of a good fit's error to Lambert's: {:.4f} ({})\n", tally.worst_good_ratio,
               tally.worst_good);
    if (repeat > 0) fmt::print("repeated {} members: {} errors differ\n", first_errors.size(), repeat_mismatches);
    fmt::print("seconds per member (all {} models): mean {:.2f}, worst {:.2f}\n", models.size(),
               total_seconds / std::max<size_t>(1, list.size()), worst_seconds);
    return tally.nesting_violations + tally.good_worse_than_lambert + tally.oriented_on_isotropic + repeat_mismatches >
                   0
               ? 1
               : 0;
  } catch (const Error& e) {
    fmt::print(stderr, "bench_robustness: error: {}\n", e.what());
    return 2;
  }
}
