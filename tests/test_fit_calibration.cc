// The fitter's uncertainties and its cost function, checked against independent computations:
// reported standard deviations against the spread of estimates over many noise draws, at_bound
// for an optimum beyond a bound, and BatchCost's compressed residuals against the per-sample
// residuals and a finite-difference Jacobian.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include "brdffit/fit.h"
#include "brdffit/fit_residual.h"
#include "brdffit/importance_subset.h"
#include "brdffit/models/ggx.h"
#include "brdffit/registry.h"
#include "test_util.h"

namespace brdffit {
namespace {

// Samples of `model` at `values` over the same random direction pairs for every `seed`, plus
// additive Gaussian noise of standard deviation `sigma` drawn from `seed`: homoscedastic, so
// σ²(JᵀJ)⁻¹ is the estimates' covariance over noise draws. (The directions stay fixed so that
// JᵀJ does too: with new directions each draw, a lobe that a few hundred pairs sample a dozen
// times gets a JᵀJ that varies from draw to draw, and the spread then exceeds the mean reported
// stddev by Jensen's inequality, by 20 % for GGX's roughness below.) With `weighted`, each sample
// gets a weight w uniform in [0.5, 2] and noise σ/√w, so that the weighted residuals √w·r are
// homoscedastic again (what a sample's weight claims: its variance is σ²/w).
SampleSet with_additive_noise(const Model& model, const std::vector<double>& values, size_t count, double sigma,
                              uint64_t seed, bool weighted = false) {
  std::mt19937_64 directions(1234), noise(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> weight(0.5, 2.0);
  SampleSet set;
  set.source = "calibration";
  while (set.samples.size() < count) {
    Sample s{test::random_upper_direction(directions, 0.1), test::random_upper_direction(directions, 0.1), {}, 1.0};
    if (weighted) s.weight = weight(directions);
    s.value = model.shade(values.data(), s.l, s.v);
    for (int c = 0; c < 3; ++c) s.value[c] += sigma / std::sqrt(s.weight) * gauss(noise);
    set.samples.push_back(s);
  }
  return set;
}

// One calibration: `draws` noise draws of the same material, each fitted with `options`
// (`make_options` may set the start from the truth); for every value the standard deviation of
// the estimates over the draws must match the mean reported stddev, and the mean estimate the
// truth. A sample stddev over n draws is itself uncertain by about 1/√(2(n−1)) (5 % at 200
// draws, 7 % at 100), so each value's ratio gets `per_value` (about 4 of those) and the mean of
// the ratios `mean_ratio`. An inflated or deflated covariance (a factor 2 in σ², a missing ½ of
// Ceres' cost, wrong degrees of freedom, weights or a loss left out of JᵀJ or of σ²) moves every
// ratio by the same factor. Unbiased: the mean estimate within 3.5 standard errors of the truth.
template <class MakeData>
void expect_calibrated(const Model& model, const std::vector<double>& truth, int draws, const FitOptions& options,
                       MakeData make_data, double per_value, double mean_ratio) {
  const size_t values = truth.size();
  std::vector<std::vector<double>> estimates(values), reported(values);
  for (int seed = 1; seed <= draws; ++seed) {
    const FitResult fit = fit_model(model, make_data(static_cast<uint64_t>(seed)), options);
    ASSERT_TRUE(fit.ok) << fit.error;
    size_t i = 0;
    for (const ParameterEstimate& p : fit.parameters)
      for (size_t c = 0; c < p.value.size(); ++c, ++i) {
        ASSERT_TRUE(p.identifiable) << p.name;
        ASSERT_FALSE(p.at_bound) << p.name;
        estimates[i].push_back(p.value[c]);
        reported[i].push_back(p.stddev[c]);
      }
    ASSERT_EQ(i, values);
  }
  double ratio_sum = 0.0;
  for (size_t i = 0; i < values; ++i) {
    double mean = 0.0, mean_reported = 0.0;
    for (int k = 0; k < draws; ++k) mean += estimates[i][k] / draws, mean_reported += reported[i][k] / draws;
    double spread = 0.0;
    for (int k = 0; k < draws; ++k) spread += (estimates[i][k] - mean) * (estimates[i][k] - mean) / (draws - 1);
    spread = std::sqrt(spread);
    const double ratio = spread / mean_reported;
    EXPECT_NEAR(ratio, 1.0, per_value) << "value " << i << ": spread " << spread << ", reported " << mean_reported;
    EXPECT_NEAR(mean, truth[i], 3.5 * spread / std::sqrt(draws)) << "value " << i;
    ratio_sum += ratio;
  }
  EXPECT_NEAR(ratio_sum / values, 1.0, mean_ratio);
}

// Each fit starts from the truth on all samples: the calibration of the covariance alone.
FitOptions from_the_truth(const std::vector<double>& truth) {
  FitOptions options;
  options.single_start = true;
  options.initial_values = truth;
  return options;
}

TEST(FitCalibration, ReportedStddevMatchesTheSpreadOverNoiseDraws) {
  // 200 noise draws of the same Ward material (400 samples each: half a second in all); measured
  // ratios 0.97 to 1.06.
  const Model& ward = *find_model("ward");
  const std::vector<double> truth =
      parameter_values(ward, {"albedo=0.3,0.2,0.1", "specular=0.08,0.1,0.12", "alpha=0.2"});
  expect_calibrated(
      ward, truth, 200, from_the_truth(truth),
      [&](uint64_t seed) { return with_additive_noise(ward, truth, 400, 0.004, seed); }, 0.2, 0.1);
}

TEST(FitCalibration, SecondModelGgx) {
  // The same on GGX, whose Fresnel and masking make f0 and roughness enter non-linearly; measured
  // ratios 0.95 to 1.06.
  const Model& ggx = *find_model("ggx");
  const std::vector<double> truth = parameter_values(ggx, {"albedo=0.3,0.2,0.1", "roughness=0.4", "f0=0.04,0.06,0.08"});
  expect_calibrated(
      ggx, truth, 200, from_the_truth(truth),
      [&](uint64_t seed) { return with_additive_noise(ggx, truth, 400, 0.004, seed); }, 0.2, 0.1);
}

TEST(FitCalibration, WeightedSamples) {
  // Weights w in [0.5, 2] with noise σ/√w: the weighted fit's reported stddevs still match the
  // spread (weights left out of JᵀJ or of σ² would scale every ratio by about 0.8 to 1.25);
  // measured ratios 0.96 to 1.09.
  const Model& ward = *find_model("ward");
  const std::vector<double> truth =
      parameter_values(ward, {"albedo=0.3,0.2,0.1", "specular=0.08,0.1,0.12", "alpha=0.2"});
  expect_calibrated(
      ward, truth, 200, from_the_truth(truth),
      [&](uint64_t seed) { return with_additive_noise(ward, truth, 400, 0.004, seed, true); }, 0.2, 0.1);
}

TEST(FitCalibration, HuberLossOnGaussianNoise) {
  // Huber's loss (the automatic scale, 1.345 robust σ) on Gaussian noise: an M-estimator whose
  // variance is 1/0.95 of least squares'; the reported stddevs must follow it (from the robust
  // cost and the loss-corrected Jacobian). Measured ratios 0.98 to 1.09, mean 1.05.
  const Model& ward = *find_model("ward");
  const std::vector<double> truth =
      parameter_values(ward, {"albedo=0.3,0.2,0.1", "specular=0.08,0.1,0.12", "alpha=0.2"});
  FitOptions options = from_the_truth(truth);
  options.loss = LossKind::Huber;
  expect_calibrated(
      ward, truth, 200, options, [&](uint64_t seed) { return with_additive_noise(ward, truth, 400, 0.004, seed); }, 0.2,
      0.1);
}

TEST(FitCalibration, PolishedAfterAnImportanceSubset) {
  // The path of a large table, scaled down: the grid on a 300-sample subsample, a refinement on
  // an importance subset of 3,000 draws (at least polish_after), then at most polish_iterations
  // steps on all 6,000 samples, with JᵀJ from the subset (its weights make its sums estimate the
  // full ones). The estimates are still unbiased and their stddevs still match the spread (100
  // draws, 2 s: a sample stddev uncertain by 7 %; measured ratios 0.95 to 1.12).
  const Model& ward = *find_model("ward");
  const std::vector<double> truth =
      parameter_values(ward, {"albedo=0.3,0.2,0.1", "specular=0.08,0.1,0.12", "alpha=0.2"});
  FitOptions options;
  options.subsample = 300;
  options.polish_after = 2000;
  options.threads = 1;
  const auto data = [&](uint64_t seed) { return with_additive_noise(ward, truth, 6000, 0.02, seed); };
  // fit_channels' rule: subsets of 10× the subsample's size while below all samples; the last
  // one's draws reach polish_after, so the stage on all samples polishes.
  const size_t subsample = importance_subset(data(1).samples, options.subsample, options.seed).size();
  ASSERT_GE(10 * subsample, options.polish_after);
  ASSERT_LT(10 * subsample, 6000u);
  ASSERT_GE(100 * subsample, 6000u);
  expect_calibrated(ward, truth, 100, options, data, 0.25, 0.12);
}

TEST(FitCalibration, AnOptimumBeyondABoundIsFlaggedAtBound) {
  // Blue albedo generated negative: the best admissible value is the bound 0, and only that
  // parameter is at a bound.
  const Model& ggx = *find_model("ggx");
  std::vector<double> truth = parameter_values(ggx, {"albedo=0.3,0.2,0", "roughness=0.3", "f0=0.04,0.05,0.06"});
  truth[ggx.offset_of("albedo") + 2] = -0.05;
  SampleSet data;
  std::mt19937_64 rng(7);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 l = test::random_upper_direction(rng, 0.1), v = test::random_upper_direction(rng, 0.1);
    data.samples.push_back({l, v, ggx.shade(truth.data(), l, v), 1.0});
  }
  const FitResult fit = fit_model(ggx, data, FitOptions{});
  ASSERT_TRUE(fit.ok) << fit.error;
  EXPECT_EQ(fit.values[ggx.offset_of("albedo") + 2], 0.0);
  for (const ParameterEstimate& p : fit.parameters) EXPECT_EQ(p.at_bound, p.name == "albedo") << p.name;
  // The other channels are unaffected by the blue one's bound.
  EXPECT_NEAR(fit.values[ggx.offset_of("albedo")], 0.3, 1e-3);
  EXPECT_NEAR(fit.values[ggx.offset_of("roughness")], 0.3, 0.02);
}

// BatchCost's compressed residuals against the plain per-sample least-squares problem: r_i
// the residual of each sample-channel (after the robust loss, √ρ(r²) with r's sign), J its
// Jacobian by central differences of the model's double evaluation.
struct PlainProblem {
  Eigen::VectorXd r;
  Eigen::MatrixXd j;
};

PlainProblem plain_problem(const Model& model, const std::vector<Sample>& samples, const std::vector<double>& full,
                           const std::vector<int>& free, const ceres::LossFunction* loss) {
  auto residuals_at = [&](const std::vector<double>& values) {
    std::vector<double> out;
    for (const Sample& s : samples) {
      const Rgb<double> shade = model.shade(values.data(), s.l, s.v);
      for (int c = 0; c < 3; ++c) {
        const double r = (shade[c] - s.value[c]) * std::sqrt(s.weight);
        double rho[3] = {r * r, 1.0, 0.0};
        if (loss) loss->Evaluate(r * r, rho);
        out.push_back(std::copysign(std::sqrt(rho[0]), r));
      }
    }
    return out;
  };
  const std::vector<double> r0 = residuals_at(full);
  PlainProblem p{Eigen::Map<const Eigen::VectorXd>(r0.data(), r0.size()), Eigen::MatrixXd(r0.size(), free.size())};
  for (size_t k = 0; k < free.size(); ++k) {
    const double h = 1e-6 * std::max(1.0, std::abs(full[free[k]]));
    std::vector<double> plus = full, minus = full;
    plus[free[k]] += h;
    minus[free[k]] -= h;
    const std::vector<double> rp = residuals_at(plus), rm = residuals_at(minus);
    for (size_t i = 0; i < r0.size(); ++i) p.j(i, k) = (rp[i] - rm[i]) / (2 * h);
  }
  return p;
}

TEST(BatchCost, CompressionIsExact) {
  const Model& ggx = *find_model("ggx");
  const std::vector<double> truth = parameter_values(ggx, {"albedo=0.3,0.2,0.1", "roughness=0.25", "f0=0.04,0.5,0.9"});
  // Evaluated away from the optimum, so the residuals and the gradient are not zero.
  const std::vector<double> at = parameter_values(ggx, {"albedo=0.25,0.22,0.05", "roughness=0.3", "f0=0.06,0.4,0.8"});
  std::vector<Sample> samples;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> weight(0.5, 2.0);
  for (int i = 0; i < 300; ++i) {
    const Vec3 l = test::random_upper_direction(rng, 0.1), v = test::random_upper_direction(rng, 0.1);
    samples.push_back({l, v, ggx.shade(truth.data(), l, v), weight(rng)});
  }
  // f0's blue held fixed: the block holds only the other six values (roughness among them, the
  // one value whose derivative goes through D, G and α = roughness²).
  const std::vector<int> free = {0, 1, 2, 3, 4, 5};
  ceres::HuberLoss huber(0.01);
  for (const ceres::LossFunction* loss :
       {static_cast<const ceres::LossFunction*>(nullptr), static_cast<const ceres::LossFunction*>(&huber)}) {
    SCOPED_TRACE(loss ? "Huber loss" : "no loss");
    ResidualBatch batch;
    batch.samples = samples.data();
    batch.count = samples.size();
    batch.loss = loss;
    batch.free_index = &free;
    batch.full_values = &at;
    const std::unique_ptr<ceres::CostFunction> cost(new BatchCost<models::Ggx>(batch));
    const int F = static_cast<int>(free.size());
    ASSERT_EQ(cost->num_residuals(), F + 1);
    ASSERT_EQ(cost->parameter_block_sizes(), std::vector<int32_t>{F});

    std::vector<double> x;
    for (int i : free) x.push_back(at[i]);
    const double* parameters[] = {x.data()};
    Eigen::VectorXd residuals(F + 1);
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> jacobian(F + 1, F);
    double* jacobians[] = {jacobian.data()};
    ASSERT_TRUE(cost->Evaluate(parameters, residuals.data(), jacobians));
    Eigen::VectorXd cost_only(F + 1);
    ASSERT_TRUE(cost->Evaluate(parameters, cost_only.data(), nullptr));

    const PlainProblem plain = plain_problem(ggx, samples, at, free, loss);
    const Eigen::MatrixXd jtj = plain.j.transpose() * plain.j;
    const Eigen::VectorXd jtr = plain.j.transpose() * plain.r;
    const Eigen::MatrixXd r = jacobian.topRows(F);
    const Eigen::VectorXd y = residuals.head(F);
    EXPECT_TRUE(jacobian.row(F).isZero(0.0));
    EXPECT_LT((r.transpose() * r - jtj).norm(), 1e-6 * jtj.norm()) << "RᵀR\n" << r.transpose() * r << "\nJᵀJ\n" << jtj;
    EXPECT_LT((r.transpose() * y - jtr).norm(), 1e-6 * jtr.norm())
        << "Rᵀy " << (r.transpose() * y).transpose() << "\nJᵀr " << jtr.transpose();
    ASSERT_GT(jtr.norm(), 0.0);
    // The cost: ‖y‖² + e² = ‖r‖², with the Jacobian and without.
    EXPECT_NEAR(residuals.squaredNorm(), plain.r.squaredNorm(), 1e-12 * plain.r.squaredNorm());
    EXPECT_NEAR(cost_only.squaredNorm(), plain.r.squaredNorm(), 1e-12 * plain.r.squaredNorm());
  }
}

}  // namespace
}  // namespace brdffit
