// Synthetic photographs of spheres rendered by brdffit with known parameters and lights, for
// the sphere tests and bench/bench_sphere.
#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "brdffit/imaging/image_io.h"
#include "brdffit/imaging/sphere.h"
#include "brdffit/io.h"
#include "brdffit/registry.h"

namespace brdffit::test {

// The sphere tests' material: GGX with a coloured albedo and F0.
inline const Model& ggx() { return *find_model("ggx"); }
inline std::vector<double> ggx_truth() {
  return parameter_values(ggx(), {"albedo=0.5,0.35,0.2", "roughness=0.3", "f0=0.04,0.05,0.06"});
}

// `count` light directions around the view direction, at polar angles up to max_angle_deg,
// spread in azimuth (a golden-angle spiral) like a photometric-stereo dome.
inline std::vector<Vec3> dome_lights(int count, double max_angle_deg = 50.0) {
  std::vector<Vec3> lights;
  for (int i = 0; i < count; ++i) {
    const double polar = max_angle_deg * kPi / 180.0 * std::sqrt((i + 0.5) / count);
    const double azimuth = i * 2.39996322972865332;
    lights.emplace_back(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth), std::cos(polar));
  }
  return lights;
}

struct SphereScene {
  std::vector<std::string> images;
  std::string lights;       // light directions file
  std::string intensities;  // light intensities file
  std::string mask;         // the sphere's silhouette
  Circle outline;
};

struct SceneOptions {
  cv::Size size{320, 256};
  Circle outline{157.3, 121.8, 96.4};  // deliberately off-centre and not on whole pixels
  Encoding encoding = Encoding::Linear16;
  std::string extension = ".png";
  double noise = 0.01;         // Gaussian, relative to each value
  double noise_floor = 0.001;  // Gaussian, absolute
  double background = 0.0;
  std::vector<Rgb<double>> intensities;  // per light; empty: all 1
  uint64_t seed = 7;
};

// Renders the model on the sphere under each light (times its intensity), adds noise and writes
// dir/<prefix>NN<extension>, the lights and intensities files and a mask.
inline SphereScene write_sphere_scene(const std::string& dir, const std::string& prefix, const Model& model,
                                      const std::vector<double>& values, const std::vector<Vec3>& lights,
                                      const SceneOptions& options = {}) {
  std::filesystem::create_directories(dir);
  SphereScene scene;
  scene.outline = options.outline;
  const SphereView sphere(options.outline, Camera{});
  cv::RNG rng(options.seed);
  std::string light_lines, intensity_lines;
  for (size_t i = 0; i < lights.size(); ++i) {
    const Rgb<double> intensity = options.intensities.empty() ? Rgb<double>::Ones() : options.intensities[i];
    cv::Mat image = render_sphere(model, values, sphere, lights[i], options.size);
    cv::multiply(image, cv::Scalar(intensity[0], intensity[1], intensity[2]), image);
    image += cv::Scalar::all(options.background);
    cv::Mat relative(image.size(), CV_32FC3), absolute(image.size(), CV_32FC3);
    rng.fill(relative, cv::RNG::NORMAL, 0.0, options.noise);
    rng.fill(absolute, cv::RNG::NORMAL, 0.0, options.noise_floor);
    image += image.mul(relative) + absolute;
    const std::string path = dir + "/" + prefix + cv::format("%02d", static_cast<int>(i)) + options.extension;
    write_image(path, image, options.encoding);
    scene.images.push_back(path);
    light_lines += cv::format("%.9f %.9f %.9f\n", lights[i].x(), lights[i].y(), lights[i].z());
    intensity_lines += cv::format("%.9f %.9f %.9f\n", intensity[0], intensity[1], intensity[2]);
  }
  scene.lights = dir + "/" + prefix + "lights.txt";
  scene.intensities = dir + "/" + prefix + "intensities.txt";
  write_file_atomic(scene.lights, light_lines);
  write_file_atomic(scene.intensities, intensity_lines);

  cv::Mat mask;
  cv::cvtColor(sphere_pixels(sphere, options.size), mask, cv::COLOR_GRAY2RGB);
  mask.convertTo(mask, CV_32FC3, 1.0 / 255.0);
  scene.mask = dir + "/" + prefix + "mask.png";
  write_image(scene.mask, mask);
  return scene;
}

// A chrome ball (a sharp GGX lobe over a little diffuse, so its silhouette shows) under the lights.
inline SphereScene write_chrome_scene(const std::string& dir, const std::vector<Vec3>& lights, Encoding encoding) {
  const Model& ggx = *find_model("ggx");
  const std::vector<double> chrome = parameter_values(ggx, {"albedo=0.08", "roughness=0.08", "f0=0.95"});
  SceneOptions options;
  options.outline = Circle{161.7, 124.2, 88.3};
  options.encoding = encoding;
  options.noise = 0.005;
  return write_sphere_scene(dir, "chrome", ggx, chrome, lights, options);
}

// Angle between two directions, degrees.
inline double angle_deg(const Vec3& a, const Vec3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / kPi; }

}  // namespace brdffit::test
