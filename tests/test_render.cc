// render: sphere pictures of tables and fitted models, slices, curves, tone mapping, the command.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "batch_test_util.h"
#include "brdffit/error.h"
#include "brdffit/imaging/image_io.h"
#include "brdffit/imaging/render.h"
#include "brdffit/merl.h"
#include "brdffit/registry.h"

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

TEST(Render, SignedRelativeErrorAndItsColours) {
  cv::Mat measured(1, 4, CV_32FC3), fit(1, 4, CV_32FC3);
  measured.at<cv::Vec3f>(0, 0) = cv::Vec3f::all(0.5f);
  fit.at<cv::Vec3f>(0, 0) = cv::Vec3f::all(0.6f);  // 20 % too bright
  measured.at<cv::Vec3f>(0, 1) = cv::Vec3f(1.0f, 0.0f, 0.0f);
  fit.at<cv::Vec3f>(0, 1) = cv::Vec3f(0.5f, 0.0f, 0.0f);  // half the red: luminance too, −50 %
  measured.at<cv::Vec3f>(0, 2) = cv::Vec3f::all(0.0f);
  fit.at<cv::Vec3f>(0, 2) = cv::Vec3f::all(0.01f);  // black measured: divided by the floor 0.1
  measured.at<cv::Vec3f>(0, 3) = cv::Vec3f::all(NAN);
  fit.at<cv::Vec3f>(0, 3) = cv::Vec3f::all(0.1f);
  const cv::Mat relative = signed_relative_difference(fit, measured, 0.1);
  EXPECT_NEAR(relative.at<float>(0, 0), 0.2, 1e-6);
  EXPECT_NEAR(relative.at<float>(0, 1), -0.5, 1e-6);
  EXPECT_NEAR(relative.at<float>(0, 2), 0.1, 1e-6);
  EXPECT_TRUE(std::isnan(relative.at<float>(0, 3)));
  // Full scale ±0.5: +0.2 is a light red (red above green and blue), −0.5 full blue, NaN grey.
  const cv::Mat colours = signed_heatmap(relative, 0.5);
  const cv::Vec3f light_red = colours.at<cv::Vec3f>(0, 0), blue = colours.at<cv::Vec3f>(0, 1);
  EXPECT_GT(light_red[0], light_red[1]);
  EXPECT_NEAR(light_red[1], light_red[2], 0.05);
  EXPECT_GT(light_red[1], 0.3f);  // not saturated: still pale
  EXPECT_GT(blue[2], 3 * blue[0]);
  EXPECT_LT(blue[0], 0.05f);
  EXPECT_EQ(colours.at<cv::Vec3f>(0, 3)[0], colours.at<cv::Vec3f>(0, 3)[2]);
  EXPECT_LT(colours.at<cv::Vec3f>(0, 3)[0], 0.05f);
  // A zero error is white, the same in every channel.
  const cv::Mat zero = signed_heatmap(cv::Mat(1, 1, CV_32F, cv::Scalar(0.0)), 0.5);
  EXPECT_GT(zero.at<cv::Vec3f>(0, 0)[1], 0.9f);
  EXPECT_EQ(zero.at<cv::Vec3f>(0, 0)[0], zero.at<cv::Vec3f>(0, 0)[2]);
}

TEST(Render, QuantileIsTheNearestRankOfTheFiniteMaskedValues) {
  cv::Mat values(1, 6, CV_32F);
  const float v[] = {5, 1, NAN, 3, 2, 100};
  for (int i = 0; i < 6; ++i) values.at<float>(0, i) = v[i];
  EXPECT_EQ(quantile(values, 0.5), 3.0);  // of 1 2 3 5 100: the 3rd
  EXPECT_EQ(quantile(values, 1.0), 100.0);
  cv::Mat mask(1, 6, CV_8U, cv::Scalar(255));
  mask.at<uint8_t>(0, 5) = 0;
  EXPECT_EQ(quantile(values, 1.0, mask), 5.0);
  EXPECT_EQ(quantile(cv::Mat(1, 1, CV_32F, cv::Scalar(NAN)), 0.5), 0.0);
}

TEST(Render, EnvironmentSphereOfLambertIsItsIrradiance) {
  // For Lambert, each pixel is albedo/π times the irradiance at its normal: the same picture for
  // albedo 0.4 is 0.4x that for albedo 1, the centre (normal toward the camera) is lit, and the
  // top, facing the bright sky, is brighter than the bottom, facing the dim ground.
  const Model& lambert = *find_model("lambert");
  const std::vector<double> white = {1, 1, 1}, grey = {0.4, 0.4, 0.4};
  const auto brdf_of = [&](const std::vector<double>& values) {
    return [&lambert, values](const Vec3& l, const Vec3& v) { return *lambert.brdf(values.data(), l, v); };
  };
  const cv::Mat a = render_environment_sphere(brdf_of(white), 41), b = render_environment_sphere(brdf_of(grey), 41);
  EXPECT_NEAR(b.at<cv::Vec3f>(20, 20)[1], 0.4 * a.at<cv::Vec3f>(20, 20)[1], 1e-5);
  EXPECT_GT(a.at<cv::Vec3f>(20, 20)[1], 0.1f);
  EXPECT_GT(a.at<cv::Vec3f>(3, 20)[1], 2 * a.at<cv::Vec3f>(37, 20)[1]);
  EXPECT_EQ(a.at<cv::Vec3f>(0, 0)[1], 0.0f);  // off the sphere
  // The irradiance at the centre: Σ over the lights in front of radiance·4π/K·cosθ. The sky alone
  // (no key light) gives at most ∫ 1·cosθ dω = π over the front hemisphere; with the key light
  // it is between the sky's minimum (0.25π·(1/2)) and the sky's maximum plus the key's.
  const double irradiance = a.at<cv::Vec3f>(20, 20)[1] * kPi;
  EXPECT_GT(irradiance, 0.1 * kPi);
  EXPECT_LT(irradiance, kPi + 3.6 * 0.6);
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

  // A fit is tone-mapped with its table's reference by default, so the two pictures compare: the
  // fit's green albedo 0.4 shows darker than the table's 0.5 (each on its own scale they would
  // look alike).
  const auto table_png = test::run_cli("render " + dir + "/table.binary --size 65 --out " + dir + "/t.png");
  const auto fit_png = test::run_cli("render " + doc + " -m lambert --size 65 --out " + dir + "/f.png");
  ASSERT_EQ(table_png.exit_code, 0) << table_png.output;
  ASSERT_EQ(fit_png.exit_code, 0) << fit_png.output;
  const auto reference_in = [](const std::string& output) {
    const size_t at = output.find("tone reference ");
    return at == std::string::npos ? -1.0 : std::stod(output.substr(at + 15));
  };
  EXPECT_GT(reference_in(table_png.output), 0.0) << table_png.output;
  EXPECT_EQ(reference_in(fit_png.output), reference_in(table_png.output)) << fit_png.output;
  EXPECT_NE(fit_png.output.find("the measured table's"), std::string::npos) << fit_png.output;
  const float table_green = read_image(dir + "/t.png").at<cv::Vec3f>(32, 32)[1],
              fit_green = read_image(dir + "/f.png").at<cv::Vec3f>(32, 32)[1];
  EXPECT_LT(fit_green, 0.9f * table_green);

  test::expect_cli_errors(
      {{"render " + doc + " --out " + dir + "/x.png", "choose the model to render with -m (lambert)"},
       {"render " + doc + " -m ggx --out " + dir + "/x.png", "has no ggx result (it has lambert)"},
       {"render " + dir + "/table.binary --light 0,0,0 --out " + dir + "/x.png", "non-zero directions"},
       {"render " + dir + "/nothing.binary --out " + dir + "/x.png", "nothing.binary"}},
      dir + "/x.png");
}

}  // namespace
}  // namespace brdffit
