// Photographed spheres: image files, sphere location, lights (files and chrome ball), pixel
// rules, pipeline errors and the sphere command (recovery from photographs: test_sphere_recovery.cc).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "brdffit/error.h"
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

using test::expect_error;

// ---------------------------------------------------------------------------------------------
// Image files

TEST(ImageIo, RoundTripsEveryEncoding) {
  const std::string dir = test::fresh_dir("sphere-io");
  cv::Mat ramp(8, 64, CV_32FC3);
  for (int x = 0; x < ramp.cols; ++x)
    for (int y = 0; y < ramp.rows; ++y) ramp.at<cv::Vec3f>(y, x) = cv::Vec3f(x / 63.0f, 0.5f * x / 63.0f, 0.25f);
  struct Case {
    const char* name;
    Encoding encoding;
    double tolerance;
  };
  for (const Case& c : {Case{"a.exr", Encoding::Auto, 0.0}, Case{"b.png", Encoding::Linear16, 1.0 / 65535},
                        Case{"c.png", Encoding::Auto, 0.01}, Case{"d.tif", Encoding::Float, 0.0},
                        Case{"e.jpg", Encoding::Srgb8, 0.06}}) {
    SCOPED_TRACE(c.name);
    const std::string path = dir + "/" + c.name;
    write_image(path, ramp, c.encoding);
    const cv::Mat back = read_image(path);
    ASSERT_EQ(back.size(), ramp.size());
    EXPECT_LE(cv::norm(back, ramp, cv::NORM_INF), c.tolerance + 1e-6);
  }
  // 8-bit files are sRGB unless told otherwise.
  EXPECT_EQ(read_image_info(dir + "/c.png").bits, 8);
  const cv::Mat codes = read_image(dir + "/c.png", Decoding{Transfer::Linear});
  // The stored code of 32/63: the sRGB curve 1.055·x^(1/2.4) − 0.055 (IEC 61966-2-1) gives
  // 0.74058, code 189 (a gamma-2.2 encoding would give 0.73500, code 187).
  const double srgb = 1.055 * std::pow(32.0 / 63.0, 1 / 2.4) - 0.055;
  ASSERT_EQ(std::lround(255 * srgb), 189);
  EXPECT_NEAR(codes.at<cv::Vec3f>(0, 32)[0], 189.0 / 255.0, 1e-6);
  const cv::Mat gamma = read_image(dir + "/c.png", parse_gamma("2.2"));
  EXPECT_NEAR(gamma.at<cv::Vec3f>(0, 32)[0], std::pow(codes.at<cv::Vec3f>(0, 32)[0], 2.2), 1e-4);
  // Nothing but the written files is left behind.
  for (const auto& entry : fs::directory_iterator(dir)) EXPECT_NE(entry.path().filename().string()[0], '.');
}

TEST(ImageIo, BadFilesAreClearErrors) {
  const std::string dir = test::fresh_dir("sphere-io-bad");
  expect_error([&] { read_image(dir + "/missing.png"); }, {"missing.png", "no such file"});
  write_file_atomic(dir + "/text.png", "not an image");
  expect_error([&] { read_image(dir + "/text.png"); }, {"text.png", "cannot read image"});
  cv::Mat with_nan(4, 4, CV_32FC3, cv::Scalar::all(0.5));
  with_nan.at<cv::Vec3f>(2, 2)[1] = NAN;
  write_image(dir + "/nan.exr", with_nan);
  expect_error([&] { read_image(dir + "/nan.exr"); }, {"nan.exr", "NaN"});
  expect_error([] { parse_gamma("-1"); }, {"--gamma", "-1"});
  // A failed write leaves the previous file as it was.
  const cv::Mat grey(4, 4, CV_32FC3, cv::Scalar::all(0.5));
  write_image(dir + "/keep.png", grey);
  const std::string before = read_file(dir + "/keep.png");
  expect_error([&] { write_image(dir + "/keep.png", cv::Mat(4, 4, CV_8UC3)); }, {"keep.png"});
  expect_error([&] { write_image(dir + "/no/such/folder/x.png", grey); }, {"x.png", "cannot write"});
  EXPECT_EQ(read_file(dir + "/keep.png"), before);
}

// ---------------------------------------------------------------------------------------------
// Geometry

TEST(SphereGeometry, OrthographicAndPerspectiveNormals) {
  const SphereView ortho(Circle{50.0, 40.0, 20.0}, Camera{});
  Vec3 n, v;
  ASSERT_TRUE(ortho.surface_at(50.0, 40.0, n, v));
  EXPECT_NEAR((n - Vec3(0, 0, 1)).norm(), 0.0, 1e-12);
  ASSERT_TRUE(ortho.surface_at(60.0, 30.0, n, v));  // right and up of the centre
  EXPECT_NEAR(n.x(), 0.5, 1e-12);
  EXPECT_NEAR(n.y(), 0.5, 1e-12);
  EXPECT_FALSE(ortho.surface_at(70.5, 40.0, n, v));

  // Perspective: every normal is unit and faces the camera.
  const Camera camera = Camera::centred(400.0, cv::Size(321, 241));
  const SphereView persp(Circle{220.0, 90.0, 40.0}, camera);
  ASSERT_TRUE(persp.surface_at(220.0, 90.0, n, v));
  EXPECT_NEAR(n.norm(), 1.0, 1e-12);
  EXPECT_NEAR(v.norm(), 1.0, 1e-12);
  EXPECT_GT(n.dot(v), 0.99);
  // The outline is the circle of the silhouette's centre and area (what circle_from_mask measures
  // of a mask): integrated on a 0.1-pixel grid, the silhouette has the outline's area and centroid.
  double area = 0.0, sum_x = 0.0, sum_y = 0.0;
  const double step = 0.1;
  for (double y = 30.0; y < 150.0; y += step)
    for (double x = 160.0; x < 280.0; x += step)
      if (persp.surface_at(x, y, n, v)) area += step * step, sum_x += x * step * step, sum_y += y * step * step;
  EXPECT_NEAR(area, kPi * 40.0 * 40.0, 0.002 * kPi * 40.0 * 40.0);
  EXPECT_NEAR(sum_x / area, 220.0, 0.05);
  EXPECT_NEAR(sum_y / area, 90.0, 0.05);
  // 10° off the axis it is an ellipse, longer along the line from the principal point than across
  // it, and at its edge the view grazes the sphere.
  const Eigen::Vector2d radial = Eigen::Vector2d(220.0 - 160.0, 90.0 - 120.0).normalized();
  auto edge = [&](const Eigen::Vector2d& direction) {  // distance from the centre to the silhouette's edge
    double inside = 0.0, outside = 80.0;
    for (int i = 0; i < 50; ++i) {
      const double t = 0.5 * (inside + outside);
      (persp.surface_at(220.0 + t * direction.x(), 90.0 + t * direction.y(), n, v) ? inside : outside) = t;
    }
    EXPECT_TRUE(
        persp.surface_at(220.0 + (inside - 0.01) * direction.x(), 90.0 + (inside - 0.01) * direction.y(), n, v));
    EXPECT_LT(n.dot(v), 0.1);
    return inside;
  };
  const double along = edge(radial) + edge(-radial), across = edge(Eigen::Vector2d(-radial.y(), radial.x())) * 2;
  EXPECT_GT(along, 80.5);
  EXPECT_LT(across, 79.5);
}

TEST(SphereGeometry, NormalMapCheckMeasuresHowFarTheSphereIsOff) {
  const std::string dir = test::fresh_dir("sphere-normals");
  const SphereView truth(Circle{40.3, 35.7, 25.2}, Camera{});
  cv::Mat encoded(72, 80, CV_32FC3, cv::Scalar::all(0.0));  // background: zeros, no normal
  for (int y = 0; y < encoded.rows; ++y)
    for (int x = 0; x < encoded.cols; ++x) {
      Vec3 n, v;
      if (truth.surface_at(x, y, n, v))
        encoded.at<cv::Vec3f>(y, x) = cv::Vec3f(0.5 * (n.x() + 1.0), 0.5 * (n.y() + 1.0), 0.5 * (n.z() + 1.0));
    }
  write_image(dir + "/normals.png", encoded, Encoding::Linear16);
  const NormalCheck exact = check_normals(truth, dir + "/normals.png", encoded.size(), cv::Mat());
  EXPECT_LT(exact.median_deg, 0.01);
  EXPECT_GT(exact.pixels, 1900u);  // π·25.2² ≈ 1995 pixels
  // A sphere found 2 pixels too far right: the normals tilt by asin(2/25.2) ≈ 4.6° at the centre.
  const NormalCheck shifted =
      check_normals(SphereView(Circle{42.3, 35.7, 25.2}, Camera{}), dir + "/normals.png", encoded.size(), cv::Mat());
  EXPECT_GT(shifted.median_deg, 3.0);
  expect_error([&] { check_normals(truth, dir + "/normals.png", cv::Size(81, 72), cv::Mat()); },
               {"normals.png", "80x72 pixels, the photographs 81x72"});
}

TEST(SphereGeometry, LocalFrameIsOrthonormalWithTheNormalUp) {
  std::mt19937_64 rng(3);
  for (int i = 0; i < 100; ++i) {
    const Vec3 n = test::random_upper_direction(rng, 0.0);
    const LocalFrame frame(n);
    EXPECT_NEAR((frame.to_local(n) - Vec3(0, 0, 1)).norm(), 0.0, 1e-12);
    EXPECT_NEAR(frame.tangent.cross(frame.bitangent).dot(n), 1.0, 1e-12);
    const Vec3 d = test::random_upper_direction(rng, 0.0);
    EXPECT_NEAR(frame.to_local(d).norm(), 1.0, 1e-12);
    EXPECT_NEAR(frame.to_local(d).z(), n.dot(d), 1e-12);
    // The tangent runs along the longitude (horizontal), the bitangent upward.
    EXPECT_NEAR(frame.tangent.y(), 0.0, 1e-12);
    EXPECT_GT(frame.bitangent.y(), 0.0);
  }
  // At the sphere's centre the frame is the camera's: x right, y up; at a normal to the right
  // (1, 0, 1)/√2 the tangent leans away from the camera, (1, 0, -1)/√2, as a UV sphere's u.
  const LocalFrame centre(Vec3(0, 0, 1));
  EXPECT_NEAR((centre.tangent - Vec3(1, 0, 0)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((centre.bitangent - Vec3(0, 1, 0)).norm(), 0.0, 1e-15);
  const LocalFrame right(Vec3(1, 0, 1).normalized());
  EXPECT_NEAR((right.tangent - Vec3(1, 0, -1).normalized()).norm(), 0.0, 1e-15);
}

TEST(SphereGeometry, PixelRulesInOrder) {
  const PixelRules rules;
  const Vec3 up(0, 0, 1);
  const cv::Vec3f mid(0.3f, 0.3f, 0.3f);
  EXPECT_EQ(classify_pixel(up, up, test::dir(1, 0, -0.1), mid, 1.0, true, rules), PixelFate::Shadow);
  EXPECT_EQ(classify_pixel(up, up, test::dir(1, 0, 0.1), mid, 1.0, true, rules), PixelFate::Grazing);
  EXPECT_EQ(classify_pixel(up, test::dir(1, 0, 0.1), up, mid, 1.0, true, rules), PixelFate::Grazing);
  EXPECT_EQ(classify_pixel(up, up, up, cv::Vec3f(0.99f, 0.2f, 0.2f), 1.0, true, rules), PixelFate::Saturated);
  EXPECT_EQ(classify_pixel(up, up, up, cv::Vec3f(0.99f, 0.2f, 0.2f), 1.0, false, rules), PixelFate::Used);
  EXPECT_EQ(classify_pixel(up, up, up, cv::Vec3f(0.001f, 0.001f, 0.0f), 1.0, true, rules), PixelFate::Dark);
  EXPECT_EQ(classify_pixel(up, up, up, cv::Vec3f(0.001f, 0.001f, 0.0f), 0.01, false, rules), PixelFate::Used);
  EXPECT_EQ(classify_pixel(up, up, up, mid, 1.0, true, rules), PixelFate::Used);
}

// ---------------------------------------------------------------------------------------------
// Locating the sphere

TEST(SphereLocation, MaskAndDetectionFindTheRenderedSphere) {
  const std::string dir = test::fresh_dir("sphere-locate");
  const test::SphereScene scene =
      test::write_sphere_scene(dir, "s", test::ggx(), test::ggx_truth(), test::dome_lights(6));
  const Circle truth = scene.outline;
  const Circle from_mask = circle_from_mask(read_mask(scene.mask), scene.mask);
  EXPECT_NEAR(from_mask.x, truth.x, 0.05);
  EXPECT_NEAR(from_mask.y, truth.y, 0.05);
  EXPECT_NEAR(from_mask.radius, truth.radius, 0.05);
  const Circle detected = detect_sphere(brightest_of(scene.images, {}), "scene");
  EXPECT_NEAR(detected.x, truth.x, 0.25);
  EXPECT_NEAR(detected.y, truth.y, 0.25);
  EXPECT_NEAR(detected.radius, truth.radius, 0.25);
  // One photograph, lit from the side: only half the silhouette shows, still enough.
  const Circle half_lit = detect_sphere(read_image(scene.images.back()), scene.images.back());
  EXPECT_NEAR(half_lit.x, truth.x, 0.5);
  EXPECT_NEAR(half_lit.y, truth.y, 0.5);
  EXPECT_NEAR(half_lit.radius, truth.radius, 0.5);
}

TEST(SphereLocation, NoSphereIsAClearErrorNamingTheFile) {
  const std::string dir = test::fresh_dir("sphere-nosphere");
  cv::Mat noise(200, 240, CV_32FC3);
  cv::RNG(5).fill(noise, cv::RNG::UNIFORM, 0.0, 1.0);
  write_image(dir + "/noise.png", noise);
  write_image(dir + "/black.png", cv::Mat(200, 240, CV_32FC3, cv::Scalar::all(0.0)));
  cv::Mat square(200, 240, CV_32FC3, cv::Scalar::all(0.0));
  cv::rectangle(square, cv::Rect(60, 50, 100, 100), cv::Scalar::all(0.8), cv::FILLED);
  write_image(dir + "/square.png", square);
  for (const char* name : {"noise.png", "black.png", "square.png"}) {
    const std::string path = dir + "/" + name;
    expect_error([&] { detect_sphere(read_image(path), path); }, {path, "no sphere found"});
  }
  expect_error([&] { circle_from_mask(read_mask(dir + "/square.png"), "square mask"); },
               {"square mask", "not one disc"});
  expect_error([&] { circle_from_mask(read_mask(dir + "/black.png"), "black mask"); }, {"black mask", "empty"});
}

// ---------------------------------------------------------------------------------------------
// Lights

TEST(SphereLights, FilesAreCheckedLineByLine) {
  const std::string dir = test::fresh_dir("sphere-lights");
  write_file_atomic(dir + "/ok.txt", "# x y z\n0 0 2\n0.5, 0, 0.5\n\n");
  const std::vector<Vec3> lights = read_light_directions(dir + "/ok.txt", 2);
  EXPECT_NEAR((lights[0] - Vec3(0, 0, 1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((lights[1] - test::dir(1, 0, 1)).norm(), 0.0, 1e-12);
  expect_error([&] { read_light_directions(dir + "/ok.txt", 3); }, {"ok.txt", "2 light directions for 3 images"});
  write_file_atomic(dir + "/short.txt", "0 0 1\n0 1\n");
  expect_error([&] { read_light_directions(dir + "/short.txt", 2); }, {"short.txt:2", "expected 3 numbers"});
  write_file_atomic(dir + "/word.txt", "0 0 one\n");
  expect_error([&] { read_light_directions(dir + "/word.txt", 1); }, {"word.txt:1", "'one'"});
  write_file_atomic(dir + "/zero.txt", "0 0 0\n");
  expect_error([&] { read_light_directions(dir + "/zero.txt", 1); }, {"zero.txt", "zero"});
  write_file_atomic(dir + "/dim.txt", "1 1 0\n");
  expect_error([&] { read_light_intensities(dir + "/dim.txt", 1); }, {"dim.txt", "not positive"});
  expect_error([&] { read_light_directions(dir + "/absent.txt", 1); }, {"absent.txt", "cannot open"});
}

TEST(SphereLights, ChromeBallGivesTheLightsWithinOneDegree) {
  const std::string dir = test::fresh_dir("sphere-chrome");
  const std::vector<Vec3> lights = test::dome_lights(12, 60.0);
  for (Encoding encoding : {Encoding::Linear16, Encoding::Srgb8}) {
    const test::SphereScene scene = test::write_chrome_scene(dir, lights, encoding);
    const SphereView ball(circle_from_mask(read_mask(scene.mask), scene.mask), Camera{});
    double worst = 0.0;
    for (size_t i = 0; i < lights.size(); ++i)
      worst = std::max(
          worst, test::angle_deg(light_from_chrome(read_image(scene.images[i]), ball, scene.images[i]), lights[i]));
    EXPECT_LT(worst, 1.0);
    std::printf("chrome ball (%s, mask): worst light direction error %.3f deg over %zu lights\n",
                encoding == Encoding::Srgb8 ? "8-bit sRGB, clipped" : "16-bit linear, clipped", worst, lights.size());
  }
  const cv::Mat black(100, 100, CV_32FC3, cv::Scalar::all(0.0));
  expect_error(
      [&] {
        light_from_chrome(black, SphereView(Circle{50, 50, 30}, Camera{}), "black.png");
      },
      {"black.png", "no highlight"});
}

// ---------------------------------------------------------------------------------------------
// Pipeline errors

TEST(SpherePipeline, BadInputIsAClearErrorNamingTheFile) {
  const std::string dir = test::fresh_dir("sphere-pipeline-bad");
  const test::SphereScene scene =
      test::write_sphere_scene(dir, "g", test::ggx(), test::ggx_truth(), test::dome_lights(3));
  const auto input_with = [&](auto change) {
    SphereInput input;
    input.images = scene.images;
    input.lights = scene.lights;
    input.mask = scene.mask;
    change(input);
    return input;
  };
  expect_error([&] { observe_sphere(input_with([&](SphereInput& in) { in.images.push_back(dir + "/gone.png"); })); },
               {"gone.png", "no such file"});
  write_image(dir + "/small.png", cv::Mat(10, 10, CV_32FC3, cv::Scalar::all(0.1)));
  expect_error([&] { observe_sphere(input_with([&](SphereInput& in) { in.images[1] = dir + "/small.png"; })); },
               {"small.png", "10x10", "320x256"});
  expect_error([&] { observe_sphere(input_with([&](SphereInput& in) { in.images.pop_back(); })); },
               {scene.lights, "3 light directions for 2 images"});
  expect_error([&] { observe_sphere(input_with([&](SphereInput& in) { in.lights.clear(); })); },
               {"no light directions"});
  expect_error([&] { observe_sphere(input_with([&](SphereInput& in) { in.mask = dir + "/small.png"; })); },
               {"small.png", "10x10"});
  expect_error(
      [&] {
        observe_sphere(input_with([&](SphereInput& in) {
          in.chrome = {scene.images[0]};
          in.lights.clear();
        }));
      },
      {"1 chrome-ball photographs for 3 images"});
  // Every light behind the sphere: nothing usable.
  write_file_atomic(dir + "/behind.txt", "0 0 -1\n0 0 -1\n0 0 -1\n");
  expect_error([&] { observe_sphere(input_with([&](SphereInput& in) { in.lights = dir + "/behind.txt"; })); },
               {"no usable pixel", "in shadow"});
}

// ---------------------------------------------------------------------------------------------
// The sphere command

TEST(SphereCli, FitsWritesTheDocumentAndImages) {
  const std::string dir = test::fresh_dir("sphere-cli");
  const test::SphereScene scene =
      test::write_sphere_scene(dir, "g", test::ggx(), test::ggx_truth(), test::dome_lights(5));
  std::string images;
  for (const std::string& path : scene.images) images += " " + path;
  const auto r = test::run_cli("sphere" + images + " --lights " + scene.lights + " --intensities " + scene.intensities +
                               " --models lambert,ggx --out " + dir + "/r.json --images-out " + dir + "/panels");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("located by detection"), std::string::npos) << r.output;
  const nlohmann::json doc = nlohmann::json::parse(read_file(dir + "/r.json"));
  EXPECT_EQ(doc["schema"], 1);
  EXPECT_EQ(doc["input"]["path"], dir);
  EXPECT_EQ(doc["input"]["images"].size(), 5u);
  EXPECT_EQ(doc["weighting"], "pixel");
  EXPECT_EQ(doc["loss"], "huber");
  EXPECT_NEAR(doc["sphere"]["center"][0].get<double>(), scene.outline.x, 0.3);
  EXPECT_NEAR(doc["sphere"]["radius"].get<double>(), scene.outline.radius, 0.3);
  EXPECT_EQ(doc["sphere"]["camera"]["model"], "orthographic");
  EXPECT_GT(doc["pixels"]["used"].get<size_t>(), 10000u);
  for (const char* key : {"shadow", "grazing", "saturated", "dark", "on_sphere"})
    EXPECT_TRUE(doc["pixels"].contains(key)) << key;
  ASSERT_EQ(doc["lights"].size(), 5u);
  const std::vector<Vec3> lights = test::dome_lights(5);
  EXPECT_NEAR(doc["lights"][4][0].get<double>(), lights[4].x(), 1e-6);
  ASSERT_EQ(doc["images"].size(), 5u);
  EXPECT_LT(doc["images"][0]["relative_rms"]["ggx"].get<double>(), 0.03);
  ASSERT_EQ(doc["models"].size(), 2u);
  const nlohmann::json& fitted_ggx = doc["models"][1];
  EXPECT_EQ(fitted_ggx["model"], "ggx");
  EXPECT_NEAR(fitted_ggx["parameters"]["roughness"]["value"].get<double>(), 0.3, 0.01);
  EXPECT_LT(fitted_ggx["image_relative_rms"].get<double>(), 0.03);
  EXPECT_GT(doc["models"][0]["image_relative_rms"].get<double>(), fitted_ggx["image_relative_rms"].get<double>());
  // measured | fit | error, cropped to the sphere.
  const cv::Mat panel = read_image(dir + "/panels/ggx/001_g00.png");
  EXPECT_EQ(panel.cols % 3, 0);
  EXPECT_NEAR(panel.rows, 2 * scene.outline.radius + 5, 2);
  EXPECT_TRUE(fs::exists(dir + "/panels/lambert/005_g04.png"));
}

TEST(SphereCli, BadInputExitsNonZeroAndWritesNothing) {
  const std::string dir = test::fresh_dir("sphere-cli-bad");
  const test::SphereScene scene =
      test::write_sphere_scene(dir, "g", test::ggx(), test::ggx_truth(), test::dome_lights(2));
  cv::Mat noise(256, 320, CV_32FC3);
  cv::RNG(9).fill(noise, cv::RNG::UNIFORM, 0.0, 0.5);
  write_image(dir + "/noise.png", noise);
  write_file_atomic(dir + "/one.txt", "0 0 1\n");
  const std::string out = dir + "/never.json";
  const std::string both = scene.images[0] + " " + scene.images[1];
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"sphere " + dir + "/missing.png --lights " + dir + "/one.txt", "missing.png: no such file"},
      {"sphere " + dir + "/noise.png --lights " + dir + "/one.txt", "noise.png: no sphere found"},
      {"sphere " + both + " --lights " + dir + "/one.txt", "one.txt: 1 light direction for 2 images"},
      {"sphere " + both + " --lights " + scene.lights + " --models nosuch", "unknown model 'nosuch'"},
      {"sphere " + both + " --lights " + scene.lights + " --gamma abc", "--gamma"},
      {"sphere " + both, "no light directions"},
      {"sphere " + dir + " --lights " + scene.lights, "DiLiGenT object folder"},
  };
  for (const auto& [args, message] : cases) {
    SCOPED_TRACE(args);
    const auto r = test::run_cli(args + " --out " + out);
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
  }
}

}  // namespace
}  // namespace brdffit
