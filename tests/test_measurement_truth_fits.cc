// Physical questions asked of fits, not of the code's own conventions: isotropic data never give
// an oriented anisotropic fit (nor a stretched renderer material), and a fit called good is as good
// as Lambert on every judged metric, whatever was minimised.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "brdffit/fit.h"
#include "brdffit/measured.h"
#include "brdffit/merl.h"
#include "brdffit/registry.h"
#include "tables_test_util.h"
#include "test_util.h"

namespace brdffit {
namespace {

// --- symmetry: anisotropic models on isotropic data -----------------------------------------------

// 30 000 samples of a MERL table of an isotropic GGX metal (roughness 0.3), written as `file`.
SampleSet isotropic_ggx_metal(const std::string& file) {
  const std::string path = test::scratch_path(file);
  const Model& ggx = *find_model("ggx");
  const std::vector<double> values = parameter_values(ggx, {"albedo=0.02", "f0=0.8", "roughness=0.3"});
  write_merl(path, [&](const Vec3& l, const Vec3& v) { return *ggx.brdf(values.data(), l, v); });
  SamplingOptions sampling;
  sampling.max_samples = 30000;
  return load_samples(path, sampling);
}

TEST(Symmetry, AnAnisotropicModelFittedToIsotropicDataComesOutIsotropicWithNoOrientation) {
  const SampleSet set = isotropic_ggx_metal("isotropic-metal.binary");
  FitOptions options;
  options.threads = 2;
  const std::vector<FitResult> fits = fit_models(
      {find_model("ggx"), find_model("ggx-aniso"), find_model("ward"), find_model("ward-aniso")}, set, options);
  for (const auto& [iso, aniso] : {std::pair{fits[0], fits[1]}, std::pair{fits[2], fits[3]}}) {
    SCOPED_TRACE(aniso.model);
    ASSERT_TRUE(aniso.ok) << aniso.error;
    const auto param = [&](const std::string& name) {
      return *std::find_if(aniso.parameters.begin(), aniso.parameters.end(),
                           [&](const ParameterEstimate& p) { return p.name == name; });
    };
    // Equal widths, to the bit, and the isotropic model's error: the isotropic form was fitted.
    EXPECT_EQ(param("alpha_x").value[0], param("alpha_y").value[0]);
    EXPECT_NEAR(aniso.metrics.cosine, iso.metrics.cosine, 1e-9 * iso.metrics.cosine + 1e-12);  // round-off apart
    EXPECT_TRUE(std::isfinite(param("alpha_x").stddev[0]));
    EXPECT_FALSE(param("phi0").identifiable);
    EXPECT_TRUE(std::isnan(param("phi0").stddev[0]));
    EXPECT_TRUE(test::mentions(aniso.warnings, "phi0 is not identifiable: the data are isotropic"))
        << ::testing::PrintToString(aniso.warnings);
    EXPECT_TRUE(test::mentions(aniso.warnings, "fitted in its isotropic form, " + iso.model))
        << ::testing::PrintToString(aniso.warnings);
  }
  // ggx-aniso's widths are ggx's roughness squared, and its standard deviation follows: σ_α = 2r·σ_r.
  const ParameterEstimate& roughness = fits[0].parameters[1];
  const ParameterEstimate& alpha_x = fits[1].parameters[2];
  ASSERT_EQ(roughness.name, "roughness");
  ASSERT_EQ(alpha_x.name, "alpha_x");
  const double r = roughness.value[0];
  EXPECT_NEAR(alpha_x.value[0], 0.09, 0.005);  // roughness² of the table
  EXPECT_NEAR(alpha_x.value[0], r * r, 1e-12);
  EXPECT_NEAR(alpha_x.stddev[0], 2.0 * r * roughness.stddev[0], 1e-6 * roughness.stddev[0] + 1e-15);
}

TEST(Symmetry, AnAnisotropicModelAloneReportsItsIsotropicFormsUncertainties) {
  // fit_models leaves the uncertainties out for the models it fits only as starts and baseline
  // (FitOptions::uncertainties), but an isotropic form reports its fit as the requested model's.
  const std::vector<FitResult> fits =
      fit_models({find_model("ggx-aniso")}, isotropic_ggx_metal("isotropic-metal-alone.binary"), {});
  ASSERT_TRUE(fits[0].ok) << fits[0].error;
  for (const ParameterEstimate& p : fits[0].parameters)
    if (p.name != "phi0")
      for (double stddev : p.stddev) EXPECT_TRUE(std::isfinite(stddev) && stddev > 0.0) << p.name;
}

// The renderer materials with a stretch (a strength and its rotation): gltf+anisotropy is fitted
// as its isotropic form, gltf; principled, whose isotropic lobe is no other model, with its
// anisotropic held at 0 and its rotation at its default.
TEST(Symmetry, TheRendererMaterialsStretchNothingOnIsotropicData) {
  const std::string path = test::scratch_path("isotropic-gltf.binary");
  const Model& gltf = *find_model("gltf");
  const std::vector<double> values = parameter_values(gltf, {"baseColor=0.8,0.6,0.3", "metallic=0.9", "roughness=0.4"});
  write_merl(path, [&](const Vec3& l, const Vec3& v) { return *gltf.brdf(values.data(), l, v); });
  SamplingOptions sampling;
  sampling.max_samples = 20000;
  const SampleSet set = load_samples(path, sampling);
  ASSERT_TRUE(set.isotropic);
  FitOptions options;
  options.threads = 2;
  const std::vector<FitResult> fits =
      fit_models({find_model("gltf"), find_model("gltf+anisotropy"), find_model("principled")}, set, options);
  const auto param = [](const FitResult& fit, const std::string& name) {
    return *std::find_if(fit.parameters.begin(), fit.parameters.end(),
                         [&](const ParameterEstimate& p) { return p.name == name; });
  };
  const FitResult &iso = fits[0], &stretched = fits[1], &principled = fits[2];
  ASSERT_TRUE(stretched.ok && principled.ok) << stretched.error << principled.error;
  EXPECT_EQ(param(stretched, "anisotropyStrength").value[0], 0.0);
  EXPECT_EQ(param(stretched, "roughness").value[0], param(iso, "roughness").value[0]);
  EXPECT_NEAR(stretched.metrics.cosine, iso.metrics.cosine, 1e-9 * iso.metrics.cosine + 1e-12);
  EXPECT_FALSE(param(stretched, "anisotropyRotation").identifiable);
  EXPECT_TRUE(test::mentions(stretched.warnings, "fitted in its isotropic form, gltf"))
      << ::testing::PrintToString(stretched.warnings);
  EXPECT_TRUE(test::mentions(stretched.warnings, "anisotropyStrength = 0 is held: the data are isotropic"))
      << ::testing::PrintToString(stretched.warnings);
  EXPECT_EQ(param(principled, "anisotropic").value[0], 0.0);
  EXPECT_TRUE(param(principled, "anisotropic").fixed);
  EXPECT_EQ(param(principled, "anisotropicRotation").value[0], 0.0);
  EXPECT_TRUE(
      test::mentions(principled.warnings, "principled was fitted with its lobe held isotropic (anisotropic = 0"))
      << ::testing::PrintToString(principled.warnings);
  // The user's held parameters get the isotropic ones added.
  options.fixed = {{"metallic", 1.0}};
  const FitResult held = fit_models({find_model("principled")}, set, options)[0];
  ASSERT_TRUE(held.ok) << held.error;
  EXPECT_TRUE(param(held, "metallic").fixed);
  EXPECT_TRUE(param(held, "anisotropic").fixed);
  EXPECT_EQ(param(held, "anisotropic").value[0], 0.0);
}

// --- verdicts -------------------------------------------------------------------------------------

// The case an expert found: gltf fitted to white paper by the log metric came back good with a
// cosine error 40000x Lambert's. Whatever was minimised, a good fit is within 5% of Lambert on
// every judged metric.
TEST(Verdicts, AGoodFitIsWithinFivePercentOfLambertOnEveryJudgedMetric) {
  const std::string path = test::kSharedDir + "/data/rgl/paper_white_rgb.bsdf";
  SKIP_UNLESS_SHARED(std::filesystem::exists(path), path);
  SamplingOptions sampling;
  sampling.max_samples = 20000;
  const SampleSet set = load_samples(path, sampling);
  FitOptions options;
  options.metric = Metric::Log;
  options.threads = 2;
  const std::vector<FitResult> results = fit_models({find_model("lambert"), find_model("gltf")}, set, options);
  const FitResult& lambert = results[0];
  for (const FitResult& r : results) {
    SCOPED_TRACE(r.model);
    if (r.verdict != Verdict::Good) {
      EXPECT_TRUE(test::mentions(r.warnings, "poor fit")) << ::testing::PrintToString(r.warnings);
      continue;
    }
    for (const Metric m : {Metric::Cosine, Metric::Log, Metric::Relative, Metric::L2})
      EXPECT_LE(r.metrics.get(m), 1.05 * lambert.metrics.get(m)) << metric_name(m);
  }
}

}  // namespace
}  // namespace brdffit
