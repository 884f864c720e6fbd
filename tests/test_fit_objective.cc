// The fitter's objective and the reported metrics, against values computed by hand.
#include <gtest/gtest.h>

#include "brdffit/fit.h"
#include "brdffit/fit_objective.h"
#include "brdffit/registry.h"
#include "test_util.h"

namespace brdffit {
namespace {

// Two samples at normal light and view, measured 0.4 (weight 1) and 0.8 (weight 3), and Lambert
// with albedo 1, which predicts 1/π for both.
SampleSet two_samples() {
  SampleSet set;
  set.samples.push_back({Vec3(0, 0, 1), Vec3(0, 0, 1), Rgb<double>(0.4, 0.4, 0.4), 1.0});
  set.samples.push_back({Vec3(0, 0, 1), Vec3(0, 0, 1), Rgb<double>(0.8, 0.8, 0.8), 3.0});
  return set;
}

constexpr double kPredicted = 1.0 / kPi;

TEST(Metrics, MatchHandComputedValuesOnATinyTable) {
  const Metrics m = evaluate_metrics(*find_model("lambert"), {1.0, 1.0, 1.0}, two_samples());
  const double d1 = kPredicted - 0.4, d2 = kPredicted - 0.8;
  EXPECT_NEAR(m.cosine, std::sqrt((1 * d1 * d1 + 3 * d2 * d2) / 4), 1e-12);
  EXPECT_NEAR(m.l2, std::sqrt((d1 * d1 + d2 * d2) / 2), 1e-12);
  const double l1 = std::log1p(kPredicted) - std::log1p(0.4), l2 = std::log1p(kPredicted) - std::log1p(0.8);
  EXPECT_NEAR(m.log, std::sqrt((l1 * l1 + 3 * l2 * l2) / 4), 1e-12);
  const double r1 = d1 / (0.4 + kRelativeEpsilon), r2 = d2 / (0.8 + kRelativeEpsilon);
  EXPECT_NEAR(m.relative, std::sqrt((r1 * r1 + 3 * r2 * r2) / 4), 1e-12);
  EXPECT_NEAR(m.max, 0.8 - kPredicted, 1e-12);
  // typical: the weighted median of |p−m|/(|m| + m̄/10), m̄ = (0.4 + 3·0.8)/4 = 0.7; the sample of
  // weight 3 holds the median. Read from a histogram with 1.2 % bins.
  EXPECT_NEAR(m.typical, std::fabs(d2) / (0.8 + 0.07), 0.012 * std::fabs(d2) / 0.87);
}

TEST(FitObjective, CostIsTheWeightedSumOfSquaresOverTheFittedChannels) {
  const Model& lambert = *find_model("lambert");
  const SampleSet set = two_samples();
  const double d1 = kPredicted - 0.4, d2 = kPredicted - 0.8;
  EXPECT_NEAR(cost_of(lambert, {1, 1, 1}, set.samples, Metric::Cosine, kAllChannels, nullptr),
              3 * (d1 * d1 + 3 * d2 * d2), 1e-12);
  EXPECT_NEAR(cost_of(lambert, {1, 1, 1}, set.samples, Metric::L2, {true, false, false}, nullptr), d1 * d1 + d2 * d2,
              1e-12);
  // Huber with scale 0.1: ρ(s) = s up to 0.1², 2·0.1·√s − 0.01 beyond. |d1| = 0.082 is inside,
  // √3·|d2| = 0.83 beyond.
  const ceres::HuberLoss huber(0.1);
  const double r1 = std::fabs(d1), r2 = std::sqrt(3.0) * std::fabs(d2);
  EXPECT_NEAR(cost_of(lambert, {1, 1, 1}, set.samples, Metric::Cosine, {true, false, false}, &huber),
              r1 * r1 + (0.2 * r2 - 0.01), 1e-12);
  // A model that is not finite never wins.
  EXPECT_EQ(cost_of(lambert, {NAN, 1, 1}, set.samples, Metric::Cosine, kAllChannels, nullptr), HUGE_VAL);
}

TEST(FitObjective, MedianResidualAbsoluteErrorsAndTheZeroPrediction) {
  const Model& lambert = *find_model("lambert");
  const SampleSet set = two_samples();
  const double d1 = kPredicted - 0.4, d2 = kPredicted - 0.8;
  // |residual|·√w on the red channel: |d1| and √3|d2|; with two, the upper middle.
  EXPECT_NEAR(median_abs_residual(lambert, {1, 1, 1}, set.samples, Metric::Cosine, {true, false, false}),
              std::max(std::fabs(d1), std::sqrt(3.0) * std::fabs(d2)), 1e-12);
  const std::vector<double> error = absolute_errors(lambert, {1, 0, 1}, set.samples, {true, true, false}, 2);
  EXPECT_NEAR(error[0], (std::fabs(d1) + 0.4) / 2, 1e-12);
  EXPECT_NEAR(error[1], (std::fabs(d2) + 0.8) / 2, 1e-12);
  // Predicting zero: √(Σ w m² / Σ w) = √((0.16 + 3·0.64)/4).
  EXPECT_NEAR(zero_prediction_error(set, Metric::Cosine), std::sqrt((0.16 + 3 * 0.64) / 4), 1e-12);
}

}  // namespace
}  // namespace brdffit
