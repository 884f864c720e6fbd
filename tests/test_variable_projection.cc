// Variable projection: the box-constrained quadratic against hand solutions, and the linear
// parameters solved exactly from data baked with known values.
#include <gtest/gtest.h>

#include <cmath>

#include "brdffit/fit_objective.h"
#include "brdffit/model.h"
#include "brdffit/published_fits.h"
#include "brdffit/registry.h"
#include "brdffit/variable_projection.h"
#include "test_util.h"

namespace brdffit {
namespace {

Eigen::VectorXd solve(const Eigen::Matrix2d& a, const Eigen::Vector2d& b, double lower, double upper) {
  return solve_box_quadratic(a, b, Eigen::Vector2d::Constant(lower), Eigen::Vector2d::Constant(upper));
}

TEST(BoxQuadratic, InteriorOptimumIsTheUnconstrainedSolution) {
  // ∇ = 2(Ax − b) = 0: x = A⁻¹b = (1/2, 1/4).
  const Eigen::VectorXd x = solve(Eigen::Vector2d(2, 1).asDiagonal().toDenseMatrix(), Eigen::Vector2d(1, 0.25), 0, 1);
  EXPECT_NEAR(x[0], 0.5, 1e-12);
  EXPECT_NEAR(x[1], 0.25, 1e-12);
}

TEST(BoxQuadratic, CoupledVariablesMoveWhenOneHitsItsBound) {
  // A = [[2, 1], [1, 2]], b = (3, 0): unconstrained x = (2, −1). With x₂ ≥ 0, x₂ = 0 and
  // x₁ minimises 2x₁² − 6x₁: x₁ = 3/2 (not the unconstrained 2). KKT: ∂/∂x₂ = 2(x₁ + 2x₂) = 3 > 0.
  Eigen::Matrix2d a;
  a << 2, 1, 1, 2;
  const Eigen::VectorXd x = solve(a, Eigen::Vector2d(3, 0), 0, 5);
  EXPECT_NEAR(x[0], 1.5, 1e-12);
  EXPECT_NEAR(x[1], 0.0, 1e-12);
}

TEST(BoxQuadratic, UpperBoundsAndASingularMatrix) {
  // Both variables want 3 but stop at 1.
  const Eigen::VectorXd x = solve(Eigen::Matrix2d::Identity(), Eigen::Vector2d(3, 3), 0, 1);
  EXPECT_NEAR(x[0], 1.0, 1e-12);
  EXPECT_NEAR(x[1], 1.0, 1e-12);
  // Only x₁ + x₂ is determined (A = 11ᵀ, b = (1, 1)): any split with x₁ + x₂ = 1 is optimal.
  const Eigen::VectorXd y = solve(Eigen::Matrix2d::Ones(), Eigen::Vector2d(1, 1), 0, 1);
  EXPECT_NEAR(y[0] + y[1], 1.0, 1e-12);
}

std::vector<double> with(const Model& model, std::vector<double> values, const std::string& name,
                         std::array<double, 3> colour) {
  std::copy(colour.begin(), colour.end(), values.begin() + model.offset_of(name));
  return values;
}

TEST(SolveLinear, RecoversTheColoursOfBakedDataExactlyInEveryMetric) {
  // Blinn-Phong at its true gloss: the albedo and specular colours are linear, so one solve
  // from any starting colours gives the baked ones, whatever the metric's weighting.
  const Model& model = *find_model("blinn-phong");
  std::vector<double> truth = with(model, model.default_values(), "albedo", {0.2, 0.5, 0.8});
  truth = with(model, truth, "specular", {0.3, 0.1, 0.05});
  const SampleSet data = test::model_table(model, truth, 400, 0.0, 7, 0.05);
  for (Metric metric : {Metric::Cosine, Metric::Log, Metric::Relative, Metric::L2}) {
    SCOPED_TRACE(metric_name(metric));
    std::vector<double> values = with(model, with(model, truth, "albedo", {0.9, 0.9, 0.9}), "specular", {0, 0, 0});
    solve_linear(model, values, data.samples, metric, kAllChannels);
    for (size_t i = 0; i < truth.size(); ++i) EXPECT_NEAR(values[i], truth[i], 1e-9) << i;
  }
}

TEST(SolveLinear, ClampsToTheBoundsAndLeavesUnfittedChannelsAlone) {
  // Lambert data brighter than albedo 1 in red: the solve stops at the bound there. Only the red
  // and blue channels are fitted, so green keeps the value it had.
  const Model& lambert = *find_model("lambert");
  const SampleSet data = test::model_table(lambert, {1.0, 0.4, 0.6}, 200, 0.0, 3, 0.05);
  SampleSet brighter = data;
  for (Sample& s : brighter.samples) s.value[0] *= 1.5;
  std::vector<double> values = {0.5, 0.123, 0.5};
  solve_linear(lambert, values, brighter.samples, Metric::Cosine, {true, false, true});
  EXPECT_DOUBLE_EQ(values[0], 1.0);
  EXPECT_DOUBLE_EQ(values[1], 0.123);
  EXPECT_NEAR(values[2], 0.6, 1e-9);
}

TEST(SolveLinear, ScalesTheSharpestPublishedSgdLobeWhateverTheSearchHoldsKAt) {
  // Only specular·K sets sgd's scale, and the search tries shapes with K at grid values while the
  // solve finds specular. Bagher's largest scale, specular-white-phenolic's (specular·K up to
  // 234 to 3377 in its three channels, α near 1e-5), baked without noise and solved with K at its
  // lower bound 1: specular takes the whole scale and the fit is exact. (With specular capped at 5
  // the solve stopped there, a lobe 47 to 675 times too dim.)
  const Model& sgd = *find_model("sgd");
  const auto published = find_published_fit(test::kPublishedFits + "/bagher_sgd.fit", "specular-white-phenolic", sgd);
  ASSERT_TRUE(published.has_value());
  const std::vector<double>& truth = published->values;
  const int specular = sgd.offset_of("specular"), k = sgd.offset_of("K");
  const SampleSet data = test::model_table(sgd, truth, 2000, 0.0, 5, 0.05);
  std::vector<double> values = truth;
  for (int c = 0; c < 3; ++c) {
    values[k + c] = sgd.find_parameter("K")->lower;
    values[specular + c] = 0.0;
  }
  const double cost = solve_linear(sgd, values, data.samples, Metric::Cosine, kAllChannels);
  for (int c = 0; c < 3; ++c) {
    const double scale = truth[specular + c] * truth[k + c];
    EXPECT_GT(scale, 200.0);
    EXPECT_NEAR(values[specular + c], scale, 1e-6 * scale) << c;
  }
  EXPECT_LT(cost, 1e-12);
}

TEST(SolveLinear, ReturnsTheCostsAtItsSolutionAndAtTheValuesGivenFromTheNormalEquations) {
  // Noisy Blinn-Phong away from its true gloss, one channel clamped at its bound and one not
  // fitted: the returned objective is what a separate pass over the samples (cost_of) finds at
  // the solved values, and the one given back for the values as given (colours off their optimum
  // by 20 %) what it finds at those, for every metric whose residual is affine in the prediction.
  const Model& model = *find_model("blinn-phong");
  std::vector<double> truth = with(model, model.default_values(), "albedo", {0.99, 0.5, 0.8});
  truth = with(model, truth, "specular", {0.3, 0.1, 0.05});
  SampleSet data = test::model_table(model, truth, 400, 0.05, 11, 0.05);
  for (Sample& s : data.samples) s.value[0] *= 1.3;
  const Channels channels{true, true, false};
  for (Metric metric : {Metric::Cosine, Metric::Relative, Metric::L2}) {
    SCOPED_TRACE(metric_name(metric));
    std::vector<double> values = with(model, truth, "albedo", {0.8, 0.4, 0.64});
    values[model.offset_of("gloss")] *= 1.7;
    const double expected_as_given = cost_of(model, values, data.samples, metric, channels, nullptr);
    double as_given = NAN;
    const double cost = solve_linear(model, values, data.samples, metric, channels, &as_given);
    const double expected = cost_of(model, values, data.samples, metric, channels, nullptr);
    EXPECT_GT(expected, 0.0);
    EXPECT_NEAR(cost, expected, 1e-9 * expected);
    EXPECT_GT(expected_as_given, 1.5 * expected);  // the solve moved the colours
    EXPECT_NEAR(as_given, expected_as_given, 1e-9 * expected_as_given);
  }
  std::vector<double> values = truth;
  double as_given = 0.0;
  EXPECT_TRUE(std::isnan(solve_linear(model, values, data.samples, Metric::Log, channels, &as_given)));
  EXPECT_TRUE(std::isnan(as_given));
}

TEST(SolveLinear, GivesUpOnlyWhereItsObjectiveIsSurelyAboveTheBoundAndReturnsALowerBoundOfIt) {
  // Noisy data away from the models' optimum, 3 000 samples (a look at the bound every 256): with
  // a bound above the objective the solve is the one without a bound, to the bit; below it, what
  // comes back is above the bound and at most the objective (a lower bound of it), and the values
  // are left as given wherever the solve stopped early. One linear parameter (lambert, whose
  // albedo is clamped in red) and two (blinn-phong).
  for (const char* name : {"lambert", "blinn-phong"}) {
    SCOPED_TRACE(name);
    const Model& model = *find_model(name);
    SampleSet data = test::model_table(*find_model("blinn-phong"),
                                       parameter_values(*find_model("blinn-phong"), {"albedo=0.9,0.4,0.2", "gloss=40"}),
                                       3000, 0.05, 13, 0.05);
    for (Sample& s : data.samples) s.value[0] *= 1.3;
    std::vector<double> given = model.default_values();
    if (model.find_parameter("gloss")) given[model.offset_of("gloss")] = 200;
    for (Metric metric : {Metric::Cosine, Metric::L2}) {
      std::vector<double> solved = given;
      const double cost = solve_linear(model, solved, data.samples, metric, kAllChannels);
      ASSERT_GT(cost, 0.0);
      std::vector<double> values = given;
      EXPECT_EQ(solve_linear(model, values, data.samples, metric, kAllChannels, nullptr, 1.01 * cost), cost);
      EXPECT_EQ(values, solved);
      int given_up = 0;
      for (double fraction : {0.1, 0.3, 0.5, 0.7, 0.9, 0.99}) {
        values = given;
        const double bounded =
            solve_linear(model, values, data.samples, metric, kAllChannels, nullptr, fraction * cost);
        EXPECT_GT(bounded, fraction * cost);
        EXPECT_LE(bounded, cost);
        if (bounded < cost) {
          EXPECT_EQ(values, given);
          ++given_up;
        }
      }
      EXPECT_GE(given_up, 3);  // at least below half the objective
      values = given;
      EXPECT_TRUE(std::isnan(solve_linear(model, values, data.samples, Metric::Log, kAllChannels, nullptr, 0.0)));
    }
  }
}

}  // namespace
}  // namespace brdffit
