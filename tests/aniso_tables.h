// Test and bench helper: anisotropic reflectance tables made from an analytic model with known
// values (random pairs as samples, CSV, and an RGL-format file written with
// tensor_file_writer.h), and the comparison of a fitted tangent frame with the truth.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "brdffit/model.h"
#include "brdffit/samples.h"
#include "tensor_file_writer.h"

namespace brdffit::test {

// n samples of `model` at `values` on pairs of directions uniform over the hemisphere up to
// max_angle_deg from the normal, each value multiplied by (1 + noise·N(0,1)), weight 1.
inline SampleSet anisotropic_samples(const Model& model, const std::vector<double>& values, size_t n, double noise,
                                     uint64_t seed, double max_angle_deg = 80.0) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double min_z = std::cos(max_angle_deg * kPi / 180.0);
  auto direction = [&] {
    const double z = min_z + (1.0 - min_z) * unit(rng), r = std::sqrt(1.0 - z * z), phi = 2 * kPi * unit(rng);
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
  };
  SampleSet set;
  set.source = "synthetic " + model.name();
  set.weighting = "uniform";
  for (size_t i = 0; i < n; ++i) {
    const Vec3 l = direction(), v = direction();
    Rgb<double> value = model.shade(values.data(), l, v);
    for (int c = 0; c < 3; ++c) value[c] *= 1.0 + noise * gauss(rng);
    set.samples.push_back({l, v, value, 1.0});
  }
  return set;
}

// The tensor-file fields of an anisotropic RGL BRDF that tabulates `model` at `values`. The
// RGL table's value is f·cosθo = rgb(warped u)·ndf(u)/(4σ) with u the half vector's coordinates
// (rgl.h); here the VNDF is uniform (its warp is the identity), σ = 1/4, the NDF table holds
// the fast-varying part of the lobe, P(h) = f(h, h) (the half vector's peak value), on a fine
// grid, and rgb the slowly varying f(l, v)·cosθo/P(h) per incident direction. `resolution` scales
// every grid.
inline std::vector<TensorField> anisotropic_rgl_fields(const Model& model, const std::vector<double>& values,
                                                       int resolution = 1) {
  using Index = std::vector<uint64_t>;
  const int n_phi_i = 12 * resolution + 1, n_theta_i = 20 * resolution, n_theta_m = 32 * resolution,
            n_phi_m = 64 * resolution;
  std::vector<float> phi_i, theta_i;
  for (int i = 0; i < n_phi_i; ++i) phi_i.push_back(float(-kPi + 2 * kPi * i / (n_phi_i - 1)));
  for (int i = 0; i < n_theta_i; ++i) theta_i.push_back(float(0.5 * kPi * i / (n_theta_i - 1)));
  // Grid vertex -> direction: u_x = √(θ/(π/2)), u_y = (φ + π)/(2π), as the RGL reader maps them.
  auto from_grid = [](uint64_t x, uint64_t nx, uint64_t y, uint64_t ny) {
    const double ux = double(x) / (nx - 1), uy = double(y) / (ny - 1);
    const double theta = ux * ux * kPi / 2, phi = 2 * kPi * uy - kPi;
    return Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  };
  // P(h): as fast-varying in h as the lobe's D(h), while f/P stays smooth and bounded (both
  // include the Lambert term).
  const int ndf_ny = 4 * n_phi_m, ndf_nx = 4 * n_theta_m;
  auto peak = [&](const Vec3& h) {
    const Rgb<double> f = *model.brdf(values.data(), h, h);
    return std::max(f.mean(), 1e-6);
  };
  return {
      bytes_field("description", "analytic " + model.name()),
      float_values("phi_i", phi_i),
      float_values("theta_i", theta_i),
      float_field("ndf", {uint64_t(ndf_ny), uint64_t(ndf_nx)},
                  [&](const Index& i) { return peak(from_grid(i[1], ndf_nx, i[0], ndf_ny)); }),
      float_field("sigma", {2, 2}, [](const Index&) { return 0.25; }),
      float_field("vndf", {uint64_t(n_phi_i), uint64_t(n_theta_i), 2, 2}, [](const Index&) { return 1.0; }),
      float_field("luminance", {uint64_t(n_phi_i), uint64_t(n_theta_i), 2, 2}, [](const Index&) { return 1.0; }),
      float_field("rgb", {uint64_t(n_phi_i), uint64_t(n_theta_i), 3, uint64_t(n_phi_m), uint64_t(n_theta_m)},
                  [&](const Index& i) {
                    const double th = theta_i[i[1]], ph = phi_i[i[0]];
                    const Vec3 l(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
                    const Vec3 h = from_grid(i[4], n_theta_m, i[3], n_phi_m);
                    const Vec3 v = 2 * l.dot(h) * h - l;
                    if (l.z() <= 1e-4 || v.z() <= 1e-4) return 0.0;
                    // RGL tables hold f·cosθo, wi the view (rgl.h): here l is the table's wi.
                    return (*model.brdf(values.data(), l, v))[i[2]] * v.z() / peak(h);
                  }),
      {"jacobian", kUInt8, {1}, std::string(1, '\x01')},
  };
}

// A tangent frame as (α_x, α_y, φ₀ in degrees). A lobe is the same with φ₀ + 180°, and with
// φ₀ + 90° and its widths exchanged (common.h).
struct TangentFrame {
  double along_x, along_y, phi0;
};
// The frame in the models' range φ₀ ∈ [0°, 90°) for a lobe turned by any angle.
inline TangentFrame model_frame(double along_x, double along_y, double phi0) {
  phi0 -= 180.0 * std::floor(phi0 / 180.0);
  if (phi0 >= 90.0) return {along_y, along_x, phi0 - 90.0};
  return {along_x, along_y, phi0};
}
// The one form where α_x ≤ α_y and φ₀ ∈ [0°, 180°), to compare frames.
inline TangentFrame canonical_frame(double along_x, double along_y, double phi0) {
  if (along_x > along_y) {
    std::swap(along_x, along_y);
    phi0 += 90.0;
  }
  return {along_x, along_y, phi0 - 180.0 * std::floor(phi0 / 180.0)};
}
// The values of `model` (an anisotropic model: its last three values are the widths and φ₀)
// from `params` with the lobe turned by rotation_deg (any angle).
inline std::vector<double> turned_values(const Model& model, const std::vector<std::string>& params,
                                         const std::string& width_x, const std::string& width_y, double rotation_deg) {
  std::vector<double> values = parameter_values(model, params);
  const int x = model.offset_of(width_x), y = model.offset_of(width_y), phi0 = model.offset_of("phi0");
  const TangentFrame frame = model_frame(values[x], values[y], rotation_deg);
  values[x] = frame.along_x;
  values[y] = frame.along_y;
  values[phi0] = frame.phi0;
  return values;
}
// One anisotropic lobe per model, with distinct widths, for recovery tests and benches.
struct AnisotropicCase {
  std::string model;
  std::vector<std::string> params;  // all but φ₀
  std::string width_x, width_y;     // the names of its two widths
};
inline std::vector<AnisotropicCase> anisotropic_cases() {
  return {{"ggx-aniso", {"albedo=0.1,0.2,0.3", "f0=0.6,0.5,0.4", "alpha_x=0.08", "alpha_y=0.3"}, "alpha_x", "alpha_y"},
          {"ward-aniso", {"albedo=0.2", "specular=0.3", "alpha_x=0.25", "alpha_y=0.1"}, "alpha_x", "alpha_y"},
          {"ashikhmin-shirley-aniso", {"albedo=0.15", "specular=0.8", "f0=0.3", "n_u=20", "n_v=300"}, "n_u", "n_v"}};
}

// The difference of two φ₀ in degrees, modulo 180°.
inline double angle_difference(double a, double b) {
  const double d = std::fmod(std::fabs(a - b), 180.0);
  return std::min(d, 180.0 - d);
}

}  // namespace brdffit::test
