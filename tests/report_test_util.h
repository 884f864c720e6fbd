// The report tests' page (one batch of two baked MERL tables and a CSV of samples, reported
// once per test suite) and the reading of its pictures: test_report.cc, test_report_pictures.cc.
#pragma once

#include <gtest/gtest.h>
#include <openssl/evp.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "batch_test_util.h"
#include "brdffit/io.h"
#include "brdffit/merl.h"
#include "brdffit/registry.h"

namespace brdffit::test {

class ReportPage : public ::testing::Test {
 protected:
  // One batch and one page for every test here (ctest runs each test on its own, so each pays
  // for them: small pictures keep that to seconds).
  static void SetUpTestSuite() {
    dir_ = test::fresh_dir("report");
    std::filesystem::create_directories(dir_ + "/tables");
    bake(dir_ + "/tables/plastic.binary", "ggx", {"albedo=0.25,0.1,0.05", "roughness=0.3", "f0=0.04"});
    bake(dir_ + "/tables/brushed.binary", "ward", {"albedo=0.05", "specular=0.3,0.25,0.1", "alpha=0.15"});
    test::write_model_csv(dir_ + "/tables/samples.csv", "lambert", {"albedo=0.4,0.4,0.2"});
    batch_ = test::run_cli("batch " + dir_ + "/tables --models ggx,lambert,ward --max-samples 20000 --out " + dir_ +
                           "/fits");
    report_ = test::run_cli("report " + dir_ + "/fits --size 64 --out " + dir_ + "/report.html");
  }

  static void bake(const std::string& path, const std::string& model_name,
                   const std::vector<std::string>& assignments) {
    const Model& model = *find_model(model_name);
    const std::vector<double> values = parameter_values(model, assignments);
    write_merl(path, [&](const Vec3& l, const Vec3& v) { return *model.brdf(values.data(), l, v); });
  }

  static std::string page() { return read_file(dir_ + "/report.html"); }

  static inline std::string dir_;
  static inline test::CommandResult batch_, report_;
};

// The src of every <img> from `from` on, with its alt text. Plain scanning: libstdc++'s regex
// recurses once per character and overflows the stack on data URIs of a few hundred kilobytes.
struct ImageTag {
  std::string src, alt;
};
inline std::vector<ImageTag> image_tags(const std::string& html, size_t from = 0) {
  std::vector<ImageTag> tags;
  const std::string open = "<img src=\"";
  for (size_t at = html.find(open, from); at != std::string::npos; at = html.find(open, at + 1)) {
    const size_t src_begin = at + open.size(), src_end = html.find('"', src_begin);
    if (src_end == std::string::npos) break;
    ImageTag tag{html.substr(src_begin, src_end - src_begin), ""};
    const std::string alt = " alt=\"";
    if (html.compare(src_end + 1, alt.size(), alt) == 0) {
      const size_t alt_begin = src_end + 1 + alt.size();
      tag.alt = html.substr(alt_begin, html.find('"', alt_begin) - alt_begin);
    }
    tags.push_back(tag);
  }
  return tags;
}

inline std::vector<std::string> image_sources(const std::string& html) {
  std::vector<std::string> sources;
  for (const ImageTag& tag : image_tags(html)) sources.push_back(tag.src);
  return sources;
}

inline cv::Mat decode_png_data_uri(const std::string& uri) {
  const std::string prefix = "data:image/png;base64,";
  if (uri.rfind(prefix, 0) != 0) return cv::Mat();
  const std::string base64 = uri.substr(prefix.size());
  std::vector<unsigned char> bytes(base64.size());
  const int n = EVP_DecodeBlock(bytes.data(), reinterpret_cast<const unsigned char*>(base64.data()),
                                static_cast<int>(base64.size()));
  if (n < 0) return cv::Mat();
  bytes.resize(static_cast<size_t>(n));  // EVP_DecodeBlock counts the padding: PNG ignores trailing bytes
  return cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
}

// The picture with this alt text in the section of this material (anywhere for "").
inline cv::Mat picture(const std::string& html, const std::string& material, const std::string& alt) {
  const size_t section = material.empty() ? 0 : html.find("id=\"m-" + material + "\"");
  if (section == std::string::npos) return cv::Mat();
  for (const ImageTag& tag : image_tags(html, section))
    if (tag.alt == alt) return decode_png_data_uri(tag.src);
  return cv::Mat();
}

// Every <img> of a report page is a PNG embedded as a data URI that decodes to 8-bit RGB, and
// the page loads nothing from elsewhere; `count` images in all.
inline void expect_embedded_pngs(const std::string& html, size_t count) {
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("href=\"http"), std::string::npos);
  const std::vector<std::string> sources = image_sources(html);
  EXPECT_EQ(sources.size(), count);
  for (const std::string& source : sources) {
    const cv::Mat image = decode_png_data_uri(source);
    ASSERT_FALSE(image.empty()) << source.substr(0, 80);
    EXPECT_EQ(image.type(), CV_8UC3);
  }
}

// How many times `what` occurs in `html`.
inline size_t occurrences(const std::string& html, const std::string& what) {
  size_t n = 0;
  for (size_t at = html.find(what); at != std::string::npos; at = html.find(what, at + 1)) ++n;
  return n;
}

// ‖a − b‖₁ / ‖a‖₁ of two decoded pictures.
inline double relative_l1(const cv::Mat& a, const cv::Mat& b) {
  return cv::norm(a, b, cv::NORM_L1) / cv::norm(a, cv::NORM_L1);
}

}  // namespace brdffit::test
