#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "brdffit/samples.h"

namespace brdffit {

void apply_sampling_options(SampleSet& set, const SamplingOptions& options) {
  if (options.max_angle_deg < 90.0) {
    const double min_cos = std::cos(options.max_angle_deg * kPi / 180.0);
    set.samples.erase(std::remove_if(set.samples.begin(), set.samples.end(),
                                     [&](const Sample& s) { return s.l.z() < min_cos || s.v.z() < min_cos; }),
                      set.samples.end());
  }
  if (options.max_samples > 0 && set.samples.size() > options.max_samples) {
    // A seeded partial Fisher-Yates shuffle picks the subset; sorting the picks keeps the
    // table's order, so the same seed always gives the same samples in the same order.
    std::vector<size_t> index(set.samples.size());
    std::iota(index.begin(), index.end(), size_t{0});
    std::mt19937_64 rng(options.seed);
    for (size_t i = 0; i < options.max_samples; ++i)
      std::swap(index[i], index[i + rng() % (index.size() - i)]);
    index.resize(options.max_samples);
    std::sort(index.begin(), index.end());
    std::vector<Sample> subset;
    subset.reserve(index.size());
    for (size_t i : index) subset.push_back(set.samples[i]);
    set.samples = std::move(subset);
  }
  set.samples.shrink_to_fit();
}

}  // namespace brdffit
