// Fits of real measurements, so that a fitter change that loses quality on real data fails
// here: the bundled RGL vinyl (always present), and with ../shared the MERL proxies against the
// fits Ngan, Durand & Matusik 2005 published for the same materials (bundled in data/).
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "brdffit/fit.h"
#include "brdffit/measured.h"
#include "brdffit/published_fits.h"
#include "brdffit/registry.h"
#include "tables_test_util.h"

namespace brdffit {
namespace {

const std::string kBundledRgl = std::string(BRDFFIT_SOURCE_DIR) + "/data/cc_ibiza_sunset_rgb.bsdf";
using test::kPublishedFits;

FitResult fit(const std::string& model, const SampleSet& data) {
  const FitResult result = fit_model(*find_model(model), data, FitOptions{});
  EXPECT_TRUE(result.ok) << model << ": " << result.error;
  return result;
}

TEST(RealData, BundledRglVinylFitsAsWellAsItDid) {
  SamplingOptions sampling;
  sampling.max_samples = 20000;
  const SampleSet data = load_samples(kBundledRgl, sampling);
  ASSERT_EQ(data.size(), 20000u);  // a deterministic subset (the seed of SamplingOptions)
  const FitResult lambert = fit("lambert", data), ggx = fit("ggx", data), ward = fit("ward", data);

  // The fits' own error is the metric recomputed on the data.
  for (const FitResult* f : {&lambert, &ggx, &ward})
    EXPECT_NEAR(f->metrics.cosine, evaluate_metrics(*find_model(f->model), f->values, data).cosine,
                1e-9 * f->metrics.cosine);
  // Lambert: the best constant albedo/π·cosθi has a closed form, Σ wᵢ mᵢ cᵢ / Σ wᵢ cᵢ² per channel
  // (c = cosθi/π): the fitted albedo must be it.
  for (int ch = 0; ch < 3; ++ch) {
    double num = 0.0, den = 0.0;
    for (const Sample& s : data.samples) {
      const double c = std::max(s.l.z(), 0.0) / kPi;
      num += s.weight * s.value[ch] * c;
      den += s.weight * c * c;
    }
    EXPECT_NEAR(lambert.values[ch], std::clamp(num / den, 0.0, 1.0), 1e-6) << "channel " << ch;
  }
  // The models containing Lambert are never worse than it, and a lobe explains the vinyl's
  // highlight much better. Regression bounds: the errors measured since the reader takes the
  // table as f·cosθ (rgl.h) (cosine: lambert 0.43142, ggx 0.20219, ward 0.37111) plus 2 %.
  EXPECT_LE(ggx.metrics.cosine, lambert.metrics.cosine);
  EXPECT_LE(ward.metrics.cosine, lambert.metrics.cosine);
  EXPECT_LT(lambert.metrics.cosine, 0.43142 * 1.02);
  EXPECT_LT(ggx.metrics.cosine, 0.20219 * 1.02);
  EXPECT_LT(ward.metrics.cosine, 0.37111 * 1.02);
}

// Our fit against Ngan's published one on the same samples of a MERL proxy, under our metric:
// minimising it directly, ours must be no worse. (Ngan fitted the measured MERL table, which the
// proxy approximates, with another metric; a fitter caught in a local minimum loses to it.)
// Measured when written, ours/theirs: gold-metallic-paint ward 0.92, cook-torrance 0.70;
// blue-acrylic 0.88, 0.58; red-fabric 0.76, 0.75.
class MerlAgainstNgan : public ::testing::TestWithParam<const char*> {};

TEST_P(MerlAgainstNgan, OurFitIsNoWorseThanThePublishedOne) {
  const std::string path = test::merl_proxy(GetParam());
  SKIP_UNLESS_SHARED(!path.empty(), "the shared MERL proxies (" << test::kSharedDir << "/data/merl-proxy)");
  SamplingOptions sampling;
  sampling.max_angle_deg = 80.0;  // as Ngan
  sampling.max_samples = 20000;
  const SampleSet data = load_samples(path, sampling);
  for (const auto& [model_name, file] :
       {std::pair<const char*, const char*>{"ward", "ngan_ward.fit"}, {"cook-torrance", "ngan_cooktorrance.fit"}}) {
    SCOPED_TRACE(model_name);
    const Model& model = *find_model(model_name);
    const auto published = find_published_fit(kPublishedFits + "/" + file, GetParam(), model);
    ASSERT_TRUE(published.has_value());
    const double theirs = evaluate_metrics(model, published->values, data).cosine;
    const FitResult ours = fit(model_name, data);
    EXPECT_LE(ours.metrics.cosine, theirs * (1.0 + 1e-6)) << "published " << theirs;
  }
}

INSTANTIATE_TEST_SUITE_P(RealData, MerlAgainstNgan,
                         ::testing::Values("gold-metallic-paint", "blue-acrylic", "red-fabric"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

// After the 120 000-draw importance subset, the fit polishes on all 1.1 million samples of a MERL
// table only where the subset misjudged the cost at its optimum (fit.cc, kSubsetAgreement). On
// blue-acrylic it did for Cook-Torrance (its cost on all samples 6.6 % above the subset's estimate),
// and the polish mattered: without it the cosine error is 0.85 % worse. ggx's subset agreed (to
// 0.01 %): its optimum stands, within a hundredth of a percent of converging on all samples.
TEST(RealData, AFullTableIsPolishedWhereTheImportanceSubsetMisjudgedTheCost) {
  const std::string path = test::merl_proxy("blue-acrylic");
  SKIP_UNLESS_SHARED(!path.empty(), "the shared MERL proxies (" << test::kSharedDir << "/data/merl-proxy)");
  const SampleSet data = load_samples(path, SamplingOptions{});
  FitOptions unpolished, converged;
  unpolished.polish_iterations = 0;
  converged.polish_after = SIZE_MAX;

  const Model& cook_torrance = *find_model("cook-torrance");
  const FitResult polished = fit_model(cook_torrance, data, FitOptions{});
  const FitResult subset_optimum = fit_model(cook_torrance, data, unpolished);
  ASSERT_TRUE(polished.ok && subset_optimum.ok) << polished.error << subset_optimum.error;
  EXPECT_NE(polished.termination.find("polished: 2 steps"), std::string::npos) << polished.termination;
  EXPECT_LT(polished.metrics.cosine, subset_optimum.metrics.cosine * (1.0 - 0.005));

  const Model& ggx = *find_model("ggx");
  const FitResult stood = fit_model(ggx, data, FitOptions{});
  const FitResult walked = fit_model(ggx, data, converged);
  ASSERT_TRUE(stood.ok && walked.ok) << stood.error << walked.error;
  EXPECT_NE(stood.termination.find("not polished"), std::string::npos) << stood.termination;
  EXPECT_LE(walked.metrics.cosine, stood.metrics.cosine * (1.0 + 1e-9));
  EXPECT_NEAR(stood.metrics.cosine, walked.metrics.cosine, 1e-4 * walked.metrics.cosine);
}

// openpbr on blue-acrylic is polished (its importance subset misjudged its cost), 0.5 s of its 1.2.
// Fitted only as the start of openpbr+coat it is not: openpbr+coat walks on from its optimum and
// polishes its own end. openpbr+coat then stays better than the polished openpbr of a run that asks
// for it (0.120 against 0.166 when measured).
TEST(RealData, AContainedModelFittedOnlyAsAStartIsNotPolished) {
  const std::string path = test::merl_proxy("blue-acrylic");
  SKIP_UNLESS_SHARED(!path.empty(), "the shared MERL proxies (" << test::kSharedDir << "/data/merl-proxy)");
  const SampleSet data = load_samples(path, SamplingOptions{});
  FitOptions options;
  options.uncertainties = false;
  int openpbr_iterations = 0;
  options.on_iteration = [&](const std::string& model, int) { openpbr_iterations += model == "openpbr"; };

  const FitResult openpbr = fit_model(*find_model("openpbr"), data, options);
  ASSERT_TRUE(openpbr.ok) << openpbr.error;
  ASSERT_EQ(openpbr.termination.rfind("polished: 2 steps", 0), 0u) << openpbr.termination;
  const int when_requested = openpbr_iterations;

  openpbr_iterations = 0;
  const FitResult coated = fit_model(*find_model("openpbr+coat"), data, options);
  ASSERT_TRUE(coated.ok) << coated.error;
  EXPECT_LT(openpbr_iterations, when_requested);  // the polish's steps, and only they, are not taken
  EXPECT_GE(openpbr_iterations, when_requested - options.polish_iterations - 1);
  EXPECT_LT(coated.metrics.cosine, openpbr.metrics.cosine);
}

// gltf+clearcoat on red-fabric ends at gltf's optimum with no clearcoat (clearcoatFactor 0 on its
// bound): the base values are gltf's, and so must their uncertainties be, as JᵀJ of the same values
// on the same samples. The importance subset of its best continued start (a clearcoat spike) held
// 3 422 distinct samples of 120 000 draws, and the covariance estimated there gave baseColor
// ±0.2 and metallic ±0.9 against gltf's ±0.0001 and ±0.0005 (fit.cc, subset_covers).
TEST(RealData, ALayerOfWeightZeroReportsTheUncertaintiesOfTheModelUnderIt) {
  const std::string path = test::merl_proxy("red-fabric");
  SKIP_UNLESS_SHARED(!path.empty(), "the shared MERL proxies (" << test::kSharedDir << "/data/merl-proxy)");
  const SampleSet data = load_samples(path, SamplingOptions{});
  const std::vector<FitResult> fits =
      fit_models({find_model("gltf"), find_model("gltf+clearcoat")}, data, FitOptions{});
  ASSERT_TRUE(fits[0].ok && fits[1].ok) << fits[0].error << fits[1].error;
  const FitResult &gltf = fits[0], &coated = fits[1];
  auto estimate = [](const FitResult& r, const std::string& name) {
    for (const ParameterEstimate& p : r.parameters)
      if (p.name == name) return p;
    ADD_FAILURE() << r.model << " has no " << name;
    return ParameterEstimate{};
  };
  EXPECT_EQ(estimate(coated, "clearcoatFactor").value, std::vector<double>{0.0});
  for (const char* name : {"baseColor", "metallic", "roughness"}) {
    const ParameterEstimate under = estimate(gltf, name), over = estimate(coated, name);
    ASSERT_EQ(under.value, over.value) << name;  // the same optimum
    ASSERT_EQ(under.stddev.size(), over.stddev.size()) << name;
    for (size_t k = 0; k < under.stddev.size(); ++k)
      EXPECT_NEAR(over.stddev[k], under.stddev[k], 0.05 * under.stddev[k]) << name << "[" << k << "]";
  }
}

// The reported standard deviations are those of the Gauss-Newton covariance on all samples,
// σ²(JᵀJ)⁻¹ with σ² = Σ w r²/(residuals − free values), here rebuilt independently with J by central
// differences of the model's shade. Cook-Torrance on blue-acrylic is a near-mirror lobe (m ≈ 0.011)
// on a table whose importance subset holds few of the dim samples: estimated on that subset, m's
// stddev was 24 % too large, the specular's 17 %, f0's 5 %.
TEST(RealData, TheReportedUncertaintiesAreThoseOfAllSamples) {
  const std::string path = test::merl_proxy("blue-acrylic");
  SKIP_UNLESS_SHARED(!path.empty(), "the shared MERL proxies (" << test::kSharedDir << "/data/merl-proxy)");
  const SampleSet data = load_samples(path, SamplingOptions{});
  const Model& model = *find_model("cook-torrance");
  const FitResult result = fit("cook-torrance", data);
  const int n = model.num_values();
  Eigen::MatrixXd jtj = Eigen::MatrixXd::Zero(n, n);
  double squares = 0.0;
  std::vector<double> values = result.values;
  std::vector<Rgb<double>> derivative(n);
  for (const Sample& s : data.samples) {
    const Rgb<double> shade = model.shade(values.data(), s.l, s.v);
    squares += s.weight * (shade - s.value).squaredNorm();
    for (int j = 0; j < n; ++j) {
      const double x = values[j], h = 1e-6 * std::max(std::abs(x), 1e-3);
      values[j] = x + h;
      const Rgb<double> up = model.shade(values.data(), s.l, s.v);
      values[j] = x - h;
      derivative[j] = (up - model.shade(values.data(), s.l, s.v)) / (2.0 * h);
      values[j] = x;
    }
    for (int j = 0; j < n; ++j)
      for (int k = 0; k <= j; ++k) jtj(j, k) += s.weight * derivative[j].dot(derivative[k]);
  }
  jtj = jtj.selfadjointView<Eigen::Lower>();
  const double variance = squares / (3.0 * static_cast<double>(data.size()) - n);
  const Eigen::MatrixXd covariance = variance * jtj.inverse();
  int i = 0;
  for (const ParameterEstimate& p : result.parameters)
    for (double stddev : p.stddev) {
      EXPECT_NEAR(stddev, std::sqrt(covariance(i, i)), 0.01 * std::sqrt(covariance(i, i))) << p.name;
      ++i;
    }
  EXPECT_EQ(i, n);
}

}  // namespace
}  // namespace brdffit
