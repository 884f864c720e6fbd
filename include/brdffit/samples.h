// Measured reflectance as the fitter sees it: directions, the measured shaded value and a weight.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "brdffit/math.h"

namespace brdffit {

struct Sample {
  Vec3 l;               // unit direction towards the light, local frame (n = +z)
  Vec3 v;               // unit direction towards the viewer
  Rgb<double> value;    // measured shaded value f(l,v)·cosθi per channel
  double weight = 1.0;  // relative importance, e.g. the solid angle a table bin covers
};

struct SampleSet {
  std::vector<Sample> samples;
  std::string source;     // file or description the samples came from
  std::string weighting;  // how weights were chosen, for reports ("uniform", "solid-angle", ...)
  // The source is isotropic: f does not change when both directions turn about the normal (MERL
  // tables, isotropic RGL files). A model's orientation about the normal then means nothing.
  bool isotropic = false;

  size_t size() const { return samples.size(); }
  bool empty() const { return samples.empty(); }
};

// Options shared by every source when it turns a table into samples.
struct SamplingOptions {
  double max_angle_deg = 90.0;  // drop samples with θi or θo above this (Ngan 2005 used 80°)
  size_t max_samples = 0;       // 0: keep all; otherwise a deterministic subset of this size
  uint64_t seed = 1;            // for the subset
  // true: each weight is divided by sinθo, so that a weighted sum over a table's samples
  // estimates ∫dωi ∫dθo (Löw et al. 2012's measure, BBM's lowL2 and lowLog losses: the light
  // over the hemisphere, the view over θo only) instead of ∫dωi ∫dωo. With the "cosine" metric
  // this is Löw's E1, with "log" Löw's E2 (see metric.h).
  bool low_weighting = false;
};

// Whether both directions lie within options.max_angle_deg of the normal (+z). Sources that
// generate samples test this first, so that a limited set never holds the dropped samples.
bool within_angle_limit(const SamplingOptions& options, const Vec3& l, const Vec3& v);

// Drops samples beyond the angle limit, then keeps a deterministic random subset of
// options.max_samples, in the set's order (weights are kept; the subset is uniform so relative
// weights stay meaningful). The same seed and set always give the same subset. Then applies
// options.low_weighting. Works in place.
void apply_sampling_options(SampleSet& set, const SamplingOptions& options);

// Largest |value| and weight the fitter accepts: squared and summed over millions of samples
// they must stay far from the largest double, or the solver's cost overflows to infinity.
constexpr double kMaxSampleMagnitude = 1e100;
// And the smallest the largest of them may be: below it squares underflow toward zero, every
// model fits with no error, and the verdicts would call them all good.
constexpr double kMinSampleMagnitude = 1e-100;

// Throws Error naming set.source unless every sample's value and weight is finite, weights are
// not negative, values and weights are at most kMaxSampleMagnitude in size and the weighted sum
// of squared values is finite, and the largest value and the largest weight are zero or at least
// kMinSampleMagnitude in size. The fitter calls it before any solver sees the samples.
void check_sample_magnitudes(const SampleSet& set);

}  // namespace brdffit
