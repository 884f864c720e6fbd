// report: a page built from a real batch (the bundled RGL table and a CSV of samples), every
// image a valid PNG, and the error scale of a slice (the page of two baked MERL tables, its
// pictures and Chromium loading it: test_report_pictures.cc, with the numerical tests).
#include <gtest/gtest.h>

#include <filesystem>

#include "brdffit/imaging/image_io.h"
#include "brdffit/imaging/render.h"
#include "report_test_util.h"
#include "test_util.h"

namespace brdffit {

namespace fs = std::filesystem;
namespace {

TEST(ReportOfARealTable, EveryImageIsAnEmbeddedPngAndEveryMaterialHasItsSection) {
  // The bundled RGL table and a CSV of samples, two models, small pictures: the report's code under
  // the sanitizers in seconds (the numerical tests' page of two MERL tables and three models:
  // test_report_pictures.cc).
  const std::string dir = test::fresh_dir("report-real-table");
  fs::create_directories(dir + "/tables");
  fs::copy_file(std::string(BRDFFIT_SOURCE_DIR) + "/data/cc_ibiza_sunset_rgb.bsdf", dir + "/tables/sunset.bsdf");
  test::write_model_csv(dir + "/tables/samples.csv", "lambert", {"albedo=0.4,0.4,0.2"}, 500);
  const auto batch =
      test::run_cli("batch " + dir + "/tables --models lambert,ggx --max-samples 3000 --out " + dir + "/fits");
  ASSERT_EQ(batch.exit_code, 0) << batch.output;
  const auto report = test::run_cli("report " + dir + "/fits --size 24 --out " + dir + "/report.html");
  ASSERT_EQ(report.exit_code, 0) << report.output;
  const std::string html = read_file(dir + "/report.html");
  // The table: its measured sphere, environment sphere and slice, per model those three and the
  // absolute and signed relative error of sphere and slice, three colour bars; the CSV: each
  // model's three.
  test::expect_embedded_pngs(html, (3 + 2 * 7 + 3) + 2 * 3);
  for (const char* material : {"sunset", "samples"})
    EXPECT_NE(html.find(std::string("id=\"m-") + material + "\""), std::string::npos) << material;
  EXPECT_NE(html.find("No measured pictures:"), std::string::npos);
  // A polar plot and a slice with axes per row: the measured table and each fit.
  EXPECT_EQ(test::occurrences(html, "class=\"polar\""), 3u + 2);
  EXPECT_EQ(test::occurrences(html, "<div class=\"axes\">"), 3u + 2);
  EXPECT_EQ(test::occurrences(html, ">θh °</text>"), 3u + 2);
}

// The sRGB code of the brightest channel of a display picture's pixel, as the PNG stores it.
int brightest_code(const cv::Mat& display, int y, int x) {
  cv::Mat pixel = display(cv::Rect(x, y, 1, 1)).clone();
  linear_to_srgb(pixel);
  const cv::Vec3f p = pixel.at<cv::Vec3f>(0, 0);
  return static_cast<int>(std::lround(255.0 * std::clamp(std::max({p[0], p[1], p[2]}), 0.0f, 1.0f)));
}

TEST(ReportErrorScale, ASliceKeepsItsTypicalErrorVisibleBesideHugeGrazingPixels) {
  // A slice's |error|: typical values 0.005..0.015 (a deterministic ripple), 1000 times that
  // beyond 80° (a table of f·cosθ divided by a vanishing cosine), and one pixel in 200 within 80°
  // an outlier of 5. The scale is the 99th percentile within 80°: the outliers (0.5 %) stay above
  // it, so it is the typical values' top, about 0.015, and a typical 0.01 shows bright.
  const int size = 128;
  const cv::Mat within = slice_mask(size, 80.0);
  // half_diff_slice's pixel centres: θd = (y + ½)/128·90° is 79.8° at y = 113 and 80.5° at 114 (θh ≈ 0
  // in column 0); θh = ((x + ½)/128)²·90° is 79.8° at x = 120 and 81.1° at 121 (θd = 0.35° in row 0).
  EXPECT_EQ(within.at<uint8_t>(113, 0), 255);
  EXPECT_EQ(within.at<uint8_t>(114, 0), 0);
  EXPECT_EQ(within.at<uint8_t>(0, 120), 255);
  EXPECT_EQ(within.at<uint8_t>(0, 121), 0);
  cv::Mat error(size, size, CV_32F);
  int inside = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const float typical = 0.005f + 0.01f * static_cast<float>((7 * x + 13 * y) % 101) / 100.0f;
      if (!within.at<uint8_t>(y, x))
        error.at<float>(y, x) = 1000.0f * typical;
      else
        error.at<float>(y, x) = ++inside % 200 == 0 ? 5.0f : typical;
    }
  error.at<float>(0, 0) = 0.01f;  // the typical pixel looked at below

  const ErrorPanel linear = robust_error_panel(error, 0.99, within);
  EXPECT_GT(linear.full_scale, 0.0145);
  EXPECT_LE(linear.full_scale, 0.015 + 1e-6);
  // 0.01 of ~0.015 is two thirds up inferno: an orange well above black (its code 0.67·255 in the
  // map's red channel, ≥ 200); the grazing pixels saturate at the map's pale yellow top.
  EXPECT_GT(brightest_code(linear.image, 0, 0), 180);
  EXPECT_GT(brightest_code(linear.image, size - 1, 0), 240);
  // Scaled by the largest value, as a plain maximum would, the same pixel is black.
  EXPECT_LT(brightest_code(error_heatmap(error, 15.0), 0, 0), 20);

  // On a log scale over 3 decades below the same top, 0.01 sits at (3 + log10(0.01/0.015))/3 = 0.94
  // of the map, and an error a thousandth of the typical one is black.
  const ErrorPanel logarithmic = robust_error_panel(error, 0.99, within, 3);
  EXPECT_DOUBLE_EQ(logarithmic.full_scale, linear.full_scale);
  EXPECT_GT(brightest_code(logarithmic.image, 0, 0), 230);
  error.at<float>(0, 0) = 1e-5f;
  EXPECT_LT(brightest_code(robust_error_panel(error, 0.99, within, 3).image, 0, 0), 20);
}

}  // namespace
}  // namespace brdffit
