// render: sphere pictures of tables and fitted models, slices, curves, tone mapping, the command.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "batch_test_util.h"
#include "brdffit/error.h"
#include "brdffit/image_io.h"
#include "brdffit/merl.h"
#include "brdffit/render.h"

namespace brdffit {
namespace {

FitResult lambert_fit(double r, double g, double b) {
  FitResult fit = test::known_result("lambert", 0.01);
  fit.values = {r, g, b};
  return fit;
}

TEST(Render, LightInTheCameraFrame) {
  SphereLighting lighting;
  lighting.light = Vec3(1, 2, 3);
  EXPECT_TRUE(light_in_camera_frame(lighting).isApprox(Vec3(1, 2, 3).normalized()));
  // Seen from +x, with +y still up: the camera's z is world x and its right is world -z.
  lighting.view = Vec3(1, 0, 0);
  EXPECT_TRUE(light_in_camera_frame(lighting).isApprox(Vec3(-3, 2, 1).normalized()));
  lighting.view = Vec3::Zero();
  EXPECT_THROW(light_in_camera_frame(lighting), Error);
}

TEST(Render, FittedSphereCentreIsTheModelsShadedValue) {
  const Model& lambert = *find_model("lambert");
  const FitResult fit = lambert_fit(0.2, 0.4, 0.6);
  const SphereLighting lighting;  // light (-1,1,2)/√6, view +z
  const cv::Mat sphere = render_fitted_sphere(lambert, fit, lighting, 65);
  // Pixel (32, 32) is the centre: normal and view +z, so the shade is albedo/π · l.z.
  const cv::Vec3f centre = sphere.at<cv::Vec3f>(32, 32);
  const double cos_i = 2.0 / std::sqrt(6.0);
  EXPECT_NEAR(centre[0], 0.2 / kPi * cos_i, 1e-6);
  EXPECT_NEAR(centre[2], 0.6 / kPi * cos_i, 1e-6);
  EXPECT_EQ(sphere.at<cv::Vec3f>(0, 0), cv::Vec3f(0, 0, 0));  // off the sphere
  EXPECT_EQ(sphere_mask(65).at<uint8_t>(32, 32), 255);
  EXPECT_EQ(sphere_mask(65).at<uint8_t>(0, 0), 0);
}

TEST(Render, MeasuredSphereOfABakedModelMatchesTheModel) {
  const Model& ggx = *find_model("ggx");
  FitResult fit = test::known_result("ggx", 0.01);
  fit.values = parameter_values(ggx, {"albedo=0.3,0.2,0.1", "roughness=0.5", "f0=0.05"});
  const std::string path = test::fresh_dir("render-baked") + "/ggx.binary";
  write_merl(path, [&](const Vec3& l, const Vec3& v) { return *ggx.brdf(fit.values.data(), l, v); });
  const MerlTable table = MerlTable::read(path);
  const cv::Mat measured = render_measured_sphere(table, SphereLighting{}, 96);
  const cv::Mat fitted = render_fitted_sphere(ggx, fit, SphereLighting{}, 96);
  // The same pixels light up, with the same values up to the table's binning.
  const cv::Mat mask = sphere_mask(96);
  double difference = 0.0, total = 0.0;
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 96; ++x) {
      if (!mask.at<uint8_t>(y, x)) continue;
      difference += cv::norm(measured.at<cv::Vec3f>(y, x) - fitted.at<cv::Vec3f>(y, x), cv::NORM_L1);
      total += cv::norm(fitted.at<cv::Vec3f>(y, x), cv::NORM_L1);
    }
  EXPECT_LT(difference / total, 0.02);
}

TEST(Render, SliceAndCurvesOfALambertianAreFlat) {
  const Model& lambert = *find_model("lambert");
  const FitResult fit = lambert_fit(0.3, 0.3, 0.3);
  const BrdfFunction f = fitted_brdf(lambert, fit);
  const cv::Mat slice = half_diff_slice(f, 32);
  EXPECT_NEAR(slice.at<cv::Vec3f>(0, 0)[1], 0.3 / kPi, 1e-6);    // θh, θd near 0
  EXPECT_NEAR(slice.at<cv::Vec3f>(31, 31)[1], 0.3 / kPi, 1e-6);  // both near 90°: n·l = cosθh·cosθd > 0 still
  for (double value : in_plane_curve(f, 45.0, 19)) EXPECT_NEAR(value, 0.3 / kPi, 1e-9);

  FitResult wrong = fit;
  wrong.values = {0.3};
  EXPECT_THROW(fitted_brdf(lambert, wrong), Error);
}

TEST(Render, SliceAndCurveAxesAreTheDocumentedAngles) {
  // A "BRDF" that reports the angles it is asked about, computed here from l and v: a transposed
  // slice or a mirrored curve puts them in the wrong place.
  const auto degrees = [](double radians) { return radians * 180.0 / kPi; };
  const BrdfFunction angles = [&](const Vec3& l, const Vec3& v) {
    const Vec3 h = (l + v).normalized();
    return Rgb<double>(degrees(std::acos(h.z())), degrees(std::acos(std::clamp(l.dot(h), -1.0, 1.0))), 0.0);
  };
  const int size = 30;
  const cv::Mat slice = half_diff_slice(angles, size);
  for (int y = 0; y < size; y += 7)
    for (int x = 0; x < size; x += 5) {
      const double u = (x + 0.5) / size;
      EXPECT_NEAR(slice.at<cv::Vec3f>(y, x)[0], u * u * 90.0, 90.0 / size) << "θh at column " << x;
      EXPECT_NEAR(slice.at<cv::Vec3f>(y, x)[1], (y + 0.5) / size * 90.0, 90.0 / size) << "θd at row " << y;
    }

  // The curve: luminance of (a, a, a) is a; a = θo in degrees, signed, positive away from the
  // light, plus 100. The light is on the -x side at θi.
  const BrdfFunction outgoing = [&](const Vec3& l, const Vec3& v) {
    EXPECT_NEAR(degrees(std::atan2(-l.x(), l.z())), 30.0, 1e-9);
    return Rgb<double>::Constant(100.0 + degrees(std::atan2(v.x(), v.z())));
  };
  const std::vector<double> curve = in_plane_curve(outgoing, 30.0, 19);
  ASSERT_EQ(curve.size(), 19u);
  for (int i = 0; i < 19; ++i) EXPECT_NEAR(curve[i], 100.0 - 89.0 + i * 178.0 / 18, 1e-6) << i;
}

TEST(Render, ToneMapPutsTheReferenceAtThreeQuartersGreyAndRollsOffToWhite) {
  cv::Mat linear(1, 4, CV_32FC3);
  linear.at<cv::Vec3f>(0, 0) = cv::Vec3f::all(0.5f);  // the reference
  linear.at<cv::Vec3f>(0, 1) = cv::Vec3f::all(2.0f);  // 4x: white
  linear.at<cv::Vec3f>(0, 2) = cv::Vec3f::all(9.0f);  // beyond: clipped
  linear.at<cv::Vec3f>(0, 3) = cv::Vec3f::all(NAN);   // no data: dark grey
  const cv::Mat display = tone_map(linear, 0.5);
  EXPECT_NEAR(display.at<cv::Vec3f>(0, 0)[0], 1.0625 / 2.0, 1e-6);
  EXPECT_NEAR(display.at<cv::Vec3f>(0, 1)[0], 1.0, 1e-6);
  EXPECT_NEAR(display.at<cv::Vec3f>(0, 2)[0], 1.0, 1e-6);
  EXPECT_GT(display.at<cv::Vec3f>(0, 3)[0], 0.0f);
  EXPECT_LT(display.at<cv::Vec3f>(0, 3)[0], 0.1f);
  EXPECT_NEAR(tone_reference(linear), 9.0, 1e-6);  // 99th percentile of the finite pixels
}

TEST(RenderCli, WritesToneMappedPngAndLinearExr) {
  const std::string dir = test::fresh_dir("render-cli");
  const std::string doc = test::write_document(dir + "/r.json", dir + "/table.binary", {lambert_fit(0.2, 0.4, 0.6)});
  const double shade_g = 0.4 / kPi * (2.0 / std::sqrt(6.0));

  const auto exr = test::run_cli("render " + doc + " -m lambert --size 65 --out " + dir + "/s.exr");
  ASSERT_EQ(exr.exit_code, 0) << exr.output;
  EXPECT_NEAR(read_image(dir + "/s.exr").at<cv::Vec3f>(32, 32)[1], shade_g, 1e-6);

  // The PNG holds tone_map's display value, sRGB-encoded in 8 bits.
  const auto png = test::run_cli("render " + doc + " -m lambert --size 65 --reference 0.1 --out " + dir + "/s.png");
  ASSERT_EQ(png.exit_code, 0) << png.output;
  const double v = shade_g / 0.1, expected = v * (1 + v / 16) / (1 + v);
  const ImageInfo info = read_image_info(dir + "/s.png");
  EXPECT_EQ(info.bits, 8);
  EXPECT_EQ(info.width, 65);
  EXPECT_NEAR(read_image(dir + "/s.png").at<cv::Vec3f>(32, 32)[1], expected, 0.01 * expected);

  // A measured table, from the side.
  const Model& lambert = *find_model("lambert");
  const std::vector<double> grey = parameter_values(lambert, {"albedo=0.5"});
  write_merl(dir + "/table.binary", [&](const Vec3& l, const Vec3& v) { return *lambert.brdf(grey.data(), l, v); });
  const auto table =
      test::run_cli("render " + dir + "/table.binary --light 0,1,0 --view 0,0,1 --size 33 --out " + dir + "/t.exr");
  ASSERT_EQ(table.exit_code, 0) << table.output;
  const cv::Mat side = read_image(dir + "/t.exr");
  EXPECT_GT(side.at<cv::Vec3f>(2, 16)[0], 0.1f);   // the top of the sphere faces the light
  EXPECT_EQ(side.at<cv::Vec3f>(30, 16)[0], 0.0f);  // the bottom is in shadow

  test::expect_cli_errors(
      {{"render " + doc + " --out " + dir + "/x.png", "choose the model to render with -m (lambert)"},
       {"render " + doc + " -m ggx --out " + dir + "/x.png", "has no ggx result (it has lambert)"},
       {"render " + dir + "/table.binary --light 0,0,0 --out " + dir + "/x.png", "non-zero directions"},
       {"render " + dir + "/nothing.binary --out " + dir + "/x.png", "nothing.binary"}},
      dir + "/x.png");
}

}  // namespace
}  // namespace brdffit
