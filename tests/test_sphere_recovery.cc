// Photographed spheres, numerically: GGX's parameters recovered from rendered photographs (16-bit,
// 8-bit sRGB, unknown intensities), the sphere command with chrome-ball lights, and the DiLiGenT ball.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "brdffit/fit.h"
#include "brdffit/imaging/image_io.h"
#include "brdffit/imaging/sphere_fit.h"
#include "brdffit/io.h"
#include "brdffit/registry.h"
#include "sphere_scenes.h"
#include "test_util.h"

namespace brdffit {
namespace {

namespace fs = std::filesystem;

const std::string kDiligentBall = BRDFFIT_SHARED_DIR "/data/diligent-ball";

#define SKIP_WITHOUT_DILIGENT()                     \
  SKIP_UNLESS_SHARED(                               \
      fs::exists(kDiligentBall + "/filenames.txt"), \
      "the DiLiGenT ball at " << kDiligentBall << " (research use only, never copied into the project)")

// ---------------------------------------------------------------------------------------------
// Parameter recovery from rendered photographs

// Fits GGX to the observation and checks every parameter against the truth within `tolerance` (relative).
void expect_recovered(const SphereObservation& observation, const std::vector<double>& truth, double tolerance,
                      const char* what) {
  FitOptions options;
  options.loss = LossKind::Huber;
  const FitResult fit = fit_model(test::ggx(), observation.samples, options);
  ASSERT_TRUE(fit.ok) << fit.error;
  double worst = 0.0;
  for (size_t i = 0; i < truth.size(); ++i) {
    const double error = std::fabs(fit.values[i] / truth[i] - 1.0);
    EXPECT_LT(error, tolerance) << what << ": value " << i << " is " << fit.values[i] << ", truth " << truth[i];
    worst = std::max(worst, error);
  }
  std::printf("%s: %zu samples, worst relative parameter error %.2f%%\n", what, observation.samples.size(),
              100 * worst);
}

TEST(SphereRecovery, SixteenBitLinearWithNoise) {
  const std::string dir = test::fresh_dir("sphere-recover16");
  const std::vector<Rgb<double>> intensities = {{1.2, 1.0, 0.8}, {0.9, 1.1, 1.3}, {1.0, 1.0, 1.0}, {1.4, 1.2, 1.0},
                                                {0.8, 0.9, 1.0}, {1.1, 1.0, 0.9}, {1.0, 1.2, 1.1}, {0.9, 0.8, 1.2}};
  test::SceneOptions options;
  options.intensities = intensities;
  const test::SphereScene scene =
      test::write_sphere_scene(dir, "g", test::ggx(), test::ggx_truth(), test::dome_lights(8), options);
  SphereInput input;
  input.images = scene.images;
  input.lights = scene.lights;
  input.intensities = scene.intensities;
  input.mask = scene.mask;
  const SphereObservation observation = observe_sphere(input);
  EXPECT_EQ(observation.pixels.saturated, 0u);
  EXPECT_GT(observation.pixels.grazing, 0u);
  expect_recovered(observation, test::ggx_truth(), 0.03, "16-bit linear, 1% noise, mask");
}

TEST(SphereRecovery, EightBitSrgbWithNoiseAndDetectedSphere) {
  const std::string dir = test::fresh_dir("sphere-recover8");
  test::SceneOptions options;
  options.encoding = Encoding::Srgb8;
  const test::SphereScene scene =
      test::write_sphere_scene(dir, "g", test::ggx(), test::ggx_truth(), test::dome_lights(8), options);
  SphereInput input;
  input.images = scene.images;
  input.lights = scene.lights;
  input.intensities = scene.intensities;
  const SphereObservation observation = observe_sphere(input);
  EXPECT_EQ(observation.located_by, "detection");
  expect_recovered(observation, test::ggx_truth(), 0.03, "8-bit sRGB, 1% noise, detected sphere");
}

TEST(SphereRecovery, UnknownIntensitiesKeepShapeAndColourRatios) {
  const std::string dir = test::fresh_dir("sphere-recover-unknown");
  test::SceneOptions options;
  options.intensities.assign(8, Rgb<double>(1.7, 1.7, 1.7));  // brighter than the files will say
  options.extension = ".exr";
  options.encoding = Encoding::Float;
  const test::SphereScene scene =
      test::write_sphere_scene(dir, "g", test::ggx(), test::ggx_truth(), test::dome_lights(8), options);
  SphereInput input;
  input.images = scene.images;
  input.lights = scene.lights;
  input.mask = scene.mask;
  const SphereObservation observation = observe_sphere(input);
  EXPECT_FALSE(observation.intensities_known);
  // Scaled so that the 99th percentile of the values is 0.25.
  std::vector<double> brightest;
  for (const Sample& s : observation.samples.samples) brightest.push_back(s.value.maxCoeff());
  std::sort(brightest.begin(), brightest.end());
  EXPECT_NEAR(brightest[static_cast<size_t>(0.99 * (brightest.size() - 1))], 0.25, 1e-6);
  // Colours come back times 1.7/s, the shape unchanged.
  std::vector<double> truth = test::ggx_truth();
  for (const char* colour : {"albedo", "f0"})
    for (int c = 0; c < 3; ++c) truth[test::ggx().offset_of(colour) + c] *= 1.7 / observation.intensity_scale;
  expect_recovered(observation, truth, 0.03, "float EXR, unknown intensities");
}

// ---------------------------------------------------------------------------------------------
// The sphere command

TEST(SphereCli, ChromeBallLightsAndDiligentStyleFolder) {
  const std::string dir = test::fresh_dir("sphere-cli-chrome");
  const std::vector<Vec3> lights = test::dome_lights(6, 45.0);
  const test::SphereScene chrome = test::write_chrome_scene(dir, lights, Encoding::Linear16);
  // The object photographs in a DiLiGenT-style folder, without a lights file.
  const std::string folder = dir + "/object";
  const test::SphereScene object = test::write_sphere_scene(folder, "", test::ggx(), test::ggx_truth(), lights);
  std::string names;
  for (const std::string& path : object.images) names += fs::path(path).filename().string() + "\n";
  write_file_atomic(folder + "/filenames.txt", names);
  fs::rename(object.mask, folder + "/mask.png");
  std::string chrome_images;
  for (const std::string& path : chrome.images) chrome_images += " " + path;
  const auto r = test::run_cli("sphere " + folder + " --chrome" + chrome_images + " --chrome-mask " + chrome.mask +
                               " --models ggx --out " + dir + "/r.json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json doc = nlohmann::json::parse(read_file(dir + "/r.json"));
  EXPECT_EQ(doc["lights_from"], "chrome");
  EXPECT_EQ(doc["sphere"]["located_by"], "mask " + folder + "/mask.png");
  ASSERT_EQ(doc["lights"].size(), lights.size());
  for (size_t i = 0; i < lights.size(); ++i) {
    const nlohmann::json& l = doc["lights"][i];
    EXPECT_LT(test::angle_deg(Vec3(l[0], l[1], l[2]), lights[i]), 1.0) << i;
  }
  EXPECT_NEAR(doc["models"][0]["parameters"]["roughness"]["value"].get<double>(), 0.3, 0.015);
}

// ---------------------------------------------------------------------------------------------
// DiLiGenT ball

TEST(Diligent, NormalsFromTheLocatedSphereMatchTheGroundTruth) {
  SKIP_WITHOUT_DILIGENT();
  SphereInput input;
  add_diligent_folder(kDiligentBall, input);
  ASSERT_EQ(input.images.size(), 96u);
  const cv::Mat mask = read_mask(input.mask);
  const Circle from_mask = circle_from_mask(mask, input.mask);
  const Circle detected = detect_sphere(brightest_of(input.images, {}), "DiLiGenT ball");
  EXPECT_NEAR(detected.x, from_mask.x, 1.0);
  EXPECT_NEAR(detected.y, from_mask.y, 1.0);
  EXPECT_NEAR(detected.radius, from_mask.radius, 1.0);

  for (const auto& [name, circle] : {std::pair<const char*, Circle>{"mask", from_mask}, {"detection", detected}}) {
    const NormalCheck check = check_normals(SphereView(circle, Camera{}), input.normals, mask.size(), mask);
    EXPECT_GT(check.pixels, 15000u) << name;  // the mask holds 15779 sphere pixels
    EXPECT_LE(check.median_deg, 2.0) << name;
    EXPECT_LE(check.p90_deg, 5.0) << name;
  }
}

TEST(Diligent, GgxReproducesTheRealPhotographsBetterThanLambert) {
  SKIP_WITHOUT_DILIGENT();
  SphereInput input;
  add_diligent_folder(kDiligentBall, input);
  input.max_gathered = 100000;  // a coarser pixel grid: the same fit, a test's time
  const SphereObservation observation = observe_sphere(input);
  EXPECT_LT(observation.normals->median_deg, 2.0);
  FitOptions options;
  options.loss = LossKind::Huber;
  const std::vector<FitResult> fits =
      fit_models({find_model("lambert"), find_model("ggx")}, observation.samples, options);
  ASSERT_TRUE(fits[0].ok && fits[1].ok) << fits[0].error << fits[1].error;
  const std::vector<PhotoError> errors = compare_with_photographs(observation, input, fits);
  ASSERT_EQ(errors.size(), 2u);
  // Relative RMS of the rendered images over every used pixel of the 96 photographs: the glossy
  // ball's highlights are what a diffuse model misses.
  EXPECT_LT(errors[1].relative_rms, 0.10);
  EXPECT_GT(errors[0].relative_rms, errors[1].relative_rms + 0.03);
  EXPECT_EQ(errors[1].per_image.size(), 96u);
  // A plausible glossy dielectric: a yellowish diffuse albedo and a small, grey F0.
  const std::vector<double>& v = fits[1].values;
  const int albedo = test::ggx().offset_of("albedo"), f0 = test::ggx().offset_of("f0");
  EXPECT_GT(v[albedo], v[albedo + 2]);
  EXPECT_GT(v[test::ggx().offset_of("roughness")], 0.1);
  EXPECT_LT(v[test::ggx().offset_of("roughness")], 0.35);
  EXPECT_LT(v[f0], 0.05);
}

}  // namespace
}  // namespace brdffit
