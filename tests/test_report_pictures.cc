// report, numerically: the page of a batch of two MERL tables and a CSV (every image an embedded
// PNG, a section and plots per material), the measured pictures beside the best fit's agree, the
// error maps do not saturate and each slice's panel shows the bulk of its error, a sphere fit's
// photographs match the fit rendered under their lights, and Debian's headless Chromium loads the
// page without a missing image.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "brdffit/imaging/image_io.h"
#include "brdffit/imaging/render.h"
#include "report_test_util.h"
#include "sphere_scenes.h"

namespace brdffit {
namespace {

namespace fs = std::filesystem;
using Report = test::ReportPage;

TEST_F(Report, EveryImageIsAnEmbeddedPng) {
  ASSERT_EQ(batch_.exit_code, 0) << batch_.output;
  ASSERT_EQ(report_.exit_code, 0) << report_.output;
  const std::string html = page();
  // Per table: the measured sphere, environment sphere and slice, and per model those three and
  // the absolute and signed relative error of sphere and slice; per CSV material (no measured
  // pictures): each model's three; per table three colour bars (|error| twice, relative once).
  test::expect_embedded_pngs(html, 2 * (3 + 3 * 7) + 3 * 3 + 2 * 3);
  // The comparison, a section per material, a polar plot per row, the CSV material's note.
  EXPECT_NE(html.find("<table class=\"summary\">"), std::string::npos);
  for (const char* material : {"brushed", "plastic", "samples"})
    EXPECT_NE(html.find(std::string("id=\"m-") + material + "\""), std::string::npos) << material;
  EXPECT_NE(html.find("No measured pictures:"), std::string::npos);
  EXPECT_NE(html.find("samples.csv: a CSV of samples is not a table"), std::string::npos);
  // A polar plot and a slice with axes per row.
  EXPECT_EQ(test::occurrences(html, "class=\"polar\""), 2u * 4 + 3);
  EXPECT_EQ(test::occurrences(html, "<div class=\"axes\">"), 2u * 4 + 3);
  EXPECT_EQ(test::occurrences(html, ">θh °</text>"), 2u * 4 + 3);
}

TEST_F(Report, TheMeasuredPicturesAndTheBestFitsLookAlike) {
  // On the ggx-baked table ggx ranks first, and its pictures match the measured ones.
  const std::string html = page();
  for (const std::string picture_name : {"sphere", "slice", "environment"}) {
    const cv::Mat measured = test::picture(html, "plastic", "measured " + picture_name),
                  fitted = test::picture(html, "plastic", "1. ggx " + picture_name);
    ASSERT_FALSE(measured.empty()) << picture_name;
    ASSERT_FALSE(fitted.empty()) << picture_name;
    EXPECT_LT(test::relative_l1(measured, fitted), 0.03) << picture_name;
  }
}

TEST_F(Report, ErrorMapsDoNotSaturate) {
  const std::string html = page();
  // The |error| scale is the largest 99th percentile of any model's error: at most 1 % of the
  // worst model's sphere pixels reach the colour map's top, and fewer of the best model's.
  // (Inferno's top is pale yellow: red and green above 240 in the PNG, BGR order.)
  const auto saturated_fraction = [](const cv::Mat& bgr) {
    int saturated = 0, sphere = 0;
    for (int y = 0; y < bgr.rows; ++y)
      for (int x = 0; x < bgr.cols; ++x) {
        const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
        if (p[0] == p[1] && p[1] == p[2]) continue;  // the grey outside the sphere
        ++sphere;
        saturated += p[2] > 240 && p[1] > 240;
      }
    return sphere ? static_cast<double>(saturated) / sphere : 1.0;
  };
  for (const char* row : {"1. ggx", "2. ward", "3. lambert"}) {
    const cv::Mat error = test::picture(html, "plastic", std::string(row) + " sphere error");
    ASSERT_FALSE(error.empty()) << row;
    EXPECT_LE(saturated_fraction(error), 0.012) << row;
  }
  // The signed relative error of the exact fit is near zero: nearly white (within ±5 % of the
  // measured value shows as codes above 235 in every channel) on most of the sphere.
  const cv::Mat relative = test::picture(html, "plastic", "1. ggx sphere relative error");
  ASSERT_FALSE(relative.empty());
  int white = 0, sphere = 0;
  for (int y = 0; y < relative.rows; ++y)
    for (int x = 0; x < relative.cols; ++x) {
      const cv::Vec3b p = relative.at<cv::Vec3b>(y, x);
      if (p[0] < 60 && p[1] < 60 && p[2] < 60) continue;  // off the sphere
      ++sphere;
      white += p[0] > 235 && p[1] > 235 && p[2] > 235;
    }
  EXPECT_GT(white, 0.9 * sphere);
}

TEST_F(Report, ChromiumLoadsThePageWithEveryImage) {
  const std::string chromium = test::find_chromium();
  if (chromium.empty() && test::running_in_ci()) FAIL() << "chromium is missing (CI installs it)";
  if (chromium.empty())
    GTEST_SKIP() << "chromium is not installed (scripts/install-deps.sh installs it with BRDFFIT_WITH_CHROMIUM=1)";
  ASSERT_EQ(report_.exit_code, 0) << report_.output;
  const std::string profile = test::fresh_dir("chromium-profile"), shot = dir_ + "/report.png";
  const std::string browser = "timeout 180 " + chromium +
                              " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
                              " --disable-background-networking --disable-component-update --disable-sync"
                              " --user-data-dir=" +
                              profile + " --window-size=1280,2000 ";
  const std::string url = "file://" + dir_ + "/report.html";

  const test::CommandResult screenshot = test::run_command(browser + "--screenshot=" + shot + " " + url);
  ASSERT_TRUE(fs::exists(shot)) << screenshot.output;
  EXPECT_GT(fs::file_size(shot), 20000u);  // a page with pictures, not a blank one
  const ImageInfo info = read_image_info(shot);
  EXPECT_EQ(info.width, 1280);
  EXPECT_EQ(info.height, 2000);

  // The page's own check, run on load, reports every image decoded.
  const test::CommandResult dom = test::run_command(browser + "--virtual-time-budget=20000 --dump-dom " + url);
  const std::string marker = "id=\"image-check\" data-total=\"";
  const size_t at = dom.output.find(marker);
  ASSERT_NE(at, std::string::npos) << dom.output.substr(0, 2000);
  size_t total = 0, broken = 0;
  ASSERT_EQ(std::sscanf(dom.output.c_str() + at + marker.size(), "%zu\" data-broken=\"%zu\"", &total, &broken), 2)
      << dom.output.substr(at, 200);
  EXPECT_EQ(total, test::image_sources(page()).size());
  EXPECT_EQ(broken, 0u);
  EXPECT_NE(dom.output.find("data-sideways=\"0\""), std::string::npos) << dom.output.substr(at, 200);

  // At the default picture sizes, the page fits a window 1600 pixels wide: the pictures, polar
  // plots, parameters and warnings wrap or stack, nothing scrolls sideways.
  const std::string full = dir_ + "/report-full.html";
  const auto report = test::run_cli("report " + dir_ + "/fits -o " + full);
  ASSERT_EQ(report.exit_code, 0) << report.output;
  std::string wide = browser;
  wide.replace(wide.find("--window-size=1280,2000"), std::string("--window-size=1280,2000").size(),
               "--window-size=1600,2000");
  const test::CommandResult full_dom =
      test::run_command(wide + "--virtual-time-budget=20000 --dump-dom file://" + full);
  const size_t check = full_dom.output.find("id=\"image-check\"");
  ASSERT_NE(check, std::string::npos) << full_dom.output.substr(0, 2000);
  const std::string status = full_dom.output.substr(check, full_dom.output.find('>', check) - check);
  EXPECT_NE(status.find("data-broken=\"0\""), std::string::npos) << status;
  EXPECT_NE(status.find("data-sideways=\"0\""), std::string::npos) << status;
}

TEST_F(Report, EachSliceErrorPanelSaysItsScaleAndShowsTheBulkOfTheError) {
  const std::string html = page();
  // Under each slice |error| panel (two tables, three models each) its scale, and the legend's rule.
  size_t captions = 0;
  for (size_t at = html.find("(p99, θ ≤ 80°)</div>"); at != std::string::npos;
       at = html.find("(p99, θ ≤ 80°)</div>", at + 1))
    ++captions;
  EXPECT_EQ(captions, 2u * 3);
  EXPECT_NE(html.find("up to each panel's own 99th percentile of |error| where θi, θo ≤ 80°"), std::string::npos);
  // Lambert on the GGX plastic: a third of its slice (38 % when this was written) is within three
  // decades of the panel's top, so shows coloured (not black, not the no-data grey); at most 1 % of
  // the pixels within 80° lie above the 99th percentile, and those at the colour map's pale yellow
  // top (codes above 240 in red and green) are hardly more (the top code spans 3/255 of a decade).
  const cv::Mat lambert = test::picture(html, "plastic", "3. lambert slice error");
  ASSERT_FALSE(lambert.empty());
  const cv::Mat within = slice_mask(lambert.rows, 80.0);
  int shown = 0, saturated = 0;
  for (int y = 0; y < lambert.rows; ++y)
    for (int x = 0; x < lambert.cols; ++x) {
      const cv::Vec3b p = lambert.at<cv::Vec3b>(y, x);  // BGR
      shown += std::max({p[0], p[1], p[2]}) > 60 && !(p[0] == p[1] && p[1] == p[2]);
      saturated += within.at<uint8_t>(y, x) && p[2] > 240 && p[1] > 240;
    }
  EXPECT_GT(shown, lambert.rows * lambert.cols / 4);
  EXPECT_LE(saturated, 0.015 * cv::countNonZero(within));
}

TEST(SphereReport, ShowsThePhotographsBesideTheBestFitUnderTheSameLight) {
  // Photographs of a GGX sphere under four lights of different intensities, fitted; the report
  // shows four photographs, each beside GGX rendered with the document's light, intensity and
  // camera: the two pictures agree (a flipped axis, a wrong light or a missed intensity would not).
  const std::string dir = test::fresh_dir("sphere-report");
  const Model& ggx = *find_model("ggx");
  test::SceneOptions options;
  options.intensities = {Rgb<double>(1, 1, 1), Rgb<double>(2, 1.5, 1), Rgb<double>(0.5, 0.5, 0.8),
                         Rgb<double>(1.2, 1, 1)};
  options.noise_floor = 0.0;  // the black background, amplified by the sRGB curve, would dominate the norm
  const test::SphereScene scene =
      test::write_sphere_scene(dir, "p", ggx, parameter_values(ggx, {"albedo=0.5,0.35,0.2", "roughness=0.3"}),
                               {Vec3(-0.4, 0.3, 0.87).normalized(), Vec3(0.5, 0.2, 0.84).normalized(),
                                Vec3(0.1, -0.5, 0.86).normalized(), Vec3(0, 0, 1)},
                               options);
  std::string images;
  for (const std::string& path : scene.images) images += " " + path;
  const auto fit = test::run_cli("sphere" + images + " --lights " + scene.lights + " --intensities " +
                                 scene.intensities + " --mask " + scene.mask + " -m ggx,lambert -o " + dir + "/r.json");
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  const auto report = test::run_cli("report " + dir + "/r.json --size 96 -o " + dir + "/report.html");
  ASSERT_EQ(report.exit_code, 0) << report.output;
  const std::string html = read_file(dir + "/report.html");
  EXPECT_NE(html.find("Fitted from photographs"), std::string::npos);
  EXPECT_EQ(html.find("No measured pictures"), std::string::npos);
  EXPECT_NE(html.find("4 of 4 photographs shown"), std::string::npos);
  for (const std::string& path : scene.images) {
    SCOPED_TRACE(path);
    const cv::Mat photo = test::picture(html, "", "photograph " + path);
    const cv::Mat model = test::picture(html, "", "ggx under the light of " + path);
    ASSERT_FALSE(photo.empty());
    ASSERT_FALSE(model.empty());
    EXPECT_EQ(photo.size(), model.size());
    EXPECT_LT(test::relative_l1(photo, model), 0.05);
  }
}

}  // namespace
}  // namespace brdffit
