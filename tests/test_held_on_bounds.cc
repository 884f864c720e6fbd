// Values held on a bound while the cost pushes them against it, released when it no longer does
// (LeastSquares::run in fit.cc): the fit still ends at an optimum on the box.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "brdffit/fit.h"
#include "brdffit/metric.h"
#include "brdffit/registry.h"
#include "test_util.h"

namespace brdffit {
namespace {

// The cosine metric of `model` at `values` on `data` with one value moved by `step`.
double cosine_with(const Model& model, std::vector<double> values, int index, double step, const SampleSet& data) {
  values[index] += step;
  return evaluate_metrics(model, values, data, {}).cosine;
}

TEST(HeldOnABound, AValuePushedPastItsBoundEndsOnItAndTheOthersAtTheirOptimum) {
  // glTF data made with metallic −0.15 (a dielectric darker at grazing than metallic 0 allows):
  // the best admissible metallic is the bound 0. The fit must end there, with the cost rising
  // into the box (first-order optimality on the bound) and flat in roughness (an interior
  // optimum), and recover the shape it was made with.
  const Model& gltf = *find_model("gltf");
  std::vector<double> truth = parameter_values(gltf, {"baseColor=0.5,0.3,0.2", "roughness=0.35"});
  truth[gltf.offset_of("metallic")] = -0.15;
  const SampleSet data = test::model_table(gltf, truth, 20000, 0.0, 11, 0.05);
  const FitResult fit = fit_model(gltf, data, FitOptions{});
  ASSERT_TRUE(fit.ok) << fit.error;
  const int metallic = gltf.offset_of("metallic"), roughness = gltf.offset_of("roughness");
  EXPECT_EQ(fit.values[metallic], 0.0);
  const double at_fit = fit.metrics.cosine;
  EXPECT_GT(cosine_with(gltf, fit.values, metallic, 1e-3, data), at_fit);
  const double h = 1e-4 * fit.values[roughness];
  const double slope =
      (cosine_with(gltf, fit.values, roughness, h, data) - cosine_with(gltf, fit.values, roughness, -h, data)) /
      (2 * h);
  const double curvature = (cosine_with(gltf, fit.values, roughness, h, data) - 2 * at_fit +
                            cosine_with(gltf, fit.values, roughness, -h, data)) /
                           (h * h);
  // Flat: the step to the minimum of the local parabola is a small fraction of h.
  EXPECT_LT(std::fabs(slope / curvature), 0.05 * h) << "slope " << slope << " curvature " << curvature;
  EXPECT_NEAR(fit.values[roughness], 0.35, 0.02);
}

TEST(HeldOnABound, AValueStartingOnItsBoundIsReleasedWhenTheDataPullIt) {
  // The default metallic is 0, on its bound, where the data made with 0.4 pull it inward: the
  // fit from that single start must leave the bound and recover 0.4.
  const Model& gltf = *find_model("gltf");
  const std::vector<double> truth = parameter_values(gltf, {"baseColor=0.6,0.5,0.3", "metallic=0.4", "roughness=0.3"});
  const SampleSet data = test::model_table(gltf, truth, 20000, 0.0, 12, 0.05);
  FitOptions options;
  options.single_start = true;
  const FitResult fit = fit_model(gltf, data, options);
  ASSERT_TRUE(fit.ok) << fit.error;
  EXPECT_NEAR(fit.values[gltf.offset_of("metallic")], 0.4, 1e-4);
  EXPECT_NEAR(fit.values[gltf.offset_of("roughness")], 0.3, 1e-4);
}

}  // namespace
}  // namespace brdffit
