// Where the sphere is: from a mask, or found in the pictures (OpenCV).
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "brdffit/error.h"
#include "brdffit/imaging/sphere.h"

namespace brdffit {

namespace {

// Least-squares circle through points (Kåsa's algebraic fit: x² + y² + Dx + Ey + F = 0), on
// coordinates taken relative to their mean for conditioning.
Circle fit_circle(const std::vector<cv::Point2d>& points) {
  cv::Point2d mean(0.0, 0.0);
  for (const cv::Point2d& p : points) mean += p;
  mean *= 1.0 / static_cast<double>(points.size());
  Eigen::MatrixXd a(points.size(), 3);
  Eigen::VectorXd b(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const double x = points[i].x - mean.x, y = points[i].y - mean.y;
    a.row(static_cast<Eigen::Index>(i)) << x, y, 1.0;
    b[static_cast<Eigen::Index>(i)] = -(x * x + y * y);
  }
  const Eigen::Vector3d def = a.colPivHouseholderQr().solve(b);
  const double cx = -def[0] / 2.0, cy = -def[1] / 2.0;
  return Circle{mean.x + cx, mean.y + cy, std::sqrt(std::max(0.0, cx * cx + cy * cy - def[2]))};
}

// The edge points that lie on one circle: the circle through three random points that the most
// points lie within half a pixel of (RANSAC, seeded so that results repeat). In a picture lit
// from one side, half the silhouette is in attached shadow and the rays there find the
// terminator instead, which is not on that circle.
std::vector<cv::Point2d> consensus(const std::vector<cv::Point2d>& points) {
  constexpr double kTolerance = 0.5;
  cv::RNG rng(1);
  const int n = static_cast<int>(points.size());
  std::vector<cv::Point2d> best;
  for (int trial = 0; trial < 300 && n >= 3; ++trial) {
    const Circle c = fit_circle({points[rng.uniform(0, n)], points[rng.uniform(0, n)], points[rng.uniform(0, n)]});
    if (!(c.radius > 0.0)) continue;
    std::vector<cv::Point2d> inliers;
    for (const cv::Point2d& p : points)
      if (std::fabs(std::hypot(p.x - c.x, p.y - c.y) - c.radius) < kTolerance) inliers.push_back(p);
    if (inliers.size() > best.size()) best = std::move(inliers);
  }
  return best;
}

// The circle a candidate really is, to sub-pixel precision, or nothing when its edge does not
// hold up. Along 360 rays from the centre across the current outline, the silhouette is where
// the (blurred) brightness changes fastest: each ray's steepest point, located between samples
// by a parabola, is one edge point when the brightness clearly changes across it. A circle is
// fitted by least squares to the edge points that agree on one; three rounds, each from the
// previous circle. The edge must show on at least 30% of the rays (a sphere lit from one side
// shows half its silhouette) and the circle may move only a little from the candidate.
std::optional<Circle> refine_on_silhouette(const cv::Mat& brightness, const Circle& candidate) {
  constexpr int kRays = 360;
  constexpr double kStep = 0.25;                     // pixels between samples along a ray
  constexpr double kMinStep = 0.08;                  // brightness change across the edge (0..1 scale) that counts
  constexpr double kMinFraction = 0.3;               // of the rays
  const int across = static_cast<int>(2.0 / kStep);  // samples in 2 px
  Circle circle = candidate;
  for (int round = 0; round < 3; ++round) {
    const double half_band = std::max(4.0, 0.15 * circle.radius);
    const int samples = static_cast<int>(2.0 * half_band / kStep) + 1;
    cv::Mat map_x(kRays, samples, CV_32F), map_y(kRays, samples, CV_32F);
    for (int k = 0; k < kRays; ++k) {
      const double angle = 2.0 * kPi * k / kRays;
      for (int j = 0; j < samples; ++j) {
        const double r = circle.radius - half_band + j * kStep;
        map_x.at<float>(k, j) = static_cast<float>(circle.x + r * std::cos(angle));
        map_y.at<float>(k, j) = static_cast<float>(circle.y + r * std::sin(angle));
      }
    }
    cv::Mat profiles, slopes;  // one row per ray
    cv::remap(brightness, profiles, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    cv::Sobel(profiles, slopes, CV_32F, 1, 0, 1);  // central differences along each ray only
    slopes = cv::abs(slopes);

    std::vector<cv::Point2d> edge;
    for (int k = 0; k < kRays; ++k) {
      const float* slope = slopes.ptr<float>(k);
      const float* profile = profiles.ptr<float>(k);
      const int steepest = static_cast<int>(std::max_element(slope + across, slope + samples - across) - slope);
      if (std::fabs(profile[steepest - across] - profile[steepest + across]) < kMinStep) continue;
      const double before = slope[steepest - 1], at = slope[steepest], after = slope[steepest + 1];
      const double curvature = before - 2.0 * at + after;
      const double offset = curvature < 0.0 ? 0.5 * (before - after) / curvature : 0.0;
      const double r = circle.radius - half_band + (steepest + offset) * kStep;
      const double angle = 2.0 * kPi * k / kRays;
      edge.emplace_back(circle.x + r * std::cos(angle), circle.y + r * std::sin(angle));
    }
    const std::vector<cv::Point2d> inliers = consensus(edge);
    if (inliers.size() < kMinFraction * kRays) return std::nullopt;
    circle = fit_circle(inliers);
  }
  const double moved = std::hypot(circle.x - candidate.x, circle.y - candidate.y);
  if (moved > 0.25 * candidate.radius || std::fabs(circle.radius - candidate.radius) > 0.25 * candidate.radius)
    return std::nullopt;
  return circle;
}

}  // namespace

Circle circle_from_mask(const cv::Mat& mask, const std::string& what) {
  const cv::Moments moments = cv::moments(mask, /*binaryImage=*/true);
  if (moments.m00 < 1.0) fail("{}: the mask is empty", what);
  const Circle circle{moments.m10 / moments.m00, moments.m01 / moments.m00, std::sqrt(moments.m00 / kPi)};
  // A disc's bounding box is a square about as wide as the disc of the same area.
  std::vector<cv::Point> inside;
  cv::findNonZero(mask, inside);
  const cv::Rect box = cv::boundingRect(inside);
  const double diameter = 2.0 * circle.radius, tolerance = 0.05 * diameter + 1.5;
  if (std::fabs(box.width - diameter) > tolerance || std::fabs(box.height - diameter) > tolerance)
    fail("{}: the mask is not one disc: it spans {}x{} pixels, a disc of its area would span {:.0f}", what, box.width,
         box.height, diameter);
  return circle;
}

cv::Mat read_mask(const std::string& path) {
  const cv::Mat rgb = read_image(path, Decoding{Transfer::Linear});
  std::vector<cv::Mat> channels;
  cv::split(rgb, channels);
  const cv::Mat brightest = cv::max(cv::max(channels[0], channels[1]), channels[2]);
  return brightest > 0.5;
}

Circle detect_sphere(const cv::Mat& rgb, const std::string& what) {
  cv::Mat luminance;
  cv::cvtColor(rgb, luminance, cv::COLOR_RGB2GRAY);
  double peak = 0.0;
  cv::minMaxLoc(luminance, nullptr, &peak);
  if (!(peak > 0.0)) fail("{}: no sphere found: the picture is black", what);
  // Brightness on a 0..1 scale, gamma-compressed so that the dim rim of a lit sphere stands
  // out from a dark background, lightly blurred so that edges are smooth to sub-pixel level.
  cv::Mat brightness;
  cv::pow(cv::max(luminance / peak, 0.0), 1.0 / 2.2, brightness);
  cv::GaussianBlur(brightness, brightness, cv::Size(0, 0), 1.0);
  cv::Mat codes;
  brightness.convertTo(codes, CV_8U, 255.0);

  const int smaller = std::min(rgb.cols, rgb.rows);
  std::vector<cv::Vec3f> candidates;
  // The "alternative" Hough gradient method scores how complete each circle is (0.8: most of
  // its edge found); 300 is OpenCV's recommended Canny threshold for it on 8-bit images. Circles
  // may share a centre (a highlight in the middle of the sphere), hence the tiny minimum distance.
  cv::HoughCircles(codes, candidates, cv::HOUGH_GRADIENT_ALT, 1.5, 2.0, 300.0, 0.8, 6, smaller / 2);
  // The sphere is the largest circle: the others are highlights or details on it.
  std::sort(candidates.begin(), candidates.end(), [](const cv::Vec3f& a, const cv::Vec3f& b) { return a[2] > b[2]; });
  for (const cv::Vec3f& c : candidates)
    if (const std::optional<Circle> circle = refine_on_silhouette(brightness, Circle{c[0], c[1], c[2]})) return *circle;
  fail("{}: no sphere found: no circular silhouette stands out from the background (give a mask with --mask)", what);
}

cv::Mat brightest_of(const std::vector<std::string>& paths, const Decoding& decoding) {
  cv::Mat brightest;
  for (const std::string& path : paths) {
    const cv::Mat image = read_image(path, decoding);
    if (brightest.empty()) {
      brightest = image;
      continue;
    }
    if (image.size() != brightest.size())
      fail("{}: is {}x{} pixels, but {} is {}x{}", path, image.cols, image.rows, paths.front(), brightest.cols,
           brightest.rows);
    brightest = cv::max(brightest, image);
  }
  return brightest;
}

}  // namespace brdffit
