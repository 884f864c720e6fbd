// The fitter: metrics minimised, parameters flagged as not identifiable, failures and cancelling
// (the numerical sweeps are test_fit_sweeps.cc).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <set>
#include <type_traits>

#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/fit_residual.h"
#include "brdffit/registry.h"
#include "broken_model.h"
#include "test_util.h"

namespace brdffit {
namespace {

// The models' declared facts name their own parameters (a misspelt name fails here, not as a
// recovery that looks wrong).
TEST(RecoveryFacts, NameTheModelsOwnParameters) {
  for (const auto& m : all_models()) {
    SCOPED_TRACE(m->name());
    const RecoveryFacts& facts = m->recovery_facts();
    EXPECT_NO_THROW(parameter_values(*m, facts.material));
    for (const std::string& name : facts.not_identifiable) EXPECT_NE(m->find_parameter(name), nullptr) << name;
  }
}

TEST(Fit, EveryMetricCanBeMinimised) {
  const Model& ggx = *find_model("ggx");
  const std::vector<double> truth = parameter_values(ggx, {"albedo=0.3,0.2,0.1", "roughness=0.4", "f0=0.05"});
  const SampleSet data = test::synthetic(ggx, truth, 3000, 0.0, 9);
  for (Metric metric : {Metric::Cosine, Metric::Log, Metric::Relative, Metric::L2}) {
    SCOPED_TRACE(metric_name(metric));
    FitOptions options;
    options.metric = metric;
    const FitResult fit = fit_model(ggx, data, options);
    ASSERT_TRUE(fit.ok) << fit.error;
    EXPECT_NEAR(fit.values[ggx.offset_of("roughness")], 0.4, 1e-4);
    EXPECT_LT(fit.metrics.get(metric), 1e-6);
  }
}

// A Model written against the public model.h alone, with no batch cost of its own, is fitted
// through the JacobianBatchCost that new_batch_cost (fit_residual.h) gives it: wrapping the
// registered ggx, it recovers the truth and ends where ggx's own BatchCost does.
TEST(Fit, AModelWithoutItsOwnBatchCostFitsLikeTheRegisteredOne) {
  class PublicOnly final : public Model {
   public:
    explicit PublicOnly(const Model& inner) : inner_(inner) {}
    const std::string& name() const override { return inner_.name(); }
    const std::string& summary() const override { return inner_.summary(); }
    const std::vector<ParamSpec>& parameters() const override { return inner_.parameters(); }
    bool has_brdf() const override { return inner_.has_brdf(); }
    bool energy_conserving() const override { return inner_.energy_conserving(); }
    Rgb<double> shade(const double* values, const Vec3& l, const Vec3& v) const override {
      return inner_.shade(values, l, v);
    }
    std::optional<Rgb<double>> brdf(const double* values, const Vec3& l, const Vec3& v) const override {
      return inner_.brdf(values, l, v);
    }
    Rgb<double> shade_with_jacobian(const double* values, const Vec3& l, const Vec3& v,
                                    double* jacobian) const override {
      return inner_.shade_with_jacobian(values, l, v, jacobian);
    }
    const std::vector<Nesting>& nestings() const override { return inner_.nestings(); }

   private:
    const Model& inner_;
  };
  const Model& ggx = *find_model("ggx");
  const PublicOnly wrapped(ggx);
  ASSERT_NE(dynamic_cast<const BatchCostSource*>(&ggx), nullptr);
  static_assert(!std::is_base_of_v<BatchCostSource, PublicOnly>, "the wrapper has only the public interface");
  const std::vector<double> truth = parameter_values(ggx, {"albedo=0.3,0.2,0.1", "roughness=0.4", "f0=0.05"});
  const SampleSet data = test::synthetic(ggx, truth, 3000, 0.0, 9);
  const FitResult own = fit_model(ggx, data, FitOptions{});
  const FitResult generic = fit_model(wrapped, data, FitOptions{});
  ASSERT_TRUE(own.ok && generic.ok) << own.error << generic.error;
  ASSERT_EQ(generic.values.size(), truth.size());
  for (size_t i = 0; i < truth.size(); ++i) {
    EXPECT_NEAR(generic.values[i], truth[i], 1e-4) << i;
    EXPECT_NEAR(generic.values[i], own.values[i], 1e-6) << i;
  }
  EXPECT_LT(generic.metrics.cosine, 1e-6);
}

TEST(Fit, UnidentifiableParameterIsFlaggedNotGivenANumber) {
  // With the light always at normal incidence and the view fixed, GGX's albedo and f0 both
  // only scale the same constant: neither is determined alone.
  const Model& ggx = *find_model("ggx");
  const std::vector<double> truth = parameter_values(ggx, {});
  SampleSet data;
  for (int i = 0; i < 50; ++i)
    data.samples.push_back({Vec3(0, 0, 1), Vec3(0, 0, 1), ggx.shade(truth.data(), Vec3(0, 0, 1), Vec3(0, 0, 1)), 1.0});
  const FitResult fit = fit_model(ggx, data, FitOptions{});
  ASSERT_TRUE(fit.ok) << fit.error;  // a fit with undetermined parameters is still a fit
  // It still reproduces the data exactly.
  EXPECT_LT(fit.metrics.relative, 1e-6);
  // Three constants (one per channel) for seven values: none of them is determined alone.
  for (const ParameterEstimate& p : fit.parameters) {
    EXPECT_FALSE(p.identifiable) << p.name;
    for (double s : p.stddev) EXPECT_TRUE(std::isnan(s)) << p.name;
  }
}

TEST(Fit, LafortuneAxisIsDeterminedOnlyUpToScale) {
  // Ngan's normalisation divides the lobe by max(|cxy|,|cz|)^n, so (cxy, cz) and any multiple
  // give the same BRDF: the fit recovers their ratio and flags each as not identifiable.
  const Model& lafortune = *find_model("lafortune");
  const std::vector<double> truth =
      parameter_values(lafortune, {"albedo=0.2", "specular=0.3", "cxy=-0.5", "cz=0.4", "n=15"});
  const FitResult fit = fit_model(lafortune, test::synthetic(lafortune, truth, 5000, 0.0, 4), FitOptions{});
  ASSERT_TRUE(fit.ok) << fit.error;
  const double cxy = fit.values[lafortune.offset_of("cxy")], cz = fit.values[lafortune.offset_of("cz")];
  EXPECT_NEAR(cxy / cz, -0.5 / 0.4, 1e-4);
  EXPECT_NEAR(fit.values[lafortune.offset_of("n")], 15.0, 1e-3);
  for (const ParameterEstimate& p : fit.parameters)
    EXPECT_EQ(p.identifiable, p.name != "cxy" && p.name != "cz") << p.name;
}

TEST(Fit, EmptyOrNonFiniteInputIsAClearError) {
  const Model& lambert = *find_model("lambert");
  SampleSet empty;
  empty.source = "empty.csv";
  try {
    fit_model(lambert, empty, FitOptions{});
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("empty.csv: no samples"), std::string::npos) << e.what();
  }
  SampleSet nan_set;
  nan_set.source = "nan.csv";
  nan_set.samples.push_back({Vec3(0, 0, 1), Vec3(0, 0, 1), Rgb<double>(NAN, 0, 0), 1.0});
  EXPECT_THROW(fit_model(lambert, nan_set, FitOptions{}), Error);
}

TEST(Fit, AFailingModelDoesNotLoseTheOthers) {
  const Model& lambert = *find_model("lambert");
  const SampleSet data = test::synthetic(lambert, parameter_values(lambert, {"albedo=0.4"}), 500, 0.0, 1);
  test::BrokenModel broken;
  const std::vector<FitResult> results = fit_models({&broken, &lambert}, data, FitOptions{});
  ASSERT_EQ(results.size(), 2u);
  EXPECT_FALSE(results[0].ok);
  EXPECT_FALSE(results[0].error.empty());
  EXPECT_TRUE(results[1].ok) << results[1].error;
  EXPECT_NEAR(results[1].values[0], 0.4, 1e-9);
}

// FitOptions::metrics off (fit_models' setting for the models it fits only as starts): the fit
// takes the same path to the same values and skips only the pass of the metrics; its objective is
// then what a start needs of it. The objective is checked against ½Σ w·(shade − measured)² summed
// here, sample by sample. A table larger than the subsample and its first importance subset, so
// that the result's linear values are solved on all samples after the importance subset's walk.
TEST(Fit, WithoutItsMetricsAFitEndsWhereItWouldAndReportsItsObjective) {
  const Model& ggx = *find_model("ggx");
  const SampleSet data = test::synthetic(
      ggx, parameter_values(ggx, {"albedo=0.3,0.2,0.1", "roughness=0.25", "f0=0.6,0.5,0.4"}), 30000, 0.02, 7);
  FitOptions options;
  options.uncertainties = false;
  options.subsample = 2000;
  options.polish_after = 10000;
  const FitResult with_metrics = fit_model(ggx, data, options);
  options.metrics = false;
  const FitResult without = fit_model(ggx, data, options);
  ASSERT_TRUE(with_metrics.ok && without.ok) << with_metrics.error << without.error;
  ASSERT_TRUE(std::any_of(without.stages.begin(), without.stages.end(),
                          [](const StageProfile& s) { return s.stage.rfind("subset of", 0) == 0; }));

  EXPECT_EQ(without.values, with_metrics.values);
  EXPECT_TRUE(std::isnan(without.metrics.cosine) && std::isnan(without.metrics.log)) << without.metrics.cosine;
  EXPECT_TRUE(std::isfinite(with_metrics.metrics.cosine));
  double half_sum = 0.0;
  for (const Sample& s : data.samples) {
    const Rgb<double> residual = ggx.shade(with_metrics.values.data(), s.l, s.v) - s.value;
    half_sum += 0.5 * s.weight * residual.squaredNorm();
  }
  EXPECT_NEAR(with_metrics.objective, half_sum, 1e-9 * half_sum);
  EXPECT_NEAR(without.objective, half_sum, 1e-9 * half_sum);
}

// FitOptions::cancel: set before the fit, nothing is fitted; set once the solver has
// demonstrably started (from FitOptions::on_iteration, at its third iteration, where an
// uncancelled fit goes on), no further iteration runs and fit_models throws Cancelled.
TEST(Fit, CancelStopsTheFitMidway) {
  const Model& ggx = *find_model("ggx");
  const SampleSet data =
      test::synthetic(ggx, parameter_values(ggx, {"albedo=0.2", "roughness=0.2", "f0=0.5"}), 2000, 0.01, 4);
  std::atomic<bool> cancel{true};
  FitOptions options;
  options.cancel = &cancel;
  EXPECT_THROW(fit_models({&ggx}, data, options), Cancelled);

  cancel = false;
  int iterations = 0;
  std::set<std::string> fitted;
  options.on_iteration = [&](const std::string& model, int) {
    fitted.insert(model);
    ++iterations;
  };
  ASSERT_TRUE(fit_models({&ggx}, data, options).at(0).ok);
  EXPECT_EQ(fitted, (std::set<std::string>{"lambert", "ggx"}));  // Lambert: the baseline of the verdict
  ASSERT_GT(iterations, 3);

  iterations = 0;
  int after_cancel = 0;
  options.on_iteration = [&](const std::string&, int) {
    if (cancel) ++after_cancel;
    if (++iterations == 3) cancel = true;
  };
  EXPECT_THROW(fit_models({&ggx}, data, options), Cancelled);
  EXPECT_EQ(iterations, 3);
  EXPECT_EQ(after_cancel, 0);
}

}  // namespace
}  // namespace brdffit
