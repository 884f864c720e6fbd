#include "brdffit/samples.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include "brdffit/error.h"

namespace brdffit {

bool within_angle_limit(const SamplingOptions& options, const Vec3& l, const Vec3& v) {
  if (options.max_angle_deg >= 90.0) return true;
  const double min_cos = std::cos(options.max_angle_deg * kPi / 180.0);
  return l.z() >= min_cos && v.z() >= min_cos;
}

void apply_sampling_options(SampleSet& set, const SamplingOptions& options) {
  std::vector<Sample>& samples = set.samples;
  samples.erase(std::remove_if(samples.begin(), samples.end(),
                               [&](const Sample& s) { return !within_angle_limit(options, s.l, s.v); }),
                samples.end());
  if (options.max_samples > 0 && samples.size() > options.max_samples) {
    // A seeded partial Fisher-Yates shuffle of the indices picks the subset (mt19937_64 and
    // plain modulo, unlike the std distributions, give the same numbers on every platform).
    // Sorted, the picks keep the set's order and can be moved down in place.
    std::vector<size_t> picks(samples.size());
    std::iota(picks.begin(), picks.end(), size_t{0});
    std::mt19937_64 rng(options.seed);
    for (size_t i = 0; i < options.max_samples; ++i) std::swap(picks[i], picks[i + rng() % (picks.size() - i)]);
    picks.resize(options.max_samples);
    std::sort(picks.begin(), picks.end());
    for (size_t i = 0; i < picks.size(); ++i) samples[i] = samples[picks[i]];  // picks[i] >= i
    samples.resize(picks.size());
  }
  if (options.low_weighting) {
    // sinθo is floored at sin 0.5° so that samples straddling the normal keep a finite weight.
    const double min_sin = std::sin(0.5 * kPi / 180.0);
    for (Sample& s : samples) s.weight /= std::max(std::sqrt(std::max(0.0, 1.0 - s.v.z() * s.v.z())), min_sin);
    set.weighting += " / sin(theta_o) (Low 2012)";
  }
  // Return unused memory only when it is worth a transient copy of what remains.
  if (samples.size() < samples.capacity() / 2) samples.shrink_to_fit();
}

void check_sample_magnitudes(const SampleSet& set) {
  const std::string source = set.source.empty() ? "input" : set.source;
  double sum_of_squares = 0.0, largest_value = 0.0, largest_weight = 0.0;
  for (size_t i = 0; i < set.samples.size(); ++i) {
    const Sample& s = set.samples[i];
    if (!s.value.allFinite() || !std::isfinite(s.weight) || s.weight < 0.0)
      fail("{}: sample {} has a non-finite value or an invalid weight", source, i + 1);
    const double largest = s.value.cwiseAbs().maxCoeff();
    if (largest > kMaxSampleMagnitude || s.weight > kMaxSampleMagnitude)
      fail("{}: sample {} has a value or weight of {:.3g}, beyond the {:.0e} the fitter accepts (rescale the data)",
           source, i + 1, std::max(largest, s.weight), kMaxSampleMagnitude);
    sum_of_squares += s.weight * s.value.squaredNorm();
    largest_value = std::max(largest_value, largest);
    largest_weight = std::max(largest_weight, s.weight);
  }
  for (const auto& [what, x] : {std::pair{"value", largest_value}, std::pair{"weight", largest_weight}})
    if (x > 0.0 && x < kMinSampleMagnitude)
      fail("{}: the largest sample {} is {:.3g}, below the {:.0e} the fitter resolves (rescale the data)", source, what,
           x, kMinSampleMagnitude);
  if (!std::isfinite(sum_of_squares) || sum_of_squares > std::sqrt(std::numeric_limits<double>::max()))
    fail("{}: the weighted sum of squared values ({:.3g}) would overflow the fitter's cost (rescale the data)", source,
         sum_of_squares);
}

}  // namespace brdffit
