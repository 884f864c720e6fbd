// report: a page built from a real batch (two baked MERL tables and a CSV of samples), every
// image a valid PNG, and Debian's headless Chromium loading it without a missing image.
#include <gtest/gtest.h>

#include <openssl/evp.h>
#include <cstdio>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "batch_test_util.h"
#include "brdffit/imaging/image_io.h"
#include "brdffit/imaging/render.h"
#include "brdffit/merl.h"
#include "brdffit/registry.h"
#include "sphere_scenes.h"

namespace brdffit {

namespace fs = std::filesystem;
namespace {

class Report : public ::testing::Test {
 protected:
  // One batch and one page for every test here (ctest runs each test on its own, so each pays
  // for them: small pictures keep that to seconds).
  static void SetUpTestSuite() {
    dir_ = test::fresh_dir("report");
    fs::create_directories(dir_ + "/tables");
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
std::vector<ImageTag> image_tags(const std::string& html, size_t from = 0) {
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

std::vector<std::string> image_sources(const std::string& html) {
  std::vector<std::string> sources;
  for (const ImageTag& tag : image_tags(html)) sources.push_back(tag.src);
  return sources;
}

cv::Mat decode_png_data_uri(const std::string& uri) {
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

TEST_F(Report, EveryImageIsAnEmbeddedPng) {
  ASSERT_EQ(batch_.exit_code, 0) << batch_.output;
  ASSERT_EQ(report_.exit_code, 0) << report_.output;
  const std::string html = page();
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);  // nothing from elsewhere
  EXPECT_EQ(html.find("href=\"http"), std::string::npos);
  const std::vector<std::string> sources = image_sources(html);
  // Per table: the measured sphere, environment sphere and slice, and per model those three and
  // the absolute and signed relative error of sphere and slice; per CSV material (no measured
  // pictures): each model's three; per table three colour bars (|error| twice, relative once).
  EXPECT_EQ(sources.size(), 2 * (3 + 3 * 7) + 3 * 3 + 2 * 3);
  for (const std::string& source : sources) {
    const cv::Mat image = decode_png_data_uri(source);
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

// The picture with this alt text in the section of this material (anywhere for "").
cv::Mat picture(const std::string& html, const std::string& material, const std::string& alt) {
  const size_t section = material.empty() ? 0 : html.find("id=\"m-" + material + "\"");
  if (section == std::string::npos) return cv::Mat();
  for (const ImageTag& tag : image_tags(html, section))
    if (tag.alt == alt) return decode_png_data_uri(tag.src);
  return cv::Mat();
}

// ‖a − b‖₁ / ‖a‖₁ of two decoded pictures.
double relative_l1(const cv::Mat& a, const cv::Mat& b) {
  return cv::norm(a, b, cv::NORM_L1) / cv::norm(a, cv::NORM_L1);
}

TEST_F(Report, TheMeasuredPicturesAndTheBestFitsLookAlike) {
  // On the ggx-baked table ggx ranks first, and its pictures match the measured ones.
  const std::string html = page();
  for (const std::string picture_name : {"sphere", "slice", "environment"}) {
    const cv::Mat measured = picture(html, "plastic", "measured " + picture_name),
                  fitted = picture(html, "plastic", "1. ggx " + picture_name);
    ASSERT_FALSE(measured.empty()) << picture_name;
    ASSERT_FALSE(fitted.empty()) << picture_name;
    EXPECT_LT(relative_l1(measured, fitted), 0.03) << picture_name;
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
    const cv::Mat error = picture(html, "plastic", std::string(row) + " sphere error");
    ASSERT_FALSE(error.empty()) << row;
    EXPECT_LE(saturated_fraction(error), 0.012) << row;
  }
  // The signed relative error of the exact fit is near zero: nearly white (within ±5 % of the
  // measured value shows as codes above 235 in every channel) on most of the sphere.
  const cv::Mat relative = picture(html, "plastic", "1. ggx sphere relative error");
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
  const cv::Mat lambert = picture(html, "plastic", "3. lambert slice error");
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
    const cv::Mat photo = picture(html, "", "photograph " + path);
    const cv::Mat model = picture(html, "", "ggx under the light of " + path);
    ASSERT_FALSE(photo.empty());
    ASSERT_FALSE(model.empty());
    EXPECT_EQ(photo.size(), model.size());
    EXPECT_LT(relative_l1(photo, model), 0.05);
  }
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
  EXPECT_EQ(total, image_sources(page()).size());
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

}  // namespace
}  // namespace brdffit
