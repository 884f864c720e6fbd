// Command-line options shared by the commands that fit (fit, score, batch, sphere), and how they
// print values.
#pragma once

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/metric.h"
#include "brdffit/names.h"
#include "brdffit/result_json.h"
#include "brdffit/samples.h"

namespace brdffit::cli {

// The ranges counts given on the command line must lie in, checked by CLI11 before a command
// runs: a negative or absurd value (--threads -5, --max-samples -1) is a typo, never a wish.
inline const CLI::Range kThreadsRange(0, 1024);                           // --threads (0: every core)
inline const CLI::Range kJobsRange(1, 1024);                              // --jobs
inline const CLI::Range kCountRange(int64_t{0}, int64_t{1000000000000});  // --max-samples, --top (0: all)
inline const CLI::Range kFramesRange(1, 100000);                          // --frames
inline const CLI::Validator& kSeedRange = CLI::NonNegativeNumber;         // --seed: any uint64, not -1 wrapped

struct SamplingArgs {
  double max_angle = 90.0;
  size_t max_samples = 0;
  uint64_t seed = 1;
  std::string weighting = "solid-angle";

  void add_to(CLI::App* command) {
    command->add_option("--max-angle", max_angle, "Leave out samples with θi or θo above this (degrees; Ngan used 80)")
        ->check(CLI::Range(1.0, 90.0));
    command->add_option("--max-samples", max_samples, "Fit a deterministic random subset of this many samples (0: all)")
        ->check(kCountRange);
    command->add_option("--seed", seed, "Seed of the subset")->check(kSeedRange);
    command
        ->add_option("--weighting", weighting,
                     "solid-angle (Ngan 2005), or low: ÷ sinθo, Löw 2012's measure (with --metric log: Löw's E2)")
        ->check(CLI::IsMember({"solid-angle", "low"}));
  }
  SamplingOptions options() const { return {max_angle, max_samples, seed, weighting == "low"}; }
};

// --converge: on a large table the stage on all samples walks to convergence instead of
// polishing after the importance subsets (FitOptions::polish_after): slower, and a few percent
// better for models with long, flat cost valleys (Cook-Torrance, Ashikhmin-Shirley).
struct ConvergeArg {
  bool converge = false;

  void add_to(CLI::App* command) {
    command->add_flag("--converge", converge,
                      "Large tables: iterate to convergence on all samples, not a few polishing steps (slower)");
  }
  void apply(FitOptions& options) const {
    if (converge) options.polish_after = SIZE_MAX;
  }
};

// --fix NAME=VALUE[,NAME=VALUE]: parameters held at known values in every model that has them
// (FitOptions::fixed; the library checks the names and bounds against the models).
struct FixArg {
  std::string text;

  void add_to(CLI::App* command) {
    command->add_option("--fix", text,
                        "Hold parameters at known values, NAME=VALUE[,NAME=VALUE] (metallic=0 for a dielectric, "
                        "ior=1.5): in every model that has them, reported as fixed");
  }
  void apply(FitOptions& options) const {
    size_t begin = 0;
    while (!text.empty() && begin <= text.size()) {
      const size_t end = std::min(text.find(',', begin), text.size());
      const std::string item = text.substr(begin, end - begin);
      const size_t equals = item.find('=');
      size_t used = 0;
      double value = NAN;
      try {
        if (equals != std::string::npos) value = std::stod(item.substr(equals + 1), &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (equals == std::string::npos || equals == 0 || used == 0 || used != item.size() - equals - 1 ||
          !std::isfinite(value))
        fail_usage("--fix: '{}' is not NAME=VALUE (e.g. --fix metallic=0,ior=1.5)", item);
      options.fixed.emplace_back(item.substr(0, equals), value);
      begin = end + 1;
    }
  }
};

// NAME=VALUE±STDDEV with its flags. A poor fit's stddevs are left out: they measure how well the
// data pin down a model that does not describe them, which is not a precision worth printing.
inline std::string format_parameter(const ParameterEstimate& p, Verdict verdict) {
  std::string text = p.name + "=" + format_values(p.value, "{:.4g}");
  if (!p.identifiable)
    text += " (not identifiable)";
  else if (verdict == Verdict::Good &&
           std::any_of(p.stddev.begin(), p.stddev.end(), [](double s) { return std::isfinite(s); }))
    text += "±" + format_values(p.stddev, "{:.2g}");
  if (p.at_bound) text += " (at bound)";
  if (p.fixed) text += " (fixed)";
  return text;
}

inline std::string format_parameters(const FitResult& r) {
  std::string line;
  for (const ParameterEstimate& p : r.parameters) line += (line.empty() ? "" : "  ") + format_parameter(p, r.verdict);
  return line;
}

// The result's warning lines (verdict, bounds, identifiability), each on its own indented line.
inline void print_warnings(const FitResult& r, const char* indent) {
  for (const std::string& w : r.warnings) say("{}warning: {}\n", indent, w);
}

// --metric of the commands that fit (what they minimise; `note` appended to the help) and of
// those that rank documents (default: the documents' own metric): the list from kMetrics.
inline CLI::Option* add_minimised_metric_option(CLI::App* command, std::string& metric, const std::string& note = "") {
  return command->add_option("--metric", metric, "What to minimise: " + minimisable_metrics_text() + note);
}
inline CLI::Option* add_ranking_metric_option(CLI::App* command, std::string& metric) {
  return command->add_option("--metric", metric,
                             "Rank by: " + minimisable_metrics_text() + " (default: the documents')");
}

// The FitOptions of fit, sphere and batch, from their command-line values: the one place where
// the fitting commands turn options into the fitter's settings.
inline FitOptions fit_options(const std::string& metric, const std::string& loss, bool per_channel, int threads,
                              uint64_t seed, const ConvergeArg& converge, const FixArg& fix) {
  FitOptions options;
  options.metric = metric_from_name(metric, "--metric");
  options.loss = loss_from_name(loss, "--loss");
  options.per_channel = per_channel;
  options.threads = threads;
  options.seed = seed;
  converge.apply(options);
  fix.apply(options);
  return options;
}

}  // namespace brdffit::cli
