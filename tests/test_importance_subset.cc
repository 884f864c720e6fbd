// The importance subset: deterministic, unbiased for weighted sums, and drawn where the data or
// the current fit's error are large.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace brdffit
