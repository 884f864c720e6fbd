// Sphere geometry, the shading frame, which pixels are used, and rendering onto a sphere.
#include "brdffit/imaging/sphere.h"

#include <Eigen/Geometry>  // cross, unitOrthogonal
#include <algorithm>
#include <cmath>

#include "brdffit/error.h"
#include "brdffit/parallel.h"

namespace brdffit {

namespace {

// The unit ray from a perspective camera through pixel (x, y): image rows run down, the camera
// frame's y up, and the camera looks along -z.
Vec3 camera_ray(const Camera& camera, double x, double y) {
  return Vec3(x - camera.principal_x, -(y - camera.principal_y), -camera.focal_px).normalized();
}

}  // namespace

Camera Camera::centred(double focal_px, cv::Size image) {
  return {focal_px, (image.width - 1) / 2.0, (image.height - 1) / 2.0};
}

namespace {

// The silhouette of a sphere whose centre is seen at angle θ from the optical axis under a
// half-angle α (the cone of rays grazing it), on an image plane at distance f: an ellipse whose
// long axis lies along the radial line, from f·tan(θ−α) to f·tan(θ+α). Returns the distance of
// its centre from the principal point and the radius of the circle of equal area, √(a·b).
struct ConeImage {
  double centre, area_radius;
};
ConeImage cone_image(double theta, double alpha, double f) {
  const double near = f * std::tan(theta - alpha), far = f * std::tan(theta + alpha);
  const double centre = 0.5 * (near + far), a = 0.5 * (far - near);
  // Across the long axis at its centre: the points (centre, y, f) at angle α from the cone's axis
  // (sin θ, 0, cos θ): (centre·sin θ + f·cos θ)² = cos²α (centre² + y² + f²).
  const double along = centre * std::sin(theta) + f * std::cos(theta);
  const double b = std::sqrt(std::max(0.0, along * along / std::pow(std::cos(alpha), 2) - centre * centre - f * f));
  return {centre, std::sqrt(a * b)};
}

// x in [lo, hi] where an increasing function reaches `target`, by bisection.
template <class F>
double solve_increasing(F&& f, double target, double lo, double hi) {
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) < target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

SphereView::SphereView(const Circle& outline, const Camera& camera) : outline_(outline), camera_(camera) {
  if (!camera.perspective()) return;
  // The outline is the circle closest to the silhouette: centred on it and of the same area (as
  // circle_from_mask's moments and detect_sphere's least-squares fit to its edge give it). Off the
  // principal point the silhouette is an ellipse stretched along the radial line, so the sphere
  // is the one whose grazing cone (centre direction at θ, half-angle α) projects to an ellipse with
  // that centre and that area; its centre lies at distance 1/sin α for a sphere of radius 1.
  // (Taking the outline's radius as the ellipse's long half-axis instead put the normals of a
  // sphere 20° off the axis 1-2° off, and chrome-ball lights up to 2.5° off.)
  const double f = camera.focal_px;
  Eigen::Vector2d radial(outline.x - camera.principal_x, outline.y - camera.principal_y);
  const double distance = radial.norm();
  radial = distance > 1e-9 ? Eigen::Vector2d(radial / distance) : Eigen::Vector2d(1.0, 0.0);
  const auto theta_for = [&](double alpha) {
    return solve_increasing([&](double theta) { return cone_image(theta, alpha, f).centre; }, distance, 0.0,
                            0.5 * kPi - alpha);
  };
  const double alpha = solve_increasing([&](double a) { return cone_image(theta_for(a), a, f).area_radius; },
                                        outline.radius, 0.0, 0.5 * kPi);
  const double theta = theta_for(alpha);
  const Vec3 axis = camera_ray(camera, camera.principal_x + f * std::tan(theta) * radial.x(),
                               camera.principal_y + f * std::tan(theta) * radial.y());
  centre_ = axis / std::sin(alpha);
}

SphereView SphereView::centred(int size) {
  const double middle = (size - 1) / 2.0;
  return SphereView(Circle{middle, middle, size / 2.0 - 1.0}, Camera{});
}

bool SphereView::surface_at(double x, double y, Vec3& normal, Vec3& view) const {
  if (!camera_.perspective()) {
    const double nx = (x - outline_.x) / outline_.radius, ny = -(y - outline_.y) / outline_.radius;
    const double r2 = nx * nx + ny * ny;
    if (!(r2 < 1.0)) return false;  // also for an empty view (radius 0)
    normal = Vec3(nx, ny, std::sqrt(1.0 - r2));
    view = Vec3(0.0, 0.0, 1.0);
    return true;
  }
  // The nearer intersection of the ray t·u with the unit sphere around centre_.
  const Vec3 u = camera_ray(camera_, x, y);
  const double along = u.dot(centre_);
  const double discriminant = along * along - (centre_.squaredNorm() - 1.0);
  if (discriminant <= 0.0) return false;
  const double t = along - std::sqrt(discriminant);
  if (t <= 0.0) return false;
  normal = (t * u - centre_).normalized();
  view = -u;
  return true;
}

cv::Rect SphereView::bounds(cv::Size image) const {
  // The perspective silhouette is a slightly larger ellipse than the outline circle.
  const double reach = outline_.radius * (camera_.perspective() ? 1.1 : 1.0) + 2.0;
  const cv::Rect box(
      cv::Point(static_cast<int>(std::floor(outline_.x - reach)), static_cast<int>(std::floor(outline_.y - reach))),
      cv::Point(static_cast<int>(std::ceil(outline_.x + reach)) + 1,
                static_cast<int>(std::ceil(outline_.y + reach)) + 1));
  return box & cv::Rect(cv::Point(0, 0), image);
}

namespace {
// The longitude direction ŷ × n, where a UV sphere's u grows (three.js's SphereGeometry and the
// tangents it computes); at the poles, where it vanishes, any direction across the normal.
Vec3 longitude_tangent(const Vec3& n) {
  const Vec3 along = Vec3::UnitY().cross(n);
  return along.norm() > 1e-9 ? along.normalized() : n.unitOrthogonal();
}
}  // namespace

LocalFrame::LocalFrame(const Vec3& n) : tangent(longitude_tangent(n)), bitangent(n.cross(tangent)), normal(n) {}

const char* pixel_fate_name(PixelFate fate) {
  switch (fate) {
    case PixelFate::Used: return "used";
    case PixelFate::Shadow: return "shadow";
    case PixelFate::Grazing: return "grazing";
    case PixelFate::Saturated: return "saturated";
    case PixelFate::Dark: return "dark";
  }
  return "?";
}

PixelFate classify_pixel(const Vec3& normal, const Vec3& view, const Vec3& light, const cv::Vec3f& pixel,
                         double full_scale, bool clips, const PixelRules& rules) {
  const double cos_light = normal.dot(light), cos_view = normal.dot(view);
  if (cos_light <= 0.0) return PixelFate::Shadow;
  const double min_cos = std::cos(rules.max_angle_deg * kPi / 180.0);
  if (cos_light < min_cos || cos_view < min_cos) return PixelFate::Grazing;
  const double brightest = std::max({pixel[0], pixel[1], pixel[2]});
  if (clips && brightest >= rules.saturation * full_scale) return PixelFate::Saturated;
  if (brightest < rules.dark * full_scale) return PixelFate::Dark;
  return PixelFate::Used;
}

cv::Mat render_sphere(const ShadeFunction& shade, const SphereView& sphere, const Vec3& light, cv::Size size) {
  cv::Mat image(size, CV_32FC3, cv::Scalar::all(0.0));
  const Vec3 l = light.normalized();
  const cv::Rect box = sphere.bounds(size);
  parallel_for(static_cast<size_t>(box.height), thread_count(0), [&](size_t row) {
    const int y = box.y + static_cast<int>(row);
    for (int x = box.x; x < box.x + box.width; ++x) {
      Vec3 normal, view;
      if (!sphere.surface_at(x, y, normal, view)) continue;
      const LocalFrame frame(normal);
      const Rgb<double> value = shade(frame.to_local(l), frame.to_local(view));
      image.at<cv::Vec3f>(y, x) =
          cv::Vec3f(static_cast<float>(value[0]), static_cast<float>(value[1]), static_cast<float>(value[2]));
    }
  });
  return image;
}

cv::Mat render_sphere(const Model& model, const std::vector<double>& values, const SphereView& sphere,
                      const Vec3& light, cv::Size size, const std::vector<std::vector<double>>& per_channel_values) {
  return render_sphere(
      [&](const Vec3& l, const Vec3& v) { return shade_fitted(model, values, per_channel_values, l, v); }, sphere,
      light, size);
}

cv::Mat sphere_pixels(const SphereView& sphere, cv::Size size) {
  cv::Mat pixels(size, CV_8U, cv::Scalar(0));
  for_each_sphere_pixel(sphere, size, cv::Mat(),
                        [&](int x, int y, const Vec3&, const Vec3&) { pixels.at<uint8_t>(y, x) = 255; });
  return pixels;
}

NormalCheck check_normals(const SphereView& sphere, const std::string& normal_map, cv::Size size, const cv::Mat& mask) {
  const cv::Mat encoded = read_image(normal_map, Decoding{Transfer::Linear});
  if (encoded.size() != size)
    fail("{}: {}x{} pixels, the photographs {}x{}", normal_map, encoded.cols, encoded.rows, size.width, size.height);
  std::vector<double> errors;
  for_each_sphere_pixel(sphere, size, mask, [&](int x, int y, const Vec3& normal, const Vec3&) {
    const cv::Vec3f e = encoded.at<cv::Vec3f>(y, x);
    const Vec3 truth(2.0 * e[0] - 1.0, 2.0 * e[1] - 1.0, 2.0 * e[2] - 1.0);
    if (std::abs(truth.norm() - 1.0) > 0.1) return;
    errors.push_back(std::acos(std::clamp(normal.dot(truth.normalized()), -1.0, 1.0)) * 180.0 / kPi);
  });
  if (errors.empty()) fail("{}: holds no normal on the located sphere", normal_map);
  NormalCheck check{normal_map, errors.size()};
  auto at_fraction = [&](double q) {
    auto it = errors.begin() + static_cast<std::ptrdiff_t>(q * (errors.size() - 1));
    std::nth_element(errors.begin(), it, errors.end());
    return *it;
  };
  check.median_deg = at_fraction(0.5);
  check.p90_deg = at_fraction(0.9);
  return check;
}

}  // namespace brdffit
