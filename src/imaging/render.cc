// Pictures of reflectance (see render.h).
#include "brdffit/imaging/render.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "brdffit/error.h"
#include "brdffit/imaging/image_io.h"
#include "brdffit/imaging/sphere.h"
#include "brdffit/parallel.h"
#include "brdffit/rusinkiewicz.h"

namespace brdffit {

namespace {

// What pictures show where there is no data (below the horizon, off the sphere in error maps):
// a dark grey, distinct from black (no light) and from the heatmap's zero.
constexpr float kNoData = 0.03f;

cv::Vec3f to_pixel(const Rgb<double>& rgb) {
  return cv::Vec3f(static_cast<float>(rgb[0]), static_cast<float>(rgb[1]), static_cast<float>(rgb[2]));
}

}  // namespace

BrdfFunction measured_brdf(const MeasuredBrdf& table) {
  return [&table](const Vec3& l, const Vec3& v) { return table.eval(l, v); };
}

BrdfFunction fitted_brdf(const Model& model, const FitResult& fit) {
  const auto fits_model = [&](const std::vector<double>& values) {
    return static_cast<int>(values.size()) == model.num_values();
  };
  if (!fits_model(fit.values) || !std::all_of(fit.channel_values.begin(), fit.channel_values.end(), fits_model) ||
      (!fit.channel_values.empty() && fit.channel_values.size() != 3))
    fail("{}: the result has {} values, the model has {}", model.name(), fit.values.size(), model.num_values());
  return [&model, &fit](const Vec3& l, const Vec3& v) -> Rgb<double> {
    if (l.z() <= 0.0) return Rgb<double>::Zero();
    return shade_fitted(model, fit.values, fit.channel_values, l, v) / l.z();
  };
}

Vec3 light_in_camera_frame(const SphereLighting& lighting) {
  const Vec3 light = normalized_or_zero(lighting.light), view = normalized_or_zero(lighting.view);
  if (light.isZero() || view.isZero()) fail("--light and --view must be non-zero directions");
  const Vec3 up = std::abs(view.y()) > 0.999 ? Vec3::UnitZ() : Vec3::UnitY();
  const Vec3 right = up.cross(view).normalized();
  const Vec3 camera_up = view.cross(right);
  return Vec3(right.dot(light), camera_up.dot(light), view.dot(light));
}

cv::Mat render_measured_sphere(const MeasuredBrdf& table, const SphereLighting& lighting, int size) {
  // The same pixels, normals and shading frames as a fitted model's sphere, with the table's f·cosθi.
  const ShadeFunction shade = [&table](const Vec3& l, const Vec3& v) -> Rgb<double> {
    return l.z() > 0.0 ? Rgb<double>(table.eval(l, v) * l.z()) : Rgb<double>::Zero();
  };
  return render_sphere(shade, SphereView::centred(size), light_in_camera_frame(lighting), cv::Size(size, size));
}

cv::Mat render_fitted_sphere(const Model& model, const FitResult& fit, const SphereLighting& lighting, int size) {
  fitted_brdf(model, fit);  // checks the values
  return render_sphere(model, fit.values, SphereView::centred(size), light_in_camera_frame(lighting),
                       cv::Size(size, size), fit.channel_values);
}

namespace {

// The environment's radiance towards -direction, in the camera frame (y up, z toward the camera):
// a sky from 0.25 at the horizon to 1 overhead, a ground of 0.1 and a warm key light 4x the
// zenith within 25° of the upper left, in front of the sphere.
Rgb<double> environment_radiance(const Vec3& direction) {
  const double up = direction.y();
  Rgb<double> radiance = up >= 0.0 ? Rgb<double>::Constant(0.25 + 0.75 * up) : Rgb<double>::Constant(0.1);
  const Vec3 key = Vec3(-0.6, 0.6, 0.55).normalized();
  if (direction.dot(key) > std::cos(25.0 * kPi / 180.0)) radiance += Rgb<double>(4.0, 3.6, 3.0);
  return radiance;
}

}  // namespace

cv::Mat render_environment_sphere(const BrdfFunction& brdf, int size) {
  const ShadeFunction shade = [&brdf](const Vec3& l, const Vec3& v) -> Rgb<double> {
    return l.z() > 0.0 ? Rgb<double>(brdf(l, v) * l.z()) : Rgb<double>::Zero();
  };
  const SphereView view = SphereView::centred(size);
  cv::Mat sum = cv::Mat::zeros(size, size, CV_32FC3);
  const double golden_angle = kPi * (3.0 - std::sqrt(5.0)), solid_angle = 4.0 * kPi / kEnvironmentLights;
  for (int k = 0; k < kEnvironmentLights; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / kEnvironmentLights, r = std::sqrt(1.0 - z * z);
    const Vec3 light(r * std::cos(golden_angle * k), r * std::sin(golden_angle * k), z);
    if (light.z() < -0.999) continue;  // straight behind: lights no visible pixel
    const Rgb<double> radiance = environment_radiance(light) * solid_angle;
    const cv::Mat lit = render_sphere(shade, view, light, cv::Size(size, size));
    cv::Mat weighted;
    cv::multiply(lit, cv::Scalar(radiance[0], radiance[1], radiance[2]), weighted);
    sum += weighted;
  }
  return sum;
}

cv::Mat sphere_mask(int size) { return sphere_pixels(SphereView::centred(size), cv::Size(size, size)); }

cv::Mat half_diff_slice(const BrdfFunction& brdf, int size) {
  cv::Mat image(size, size, CV_32FC3);
  parallel_for(static_cast<size_t>(size), thread_count(0), [&](size_t row) {
    const int y = static_cast<int>(row);
    for (int x = 0; x < size; ++x) {
      const double u = (x + 0.5) / size;
      HalfDiff angles;
      angles.theta_h = u * u * (kPi / 2);
      angles.theta_d = (y + 0.5) / size * (kPi / 2);
      angles.phi_d = kPi / 2;
      Vec3 l, v;
      from_half_diff(angles, l, v);
      image.at<cv::Vec3f>(y, x) = l.z() > 0.0 && v.z() > 0.0 ? to_pixel(brdf(l, v)) : cv::Vec3f::all(NAN);
    }
  });
  return image;
}

cv::Mat slice_mask(int size, double max_angle_deg) {
  const double min_cosine = std::cos(max_angle_deg * kPi / 180.0);
  cv::Mat mask(size, size, CV_8U);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const double u = (x + 0.5) / size;  // half_diff_slice's θh and θd
      const double theta_h = u * u * (kPi / 2), theta_d = (y + 0.5) / size * (kPi / 2);
      mask.at<uint8_t>(y, x) = std::cos(theta_h) * std::cos(theta_d) >= min_cosine ? 255 : 0;
    }
  return mask;
}

std::vector<double> in_plane_curve(const BrdfFunction& brdf, double theta_i_deg, int points) {
  const double theta_i = theta_i_deg * kPi / 180.0;
  const Vec3 l(-std::sin(theta_i), 0.0, std::cos(theta_i));
  std::vector<double> curve;
  for (int k = 0; k < points; ++k) {
    const double theta_o = (-89.0 + 178.0 * k / std::max(points - 1, 1)) * kPi / 180.0;
    curve.push_back(rec709_luminance(brdf(l, Vec3(std::sin(theta_o), 0.0, std::cos(theta_o)))));
  }
  return curve;
}

cv::Mat tone_map(const cv::Mat& linear, double reference) {
  // Extended Reinhard: d = x(1 + x/w²)/(1 + x) with x in units of the reference and w = 4 the
  // white point; x = 1 gives d ≈ 0.53, which sRGB shows at about 75%.
  constexpr double kWhite = 4.0;
  cv::Mat display(linear.size(), CV_32FC3);
  for (int y = 0; y < linear.rows; ++y)
    for (int x = 0; x < linear.cols; ++x) {
      const cv::Vec3f& in = linear.at<cv::Vec3f>(y, x);
      cv::Vec3f& out = display.at<cv::Vec3f>(y, x);
      for (int c = 0; c < 3; ++c) {
        if (std::isnan(in[c])) {
          out = cv::Vec3f::all(kNoData);
          break;
        }
        const double v = std::max(0.0, static_cast<double>(in[c])) / reference;
        out[c] = static_cast<float>(std::min(1.0, v * (1.0 + v / (kWhite * kWhite)) / (1.0 + v)));
      }
    }
  return display;
}

double tone_reference(const cv::Mat& linear, const cv::Mat& mask) {
  std::vector<float> brightest;
  for (int y = 0; y < linear.rows; ++y)
    for (int x = 0; x < linear.cols; ++x) {
      if (!mask.empty() && !mask.at<uint8_t>(y, x)) continue;
      const cv::Vec3f& p = linear.at<cv::Vec3f>(y, x);
      const float b = std::max({p[0], p[1], p[2]});
      if (std::isfinite(b)) brightest.push_back(b);
    }
  if (brightest.empty()) return 1.0;
  // Nearest-rank percentile: the smallest value with at least 99% of the values at or below it.
  auto q99 = brightest.begin() + static_cast<std::ptrdiff_t>(std::ceil(0.99 * brightest.size()) - 1);
  std::nth_element(brightest.begin(), q99, brightest.end());
  return *q99 > 0.0f ? *q99 : 1.0;
}

double quantile(const cv::Mat& values, double q, const cv::Mat& mask) {
  std::vector<float> finite;
  for (int y = 0; y < values.rows; ++y)
    for (int x = 0; x < values.cols; ++x)
      if ((mask.empty() || mask.at<uint8_t>(y, x)) && std::isfinite(values.at<float>(y, x)))
        finite.push_back(values.at<float>(y, x));
  if (finite.empty()) return 0.0;
  const auto rank = static_cast<std::ptrdiff_t>(
      std::clamp(std::ceil(q * finite.size()) - 1.0, 0.0, static_cast<double>(finite.size() - 1)));
  std::nth_element(finite.begin(), finite.begin() + rank, finite.end());
  return finite[static_cast<size_t>(rank)];
}

cv::Mat signed_relative_difference(const cv::Mat& fit, const cv::Mat& measured, double floor) {
  cv::Mat relative(fit.size(), CV_32F);
  for (int y = 0; y < fit.rows; ++y)
    for (int x = 0; x < fit.cols; ++x) {
      const cv::Vec3f &p = fit.at<cv::Vec3f>(y, x), &q = measured.at<cv::Vec3f>(y, x);
      const double yp = rec709_luminance(Rgb<double>(p[0], p[1], p[2]));
      const double yq = rec709_luminance(Rgb<double>(q[0], q[1], q[2]));
      relative.at<float>(y, x) = static_cast<float>((yp - yq) / std::max(yq, floor));  // NaN stays NaN
    }
  return relative;
}

cv::Mat signed_heatmap(const cv::Mat& values, double full_scale, const cv::Mat& mask) {
  // Display (sRGB) colours, converted to linear light like every other picture.
  const cv::Vec3f blue(0.13f, 0.4f, 0.85f), white(0.97f, 0.97f, 0.97f), red(0.8f, 0.15f, 0.1f);
  cv::Mat image(values.size(), CV_32FC3);
  for (int y = 0; y < values.rows; ++y)
    for (int x = 0; x < values.cols; ++x) {
      const float v = values.at<float>(y, x);
      const float t = std::isnan(v) ? 0.0f : static_cast<float>(std::clamp(v / full_scale, -1.0, 1.0));
      image.at<cv::Vec3f>(y, x) = t < 0 ? white + (blue - white) * -t : white + (red - white) * t;
    }
  srgb_to_linear(image);
  for (int y = 0; y < values.rows; ++y)
    for (int x = 0; x < values.cols; ++x)
      if (std::isnan(values.at<float>(y, x)) || (!mask.empty() && !mask.at<uint8_t>(y, x)))
        image.at<cv::Vec3f>(y, x) = cv::Vec3f::all(kNoData);
  return image;
}

cv::Mat channel_max_difference(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat difference(a.size(), CV_32F);
  for (int y = 0; y < a.rows; ++y)
    for (int x = 0; x < a.cols; ++x) {
      const cv::Vec3f &p = a.at<cv::Vec3f>(y, x), &q = b.at<cv::Vec3f>(y, x);
      float d = 0.0f;
      for (int c = 0; c < 3; ++c) d = std::max(d, std::fabs(p[c] - q[c]));
      const bool missing = std::isnan(p[0] + p[1] + p[2] + q[0] + q[1] + q[2]);
      difference.at<float>(y, x) = missing ? NAN : d;
    }
  return difference;
}

cv::Mat error_heatmap(const cv::Mat& difference, double full_scale, const cv::Mat& mask) {
  cv::Mat finite = difference.clone();
  cv::patchNaNs(finite, 0.0);
  cv::Mat image = heatmap(finite, full_scale);
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x)
      if (std::isnan(difference.at<float>(y, x)) || (!mask.empty() && !mask.at<uint8_t>(y, x)))
        image.at<cv::Vec3f>(y, x) = cv::Vec3f::all(kNoData);
  return image;
}

ErrorPanel robust_error_panel(const cv::Mat& difference, double q, const cv::Mat& scale_mask, int decades) {
  double scale = quantile(difference, q, scale_mask);
  if (!(scale > 0.0)) scale = quantile(difference, 1.0, scale_mask);
  if (!(scale > 0.0)) scale = 1.0;
  if (decades <= 0) return {error_heatmap(difference, scale), scale};
  cv::Mat position(difference.size(), CV_32F);  // 0 at scale·10^-decades, 1 at scale; NaN stays NaN
  const double bottom = std::log10(scale) - decades;
  for (int y = 0; y < difference.rows; ++y)
    for (int x = 0; x < difference.cols; ++x) {
      const float d = difference.at<float>(y, x);
      position.at<float>(y, x) = std::isnan(d) ? NAN
                                 : d > 0.0f    ? static_cast<float>(std::max(0.0, (std::log10(d) - bottom) / decades))
                                               : 0.0f;
    }
  return {error_heatmap(position, 1.0), scale};
}

}  // namespace brdffit
