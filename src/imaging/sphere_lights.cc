// Lights: per-image text files (directions, intensities, exposures) and chrome-ball estimation.
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "brdffit/error.h"
#include "brdffit/imaging/sphere.h"
#include "brdffit/io.h"

namespace brdffit {

namespace {

// The rows of a text file with `columns` numbers per line (separated by spaces, tabs or
// commas), skipping blank lines and '#' comments; `what` names a row in messages ("light
// direction"), and there must be one per image.
std::vector<std::vector<double>> read_rows(const std::string& path, size_t columns, const char* what, size_t expected) {
  std::istringstream text(read_file(path));
  std::vector<std::vector<double>> rows;
  std::string line;
  for (int number = 1; std::getline(text, line); ++number) {
    line = line.substr(0, line.find('#'));
    for (char& c : line)
      if (c == ',' || c == '\t' || c == '\r') c = ' ';
    std::istringstream fields(line);
    std::vector<double> row;
    std::string field;
    while (fields >> field) {
      size_t used = 0;
      double x = NAN;
      try {
        x = std::stod(field, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != field.size() || !std::isfinite(x)) fail("{}:{}: '{}' is not a finite number", path, number, field);
      if (x != 0.0 && (std::abs(x) < kMinLightNumber || std::abs(x) > kMaxLightNumber))
        fail("{}:{}: '{}' is out of range (numbers here are 0 or between {:g} and {:g} in size)", path, number, field,
             kMinLightNumber, kMaxLightNumber);
      row.push_back(x);
    }
    if (row.empty()) continue;
    if (row.size() != columns)
      fail("{}:{}: expected {} (a {}), found {}", path, number, count_of(columns, "number"), what, row.size());
    rows.push_back(row);
  }
  if (rows.size() != expected) fail("{}: {} for {}", path, count_of(rows.size(), what), count_of(expected, "image"));
  return rows;
}

}  // namespace

std::vector<Vec3> read_light_directions(const std::string& path, size_t expected) {
  std::vector<Vec3> lights;
  for (const std::vector<double>& row : read_rows(path, 3, "light direction", expected)) {
    const Vec3 d(row[0], row[1], row[2]);
    if (!(d.norm() > 0.0)) fail("{}: light direction {} is zero", path, lights.size() + 1);
    lights.push_back(d.normalized());
  }
  return lights;
}

std::vector<Rgb<double>> read_light_intensities(const std::string& path, size_t expected) {
  std::vector<Rgb<double>> intensities;
  for (const std::vector<double>& row : read_rows(path, 3, "light intensity", expected)) {
    if (!(row[0] > 0.0 && row[1] > 0.0 && row[2] > 0.0))
      fail("{}: light intensity {} is not positive in every channel", path, intensities.size() + 1);
    intensities.emplace_back(row[0], row[1], row[2]);
  }
  return intensities;
}

std::vector<double> read_exposures(const std::string& path, size_t expected) {
  std::vector<double> exposures;
  for (const std::vector<double>& row : read_rows(path, 1, "exposure time", expected)) {
    if (!(row[0] > 0.0)) fail("{}: exposure time {} is not positive", path, exposures.size() + 1);
    exposures.push_back(row[0]);
  }
  return exposures;
}

Vec3 light_from_chrome(const cv::Mat& rgb, const SphereView& ball, const std::string& what) {
  const cv::Rect box = ball.bounds(rgb.size());
  cv::Mat luminance;
  cv::cvtColor(rgb(box), luminance, cv::COLOR_RGB2GRAY);
  const cv::Mat on_ball = sphere_pixels(ball, rgb.size())(box);
  double peak = 0.0;
  cv::minMaxLoc(luminance, nullptr, &peak, nullptr, nullptr, on_ball);
  if (!(peak > 0.0)) fail("{}: no highlight on the chrome ball: it is black", what);

  // Weights: how much brighter than half the peak each pixel on the ball is.
  cv::Mat weight;
  cv::threshold(luminance - 0.5 * peak, weight, 0.0, 0.0, cv::THRESH_TOZERO);
  weight.setTo(0.0, on_ball == 0);
  const cv::Moments moments = cv::moments(weight);
  const double x = box.x + moments.m10 / moments.m00, y = box.y + moments.m01 / moments.m00;
  Vec3 normal, view;
  if (!ball.surface_at(x, y, normal, view)) fail("{}: the chrome ball's highlight lies off the ball", what);
  return (2.0 * normal.dot(view) * normal - view).normalized();
}

}  // namespace brdffit
