// The importance subset (see importance_subset.h).
#include "brdffit/importance_subset.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace brdffit {

std::vector<Sample> importance_subset(const std::vector<Sample>& samples, size_t count, uint64_t seed,
                                      const std::vector<double>& error) {
  if (samples.size() <= count) return samples;
  double mean = 0.0, weight_sum = 0.0;
  for (const Sample& s : samples) {
    mean += s.weight * s.value.cwiseAbs().mean();
    weight_sum += s.weight;
  }
  mean /= std::max(weight_sum, 1e-300);
  std::vector<double> score(samples.size());
  double total = 0.0;
  for (size_t i = 0; i < samples.size(); ++i) {
    const double m = samples[i].value.cwiseAbs().mean() + (error.empty() ? 0.0 : error[i]) + mean;
    score[i] = samples[i].weight * m * m;
    total += score[i];
  }
  if (!(total > 0.0) || !std::isfinite(total))
    return std::vector<Sample>(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(count));
  std::vector<Sample> subset;
  subset.reserve(count);
  const double step = total / count;
  std::mt19937_64 rng(seed);
  double next = std::uniform_real_distribution<double>(0.0, step)(rng);
  double cumulative = 0.0;
  for (size_t i = 0; i < samples.size(); ++i) {
    cumulative += score[i];
    int hits = 0;
    while (next < cumulative) {
      ++hits;
      next += step;
    }
    if (hits == 0) continue;
    Sample s = samples[i];
    s.weight *= hits * step / score[i];
    subset.push_back(s);
  }
  return subset;
}

}  // namespace brdffit
