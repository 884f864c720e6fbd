// report: a page built from a real batch (two baked MERL tables and a CSV of samples), every
// image a valid PNG, and the error scale of a slice (the pictures themselves and Chromium loading
// the page: test_report_pictures.cc).
#include <gtest/gtest.h>

#include <filesystem>

#include "brdffit/imaging/image_io.h"
#include "brdffit/imaging/render.h"
#include "report_test_util.h"

namespace brdffit {

namespace fs = std::filesystem;
namespace {

using Report = test::ReportPage;

TEST_F(Report, EveryImageIsAnEmbeddedPng) {
  ASSERT_EQ(batch_.exit_code, 0) << batch_.output;
  ASSERT_EQ(report_.exit_code, 0) << report_.output;
  const std::string html = page();
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);  // nothing from elsewhere
  EXPECT_EQ(html.find("href=\"http"), std::string::npos);
  const std::vector<std::string> sources = test::image_sources(html);
  // Per table: the measured sphere, environment sphere and slice, and per model those three and
  // the absolute and signed relative error of sphere and slice; per CSV material (no measured
  // pictures): each model's three; per table three colour bars (|error| twice, relative once).
  EXPECT_EQ(sources.size(), 2 * (3 + 3 * 7) + 3 * 3 + 2 * 3);
  for (const std::string& source : sources) {
    const cv::Mat image = test::decode_png_data_uri(source);
    ASSERT_FALSE(image.empty()) << source.substr(0, 80);
    EXPECT_EQ(image.type(), CV_8UC3);
  }
  // The comparison, a section per material, a polar plot per row, the CSV material's note.
  EXPECT_NE(html.find("<table class=\"summary\">"), std::string::npos);
  for (const char* material : {"brushed", "plastic", "samples"})
    EXPECT_NE(html.find(std::string("id=\"m-") + material + "\""), std::string::npos) << material;
  EXPECT_NE(html.find("No measured pictures:"), std::string::npos);
  EXPECT_NE(html.find("samples.csv: a CSV of samples is not a table"), std::string::npos);
  // A polar plot and a slice with axes per row.
  const auto count = [&html](const std::string& what) {
    size_t n = 0;
    for (size_t at = html.find(what); at != std::string::npos; at = html.find(what, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("class=\"polar\""), 2u * 4 + 3);
  EXPECT_EQ(count("<div class=\"axes\">"), 2u * 4 + 3);
  EXPECT_EQ(count(">θh °</text>"), 2u * 4 + 3);
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
