// Error metrics between a model's shaded values and measured ones. Every fit reports all of
// them; --metric chooses which one the fitter minimises.
//
// For sample i with weight w_i and channel c, with p = predicted and m = measured f·cosθi:
//   cosine    sqrt(Σ w (p-m)² / Σ w)                     Ngan et al. 2005 (weights: solid angle)
//   log       sqrt(Σ w (ln(1+p) - ln(1+m))² / Σ w)       Löw et al. 2012 E2, as libbsdf; with
//             Löw's weights (SamplingOptions::low_weighting, `--weighting low`: w = solid angle
//             / sinθo) exactly BBM's lowLog (include/loss/cosine_weighted_log.h), whose sum
//             Σ (ln(1+f cosθi) − ln(1+m cosθi))² sinθi over a (θi, φi, θo) grid estimates the
//             same ∫dωi ∫dθo up to a constant factor (and the √(·/Σw), which ranks alike)
//   relative  sqrt(Σ w ((p-m)/(m+ε))² / Σ w), ε = 1e-3  relative error, ε keeps dark bins finite
//   l2        sqrt(Σ (p-m)² / N)                         plain RMS, weights ignored
//   max       max |p-m|
//   typical   weighted median of |p-m| / (|m| + m̄/10), m̄ the weighted mean |m|: how far off a
//             typical sample is relative to its own value (not a fitting metric; the verdict
//             uses it, since unlike the RMS metrics it is not dominated by a specular peak)
// Sums run over samples and the fitted channels; Σ w counts each channel once.
//
// kMetrics lists them once: their names (what --metric, JSON keys and CSV columns spell), where
// each lives in Metrics, whether it can be minimised and whether the verdict judges it. Parsing,
// naming, the result document, the CSV tables, the ranking, the help texts and the Python module
// all go through it. Adding a metric: docs/architecture.md, "Adding a metric".
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace brdffit {

// The metrics the fitter can minimise (FitOptions::metric).
enum class Metric { Cosine, Log, Relative, L2 };

// The robust loss applied to each sample-channel's residual (FitOptions::loss).
enum class LossKind { None, Huber, Cauchy };

constexpr double kRelativeEpsilon = 1e-3;

struct Metrics {
  double cosine = NAN;
  double log = NAN;
  double relative = NAN;
  double l2 = NAN;
  double max = NAN;
  double typical = NAN;

  double get(Metric metric) const;
};

// One metric of kMetrics.
struct MetricInfo {
  const char* name;     // as users type it, and the JSON key and CSV column it is written under
  const char* meaning;  // one line, as the README's "Error metrics" paragraph gives it
  double Metrics::*value;
  std::optional<Metric> minimised;  // set when the fitter can minimise it (--metric accepts it)
  bool judged;                      // the verdict compares it with the Lambert baseline's (fit.cc's judge)
  int digits;                       // significant digits in fit's ranking
  int width;                        // the width of its column there
};

// Every metric, in the order documents, tables and help list them.
inline constexpr MetricInfo kMetrics[] = {
    {"cosine", "Ngan 2005: solid-angle weighted RMS of f·cosθi", &Metrics::cosine, Metric::Cosine, true, 4, 10},
    {"log", "RMS of ln(1+f·cosθi) differences, Löw 2012 E2", &Metrics::log, Metric::Log, true, 4, 10},
    {"relative", "weighted RMS of (p−m)/(m+10⁻³)", &Metrics::relative, Metric::Relative, true, 4, 10},
    {"l2", "plain RMS", &Metrics::l2, Metric::L2, true, 4, 10},
    {"max", "the largest absolute difference", &Metrics::max, std::nullopt, false, 4, 10},
    {"typical", "the weighted median relative error", &Metrics::typical, std::nullopt, false, 3, 8},
};

const MetricInfo& metric_info(Metric metric);
const char* metric_name(Metric metric);
std::optional<Metric> parse_metric(const std::string& name);

// The metric `name` names, for an option or argument called `what` ("--metric", "metric"):
// throws UsageError "WHAT: unknown metric 'NAME'; did you mean ...? (cosine, log, relative, l2)"
// otherwise.
Metric metric_from_name(const std::string& name, const std::string& what);

// "cosine, log, relative, l2": the metrics that can be minimised, for help texts and messages.
std::string minimisable_metrics_text();

// The minimisable metrics the verdict judges every fit by.
std::vector<Metric> judged_metrics();

const char* loss_name(LossKind loss);
// The loss `name` names; throws UsageError "WHAT: unknown loss 'NAME'; did you mean ...? (none,
// huber, cauchy)" otherwise.
LossKind loss_from_name(const std::string& name, const std::string& what);

// The residual of one sample-channel under a metric, before the √weight factor; templated so
// the fitter can differentiate it. The "log" residual treats negative predictions as zero.
template <class T>
T metric_residual(Metric metric, const T& predicted, double measured) {
  using std::log;
  switch (metric) {
    case Metric::Log:
      return log(T(1.0) + (predicted > T(0.0) ? predicted : T(0.0))) - std::log1p(measured > 0.0 ? measured : 0.0);
    case Metric::Relative: return (predicted - measured) / (std::fabs(measured) + kRelativeEpsilon);
    case Metric::Cosine:
    case Metric::L2: break;
  }
  return predicted - measured;
}

inline double metric_weight(Metric metric, double sample_weight) { return metric == Metric::L2 ? 1.0 : sample_weight; }

// The weight under which the plain squared difference (p−m)² is the metric's squared residual to
// first order near p = m (the variable projection's linear solve): the sample weight divided by
// the square of ∂residual/∂p there.
inline double metric_linear_weight(Metric metric, double sample_weight, double measured) {
  const double w = metric_weight(metric, sample_weight);
  switch (metric) {
    case Metric::Relative: return w / std::pow(std::fabs(measured) + kRelativeEpsilon, 2);
    case Metric::Log: return w / std::pow(1.0 + std::max(measured, 0.0), 2);
    case Metric::Cosine:
    case Metric::L2: break;
  }
  return w;
}

// Whether the metric's residual is the difference p−m times a constant: then the linear solve's
// quadratic is the metric's own cost, not only its linearisation.
inline bool metric_is_quadratic(Metric metric) { return metric != Metric::Log; }

}  // namespace brdffit
