// The importance subset: deterministic, unbiased for weighted sums, and drawn where the data or
// the current fit's error are large.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "brdffit/importance_subset.h"

namespace brdffit {
namespace {

// 20,000 dim samples (value 0.01..0.02, weights 0.5..1.5) and, at index 777, one peak 1000x brighter.
std::vector<Sample> dim_with_one_peak() {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit;
  std::vector<Sample> samples(20000);
  for (Sample& s : samples) {
    s.l = s.v = Vec3(0, 0, 1);
    const double value = 0.01 + 0.01 * unit(rng);
    s.value = Rgb<double>(value, value, value);
    s.weight = 0.5 + unit(rng);
  }
  samples[777].value = Rgb<double>(15, 15, 15);
  return samples;
}

double weighted_sum(const std::vector<Sample>& samples, bool of_values) {
  double sum = 0.0;
  for (const Sample& s : samples) sum += s.weight * (of_values ? s.value[0] : 1.0);
  return sum;
}

TEST(ImportanceSubset, SmallSetsAreKeptWhole) {
  std::vector<Sample> samples = dim_with_one_peak();
  samples.resize(50);
  const std::vector<Sample> subset = importance_subset(samples, 50, 1);
  ASSERT_EQ(subset.size(), 50u);
  for (size_t i = 0; i < subset.size(); ++i) EXPECT_EQ(subset[i].weight, samples[i].weight);
}

TEST(ImportanceSubset, SameSeedSameSubsetAndWeightedSumsAreEstimated) {
  const std::vector<Sample> samples = dim_with_one_peak();
  const std::vector<Sample> a = importance_subset(samples, 2000, 5), b = importance_subset(samples, 2000, 5);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].weight, b[i].weight);
  // Systematic sampling draws `count` times; a sample drawn k times is kept once. The peak's score
  // (15 + m̄)² is 92 % of the total, so it takes ~1,840 draws and the dim samples the other ~160.
  EXPECT_GT(a.size(), 140u);
  EXPECT_LT(a.size(), 200u);
  // Σw and Σw·value over the subset estimate those over all samples.
  EXPECT_NEAR(weighted_sum(a, false) / weighted_sum(samples, false), 1.0, 0.03);
  EXPECT_NEAR(weighted_sum(a, true) / weighted_sum(samples, true), 1.0, 0.03);
}

TEST(ImportanceSubset, ThePeakAndTheLargeErrorsAreDrawn) {
  const std::vector<Sample> samples = dim_with_one_peak();
  // The peak holds most of the Σ w·value²: a uniform tenth would miss it nine times out of ten.
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    const std::vector<Sample> subset = importance_subset(samples, 2000, seed);
    EXPECT_TRUE(std::any_of(subset.begin(), subset.end(), [](const Sample& s) { return s.value[0] == 15; })) << seed;
  }
  // Where the current fit is badly off (samples 100..109, error 5), those samples are drawn too.
  std::vector<double> error(samples.size(), 0.0);
  for (size_t i = 100; i < 110; ++i) error[i] = 5.0;
  const std::vector<Sample> subset = importance_subset(samples, 2000, 3, error);
  size_t drawn = 0;
  for (const Sample& s : subset)
    for (size_t i = 100; i < 110; ++i) drawn += s.value[0] == samples[i].value[0] && s.value[0] != 15;
  EXPECT_EQ(drawn, 10u);
}

// 20,000 samples whose values span three decades log-uniformly (0.01 to 10, as a measured lobe's
// bins do), weights 0.5 to 2, in random order.
std::vector<Sample> three_decades() {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> unit;
  std::vector<Sample> samples(20000);
  for (Sample& s : samples) {
    s.l = s.v = Vec3(0, 0, 1);
    const double value = 0.01 * std::pow(1000.0, unit(rng));
    s.value = Rgb<double>(value, value, value);
    s.weight = 0.5 + 1.5 * unit(rng);
  }
  return samples;
}

TEST(ImportanceSubset, WeightedSumsAreUnbiasedOverSeeds) {
  // Each kept sample's weight is divided by its expected number of draws, so over the random
  // offset of the systematic sampling every weighted sum has the full set's sum as its mean. Over
  // 500 seeds (a tenth drawn each time) the mean estimate of Σw, Σw·value and Σw·value² (the
  // fitter's cost) is within 0.5 % of the full sum. The per-seed estimates scatter by at most
  // 4 % (measured: Σw 3.5 %, whose dim samples are drawn least, Σw·value 0.8 %, Σw·value² 0.9 %),
  // so the mean's standard error is at most 4 %/√500 = 0.18 % and 0.5 % is about three of them:
  // a weight off by a constant factor, or a sample's weight not divided by its own score (a bias
  // toward bright samples), fails.
  const std::vector<Sample> samples = three_decades();
  auto sums = [](const std::vector<Sample>& set) {
    std::array<double, 3> sum{};
    for (const Sample& s : set)
      for (int power = 0; power < 3; ++power) sum[power] += s.weight * std::pow(s.value[0], power);
    return sum;
  };
  const std::array<double, 3> full = sums(samples);
  const int seeds = 500;
  std::array<double, 3> mean{}, square{};
  for (int seed = 1; seed <= seeds; ++seed) {
    const std::vector<Sample> subset = importance_subset(samples, 2000, seed);
    ASSERT_LT(subset.size(), 2001u);
    const std::array<double, 3> estimate = sums(subset);
    for (int power = 0; power < 3; ++power) {
      mean[power] += estimate[power] / full[power] / seeds;
      square[power] += std::pow(estimate[power] / full[power], 2) / seeds;
    }
  }
  for (int power = 0; power < 3; ++power) {
    const double spread = std::sqrt(std::max(0.0, square[power] - mean[power] * mean[power]));
    EXPECT_LT(spread, 0.04) << "Σw·value^" << power;
    EXPECT_NEAR(mean[power], 1.0, 0.005) << "Σw·value^" << power << ": per-seed spread " << spread;
  }
}

}  // namespace
}  // namespace brdffit
