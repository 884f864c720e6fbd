// `brdffit capture`: image sequences through cv::VideoCapture, one exposure decoded as sRGB, several
// merged into a radiance map (Debevec) that is proportional to the scene's radiance.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <vector>

#include "brdffit/error.h"
#include "brdffit/imaging/capture.h"
#include "brdffit/imaging/image_io.h"
#include "test_util.h"

namespace brdffit {
namespace {

namespace fs = std::filesystem;

// A scene spanning three decades of radiance left to right, tinted, dimmer towards the top.
cv::Mat scene_radiance() {
  cv::Mat radiance(48, 96, CV_32FC3);
  for (int y = 0; y < radiance.rows; ++y)
    for (int x = 0; x < radiance.cols; ++x) {
      const float r = std::pow(10.0f, 3.0f * x / (radiance.cols - 1) - 2.0f) * (0.4f + 0.6f * y / (radiance.rows - 1));
      radiance.at<cv::Vec3f>(y, x) = cv::Vec3f(r, 0.7f * r, 0.45f * r);
    }
  return radiance;
}

// Writes frame_00.png, frame_01.png, ...: the radiance times each exposure time, through the sRGB
// curve into 8 bits (a camera whose response is sRGB), with a little sensor noise.
void write_exposures(const std::string& dir, const cv::Mat& radiance, const std::vector<double>& times) {
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(0.0f, 0.002f);
  for (size_t k = 0; k < times.size(); ++k) {
    cv::Mat exposed = radiance * times[k];
    for (auto it = exposed.begin<cv::Vec3f>(); it != exposed.end<cv::Vec3f>(); ++it)
      for (int c = 0; c < 3; ++c) (*it)[c] = std::max(0.0f, (*it)[c] * (1.0f + noise(rng)));
    write_image(fmt::format("{}/frame_{:02d}.png", dir, k), exposed, Encoding::Srgb8);
  }
}

TEST(Capture, OneExposureIsDecodedFromSrgb) {
  const std::string dir = test::fresh_dir("capture-single");
  cv::Mat grey(8, 8, CV_32FC3, cv::Scalar::all(0.2));
  grey.at<cv::Vec3f>(0, 0) = cv::Vec3f(0.5f, 0.05f, 1.0f);
  write_image(dir + "/frame_00.png", grey, Encoding::Srgb8);
  const CaptureResult result = capture({dir + "/frame_%02d.png", {}, 1});
  EXPECT_EQ(result.frames, 1);
  EXPECT_TRUE(result.response.empty());
  // 8-bit quantisation of the sRGB codes: within half a code's step in linear terms.
  EXPECT_NEAR(result.image.at<cv::Vec3f>(3, 3)[1], 0.2, 0.002);
  EXPECT_NEAR(result.image.at<cv::Vec3f>(0, 0)[0], 0.5, 0.003);
  EXPECT_NEAR(result.image.at<cv::Vec3f>(0, 0)[1], 0.05, 0.001);
  EXPECT_NEAR(result.image.at<cv::Vec3f>(0, 0)[2], 1.0, 1e-6);
}

TEST(Capture, SeveralExposuresMergeIntoRadianceProportionalToTheScene) {
  const std::string dir = test::fresh_dir("capture-bracket");
  const cv::Mat radiance = scene_radiance();
  const std::vector<double> times = {1.0 / 64, 1.0 / 16, 1.0 / 4, 1.0, 4.0, 16.0, 64.0};
  write_exposures(dir, radiance, times);
  const CaptureResult result = capture({dir + "/frame_%02d.png", times, 1});
  EXPECT_EQ(result.frames, static_cast<int>(times.size()));
  ASSERT_EQ(result.response.rows, 256);

  // Debevec recovers radiance up to one scale: the ratio to the truth is the same everywhere.
  std::vector<float> ratios;
  for (int y = 0; y < radiance.rows; ++y)
    for (int x = 0; x < radiance.cols; ++x)
      for (int c = 0; c < 3; ++c)
        ratios.push_back(result.image.at<cv::Vec3f>(y, x)[c] / radiance.at<cv::Vec3f>(y, x)[c]);
  std::sort(ratios.begin(), ratios.end());
  const float median = ratios[ratios.size() / 2];
  ASSERT_GT(median, 0.0f);
  const float p05 = ratios[ratios.size() / 20] / median, p95 = ratios[ratios.size() * 19 / 20] / median;
  EXPECT_GT(p05, 0.8f) << "5th percentile of merged/true, relative to the median";
  EXPECT_LT(p95, 1.25f) << "95th percentile of merged/true, relative to the median";
}

TEST(CaptureCli, WritesTheMergedExrAndTheResponse) {
  const std::string dir = test::fresh_dir("capture-cli");
  write_exposures(dir, scene_radiance(), {0.05, 0.5, 5.0});
  const auto r = test::run_cli("capture " + dir + "/frame_%02d.png --exposures 0.05,0.5,5 --out " + dir +
                               "/merged.exr --response " + dir + "/response.csv");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("3 frames, 3 exposures merged (Debevec)"), std::string::npos) << r.output;
  const cv::Mat merged = read_image(dir + "/merged.exr");
  EXPECT_EQ(merged.size(), cv::Size(96, 48));
  // Brighter to the right, over about three decades.
  const float left = merged.at<cv::Vec3f>(40, 2)[0], right = merged.at<cv::Vec3f>(40, 93)[0];
  EXPECT_GT(right / left, 300.0f);
  EXPECT_LT(right / left, 3000.0f);
  const std::string response = test::run_command("wc -l < " + dir + "/response.csv").output;
  EXPECT_EQ(std::stoi(response), 257);  // header and 256 codes
}

TEST(CaptureCli, BadSourcesAreClearErrors) {
  const std::string dir = test::fresh_dir("capture-bad");
  write_exposures(dir, scene_radiance(), {0.5, 5.0});
  test::expect_cli_errors(
      {{"capture " + dir + "/nothing_%02d.png --out " + dir + "/x.exr",
        "nothing_%02d.png: no frame of this image sequence exists"},
       {"capture " + dir + "/frame_%02d.png --exposures 0.5,5,50 --out " + dir + "/x.exr", "ran out of frames after 2"},
       {"capture " + dir + "/frame_%02d.png --exposures 0.5,-5 --out " + dir + "/x.exr", "must be positive"}},
      dir + "/x.exr");
}

}  // namespace
}  // namespace brdffit
