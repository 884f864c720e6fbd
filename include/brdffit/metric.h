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
#pragma once

#include <cmath>
#include <optional>
#include <string>

namespace brdffit {

enum class Metric { Cosine, Log, Relative, L2 };

constexpr double kRelativeEpsilon = 1e-3;

const char* metric_name(Metric metric);
std::optional<Metric> parse_metric(const std::string& name);

struct Metrics {
  double cosine = NAN;
  double log = NAN;
  double relative = NAN;
  double l2 = NAN;
  double max = NAN;
  double typical = NAN;

  double get(Metric metric) const;
};

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

}  // namespace brdffit
