// Fit speed and memory: fits models to a measured table (or to synthetic samples of a model)
// and prints per model the wall and CPU seconds (CPU is what a shared machine cannot inflate), the CPU
// time as a multiple of ggx's in the same run (when ggx is among the models), the error, and the process's
// peak resident memory.
//
//   bench_fit TABLE [--models ggx,...|all] [--threads N] [--polish N | --converge]
//   bench_fit --synthetic N [--models ...]      (N samples of ggx at fixed parameters)
//   bench_fit TABLE --together ...              (one fit_models call, as batch and `fit -m` fit:
//                                                contained models fitted once; per model its own time)
#include <sys/resource.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <random>

#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/measured.h"
#include "brdffit/registry.h"

using namespace brdffit;

namespace {

double cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec + 1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // kilobytes on Linux
}

SampleSet synthetic_ggx(size_t count) {
  const Model& ggx = *find_model("ggx");
  const std::vector<double> values = parameter_values(ggx, {"albedo=0.2,0.3,0.4", "roughness=0.3", "f0=0.5,0.4,0.3"});
  std::mt19937_64 rng(1);
  std::normal_distribution<double> gauss;
  SampleSet set;
  set.source = "synthetic ggx";
  while (set.samples.size() < count) {
    Vec3 l(gauss(rng), gauss(rng), std::abs(gauss(rng))), v(gauss(rng), gauss(rng), std::abs(gauss(rng)));
    l.normalize();
    v.normalize();
    set.samples.push_back({l, v, ggx.shade(values.data(), l, v) * (1.0 + 0.01 * gauss(rng)), 1.0});
  }
  return set;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"brdffit fit benchmark"};
  std::string table, models = "ggx";
  size_t synthetic = 0;
  int threads = 0;
  app.add_option("table", table, "MERL/RGL/CSV table");
  app.add_option("--synthetic", synthetic, "Fit N synthetic ggx samples instead of a table");
  app.add_option("--models", models, "Comma-separated models or 'all'");
  app.add_option("--threads", threads, "Threads (0: all cores)");
  bool converge = false;
  int polish = FitOptions{}.polish_iterations;
  app.add_option("--polish", polish, "Steps on all samples after the largest subset");
  app.add_flag(
      "--converge", converge,
      "Iterate to convergence on all samples instead of polishing after the largest subset (compare the errors)");
  FitOptions options;
  app.add_option("--starts", options.starts, "Best grid points refined on the subsample");
  app.add_option("--grid-points", options.grid_points, "Multi-start grid size");
  app.add_option("--subsample", options.subsample,
                 "Samples of the grid and the first refinements (the importance subsets are 10x, 100x, ...)");
  std::vector<std::string> start_values;
  app.add_option("--start", start_values, "NAME=VALUE the fit starts from besides its grid (one model only)");
  std::string metric = "cosine";
  app.add_option("--metric", metric, "Metric minimised");
  bool stages = false;
  app.add_flag("--stages", stages, "Print each fit's CPU seconds per stage of the fitter (use with --threads 1)");
  bool together = false;
  app.add_flag("--together", together,
               "Fit the models in one call, as batch does (each contained model once); print each model's own "
               "seconds and, with --stages, every stage summed over the models");
  CLI11_PARSE(app, argc, argv);
  try {
    if (const auto parsed = parse_metric(metric))
      options.metric = *parsed;
    else
      fail("unknown metric '{}'", metric);
    const auto load_start = std::chrono::steady_clock::now();
    const SampleSet data = synthetic ? synthetic_ggx(synthetic) : load_samples(table, SamplingOptions{});
    const double load_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - load_start).count();
    fmt::print("input {}: {} samples, loaded in {:.2f} s, peak memory so far {:.0f} MB\n", data.source, data.size(),
               load_seconds, peak_rss_mb());
    std::vector<const Model*> list;
    if (models == "all") {
      for (const auto& m : all_models()) list.push_back(m.get());
    } else {
      std::stringstream names(models);
      for (std::string name; std::getline(names, name, ',');) {
        const Model* m = find_model(name);
        if (!m) fail("unknown model '{}'", name);
        list.push_back(m);
      }
    }
    double total = 0.0, ggx_cpu = 0.0;
    // ggx first, so every other model's ratio to it can be printed.
    std::stable_partition(list.begin(), list.end(), [](const Model* m) { return m->name() == "ggx"; });
    options.threads = threads;
    options.polish_iterations = polish;
    if (converge) options.polish_after = SIZE_MAX;
    if (together) {
      const double cpu_start = cpu_seconds();
      const std::vector<FitResult> fits = fit_models(list, data, options);
      std::vector<StageProfile> summed;
      for (const FitResult& fit : fits) {
        fmt::print("{:<22} {:>7.3f} s  cosine {:.5g}  log {:.5g}  iterations {:>3}  {}\n", fit.model, fit.seconds,
                   fit.metrics.cosine, fit.metrics.log, fit.iterations, fit.ok ? "ok" : fit.error);
        if (stages && fit.seconds > 2.0)
          for (const StageProfile& s : fit.stages)
            fmt::print("    {:<22} {:>8.3f} s  {:>3} iterations\n", s.stage, s.cpu_seconds, s.iterations);
        for (const StageProfile& s : fit.stages) {
          auto it =
              std::find_if(summed.begin(), summed.end(), [&](const StageProfile& t) { return t.stage == s.stage; });
          if (it == summed.end()) it = summed.insert(summed.end(), {s.stage, 0.0, 0});
          it->cpu_seconds += s.cpu_seconds;
          it->iterations += s.iterations;
        }
      }
      if (stages)
        for (const StageProfile& s : summed)
          fmt::print("    {:<22} {:>8.3f} s  {:>5} iterations\n", s.stage, s.cpu_seconds, s.iterations);
      fmt::print("cpu {:.2f} s for {} models; peak memory {:.0f} MB\n", cpu_seconds() - cpu_start, fits.size(),
                 peak_rss_mb());
      return 0;
    }
    for (const Model* m : list) {
      const auto start = std::chrono::steady_clock::now();
      const double cpu_start = cpu_seconds();
      if (!start_values.empty()) options.initial_values = parameter_values(*m, start_values);
      const FitResult fit = fit_model(*m, data, options);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double cpu = cpu_seconds() - cpu_start;
      total += seconds;
      if (m->name() == "ggx") ggx_cpu = cpu;
      const std::string ratio = ggx_cpu > 0 ? fmt::format("{:5.1f}x ggx", cpu / ggx_cpu) : "";
      fmt::print("{:<18} {:>7.3f} s  cpu {:>7.3f} s {}  cosine {:.5g}  log {:.5g}  iterations {:>3}  {}\n", m->name(),
                 seconds, cpu, ratio, fit.metrics.cosine, fit.metrics.log, fit.iterations, fit.ok ? "ok" : fit.error);
      if (stages)
        for (const StageProfile& s : fit.stages)
          fmt::print("    {:<22} {:>8.3f} s  {:>3} iterations\n", s.stage, s.cpu_seconds, s.iterations);
    }
    fmt::print("total fit time {:.2f} s; peak memory {:.0f} MB\n", total, peak_rss_mb());
  } catch (const Error& e) {
    fmt::print(stderr, "bench_fit: error: {}\n", e.what());
    return 1;
  }
  return 0;
}
