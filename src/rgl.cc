#include "brdffit/rgl.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/rusinkiewicz.h"
#include "brdffit/tensor_file.h"

namespace brdffit {

namespace {

double theta_to_u(double theta) { return std::sqrt(std::max(theta, 0.0) * (2.0 / kPi)); }
double phi_to_u(double phi) { return (phi + kPi) / (2.0 * kPi); }

// acos(d.z) without its loss of precision near the pole.
double elevation(const Vec3& d) {
  return 2.0 * std::asin(std::min(1.0, 0.5 * std::sqrt(d.x() * d.x() + d.y() * d.y() + (d.z() - 1) * (d.z() - 1))));
}

// The index i in [0, n-2] of the interval [values[i], values[i+1]] holding x (clamped).
size_t find_interval(const std::vector<float>& values, double x) {
  const auto upper = std::upper_bound(values.begin() + 1, values.end() - 1, x);
  return static_cast<size_t>(upper - values.begin()) - 1;
}

// A unit-square coordinate scaled to a grid of n vertices: its cell index in [0, n-2] and the
// position inside the cell. Coordinates outside [0,1] (or NaN, from a malformed warp) clamp.
struct CellPosition {
  int index;
  double t;
};
CellPosition cell_of(double u, int n) {
  const double p = (u >= 0.0 ? std::min(u, 1.0) : 0.0) * (n - 1);
  const int index = std::min(static_cast<int>(p), n - 2);
  return {index, p - index};
}

}  // namespace

ParametricGrid2D::ParametricGrid2D(int nx, int ny, std::vector<float> data, std::vector<std::vector<float>> axes,
                                   bool normalise)
    : nx_(nx), ny_(ny), axes_(std::move(axes)), data_(std::move(data)) {
  size_t slices = 1;
  for (const std::vector<float>& axis : axes_) slices *= axis.size();
  if (nx < 2 || ny < 2 || axes_.size() > 3 || slices == 0 || data_.size() != slices * nx * ny)
    throw std::invalid_argument("ParametricGrid2D: data size does not match the grid and parameter axes");
  if (!normalise) return;
  const size_t slice_size = size_t(nx) * ny;
  conditional_cdf_.assign(data_.size(), 0.0);
  marginal_cdf_.assign(slices * ny, 0.0);
  for (size_t s = 0; s < slices; ++s) {
    float* d = &data_[s * slice_size];
    float* conditional = &conditional_cdf_[s * slice_size];
    double* marginal = &marginal_cdf_[s * ny];
    // Trapezoidal integrals of the bilinear density: along x per row, then the row totals along y.
    std::vector<double> row_total(ny);
    for (int y = 0; y < ny; ++y) {
      double sum = 0.0;
      for (int x = 0; x + 1 < nx; ++x) {
        sum += 0.5 * (double(d[y * nx + x]) + d[y * nx + x + 1]);
        conditional[y * nx + x + 1] = static_cast<float>(sum);
      }
      row_total[y] = sum;
    }
    for (int y = 0; y + 1 < ny; ++y) marginal[y + 1] = marginal[y] + 0.5 * (row_total[y] + row_total[y + 1]);
    const double total = marginal[ny - 1];
    const double scale = total > 0.0 ? 1.0 / total : 0.0;
    for (size_t i = 0; i < slice_size; ++i) {
      d[i] = static_cast<float>(d[i] * scale);
      conditional[i] = static_cast<float>(conditional[i] * scale);
    }
    for (int y = 0; y < ny; ++y) marginal[y] *= scale;
  }
}

ParametricGrid2D::SliceBlend ParametricGrid2D::blend(const double* params) const {
  SliceBlend b;
  b.count = 1;
  b.slice[0] = 0;
  b.weight[0] = 1.0;
  for (size_t p = 0; p < axes_.size(); ++p) {
    // Slices are row-major over the parameters: each axis multiplies the slice index, and an
    // axis with more than one value doubles the slices to blend.
    const std::vector<float>& axis = axes_[p];
    if (axis.size() == 1) continue;
    const size_t index = find_interval(axis, params[p]);
    const double t = std::clamp((params[p] - axis[index]) / (axis[index + 1] - axis[index]), 0.0, 1.0);
    const int n = b.count;
    for (int k = 0; k < n; ++k) {
      b.slice[k] = b.slice[k] * axis.size() + index;
      b.slice[n + k] = b.slice[k] + 1;
      b.weight[n + k] = b.weight[k] * t;
      b.weight[k] *= 1.0 - t;
    }
    b.count *= 2;
  }
  return b;
}

template <class Value>
double ParametricGrid2D::at(const std::vector<Value>& table, const SliceBlend& b, size_t slice_size, size_t index) {
  double value = 0.0;
  for (int k = 0; k < b.count; ++k) value += b.weight[k] * table[b.slice[k] * slice_size + index];
  return value;
}

double ParametricGrid2D::eval(double ux, double uy, const double* params) const {
  const SliceBlend b = blend(params);
  const auto [x, wx] = cell_of(ux, nx_);
  const auto [y, wy] = cell_of(uy, ny_);
  const size_t slice_size = size_t(nx_) * ny_, i = size_t(y) * nx_ + x;
  return (1 - wy) * ((1 - wx) * at(data_, b, slice_size, i) + wx * at(data_, b, slice_size, i + 1)) +
         wy * ((1 - wx) * at(data_, b, slice_size, i + nx_) + wx * at(data_, b, slice_size, i + nx_ + 1));
}

std::array<double, 2> ParametricGrid2D::invert(double ux, double uy, const double* params) const {
  const SliceBlend b = blend(params);
  const size_t slice_size = size_t(nx_) * ny_;
  const auto [x, sx] = cell_of(ux, nx_);
  const auto [y, sy] = cell_of(uy, ny_);
  const size_t i = size_t(y) * nx_ + x;
  const double v00 = at(data_, b, slice_size, i), v10 = at(data_, b, slice_size, i + 1);
  const double v01 = at(data_, b, slice_size, i + nx_), v11 = at(data_, b, slice_size, i + nx_ + 1);
  // x: the conditional CDF of the row (interpolated between the patch's two rows) at sx,
  // integrating the bilinear density across the patch, over the row's total.
  const double c0 = (1 - sy) * v00 + sy * v01, c1 = (1 - sy) * v10 + sy * v11;
  double cdf_x = sx * (c0 + 0.5 * sx * (c1 - c0));
  cdf_x += (1 - sy) * at(conditional_cdf_, b, slice_size, i) + sy * at(conditional_cdf_, b, slice_size, i + nx_);
  const size_t row_end = size_t(y) * nx_ + nx_ - 1;
  const double r0 = at(conditional_cdf_, b, slice_size, row_end),
               r1 = at(conditional_cdf_, b, slice_size, row_end + nx_);
  const double row_total = (1 - sy) * r0 + sy * r1;
  // y: the marginal CDF at the patch's row plus the integral across the patch.
  double cdf_y = sy * (r0 + 0.5 * sy * (r1 - r0));
  cdf_y += at(marginal_cdf_, b, ny_, y);
  return {row_total > 0.0 ? cdf_x / row_total : 0.0, cdf_y};
}

RglBrdf RglBrdf::read(const std::string& path) { return parse(read_file(path), path); }

RglBrdf RglBrdf::parse(const std::string& bytes, const std::string& name) {
  using Type = TensorFile::Type;
  TensorFile file = TensorFile::parse(bytes, name);
  const auto& theta_i = file.field("theta_i", Type::Float32, 1);
  const auto& phi_i = file.field("phi_i", Type::Float32, 1);
  const auto& ndf = file.field("ndf", Type::Float32, 2);
  const auto& sigma = file.field("sigma", Type::Float32, 2);
  const auto& vndf = file.field("vndf", Type::Float32, 4);
  const auto& rgb = file.field("rgb", Type::Float32, 5);
  const auto& description = file.field("description", Type::UInt8, 1);
  file.field("jacobian", Type::UInt8, 1);  // part of the format, though evaluation does not use it
  file.expect_shape("jacobian", {1});

  const uint64_t n_phi = phi_i.shape[0], n_theta = theta_i.shape[0];
  if (n_phi < 1 || n_theta < 2)
    fail("{}: field 'phi_i' needs at least 1 value and 'theta_i' at least 2 (they have {} and {})", name, n_phi,
         n_theta);
  file.expect_shape("vndf", {n_phi, n_theta, 0, 0});
  file.expect_shape("rgb", {n_phi, n_theta, 3, 0, 0});
  // Every table is bilinear between vertices, so needs at least 2x2 of them.
  for (const auto& [field_name, f] : {std::pair{"ndf", &ndf}, {"sigma", &sigma}, {"vndf", &vndf}, {"rgb", &rgb}}) {
    const uint64_t ny = f->shape[f->shape.size() - 2], nx = f->shape.back();
    if (ny < 2 || nx < 2) fail("{}: field '{}' has a {}x{} table, at least 2x2 needed", name, field_name, ny, nx);
  }

  // Values: finite; densities non-negative, the projected area (which divides f) positive.
  auto count_values = [](const std::vector<float>& values, auto&& predicate) {
    return std::count_if(values.begin(), values.end(), predicate);
  };
  const std::vector<float> theta_axis = theta_i.floats(), phi_axis = phi_i.floats();
  // Released from the file and moved into the grids below, not copied: a large file's tables
  // are held once each.
  std::vector<float> ndf_values = file.release_floats("ndf"), sigma_values = file.release_floats("sigma");
  std::vector<float> vndf_values = file.release_floats("vndf"), rgb_values = file.release_floats("rgb");
  for (const auto& [field_name, values] : {std::pair{"theta_i", &theta_axis},
                                           {"phi_i", &phi_axis},
                                           {"ndf", &ndf_values},
                                           {"sigma", &sigma_values},
                                           {"vndf", &vndf_values},
                                           {"rgb", &rgb_values}}) {
    const auto nan = count_values(*values, [](float x) { return std::isnan(x); });
    const auto infinite = count_values(*values, [](float x) { return std::isinf(x); });
    if (nan + infinite > 0) fail("{}: field '{}' has {} NaN and {} infinite values", name, field_name, nan, infinite);
  }
  for (const auto& [field_name, values] : {std::pair{"ndf", &ndf_values}, {"vndf", &vndf_values}})
    if (const auto negative = count_values(*values, [](float x) { return x < 0.0f; }))
      fail("{}: field '{}' has {} negative values (it is a density)", name, field_name, negative);
  if (const auto non_positive = count_values(sigma_values, [](float x) { return !(x > 0.0f); }))
    fail("{}: field 'sigma' has {} values that are not positive (the projected area divides f)", name, non_positive);
  for (const auto& [field_name, axis] : {std::pair{"theta_i", &theta_axis}, {"phi_i", &phi_axis}})
    if (std::adjacent_find(axis->begin(), axis->end(), std::greater_equal<float>()) != axis->end())
      fail("{}: field '{}' must be strictly ascending", name, field_name);

  RglBrdf brdf;
  brdf.path_ = name;
  brdf.description_.assign(description.bytes.begin(), description.bytes.end());
  brdf.isotropic_ = n_phi <= 2;  // the public loader's rule
  if (!brdf.isotropic_ && std::lround(2 * kPi / (phi_axis.back() - phi_axis.front())) != 1)
    fail("{}: anisotropic RGL file whose φi grid spans {:.4g} rad, not 2π (symmetry-reduced files are not supported)",
         name, phi_axis.back() - phi_axis.front());
  brdf.incident_resolution_ = {n_phi, n_theta};
  // Entries (per incident direction and grid vertex) that are 0 or clipped to 0 in every channel.
  const size_t entry_size = size_t(rgb.shape[3]) * rgb.shape[4];
  for (size_t incident = 0; incident < n_phi * n_theta; ++incident)
    for (size_t i = 0; i < entry_size; ++i) {
      const float* channels = &rgb_values[incident * 3 * entry_size + i];
      if (channels[0] <= 0.0f && channels[entry_size] <= 0.0f && channels[2 * entry_size] <= 0.0f) ++brdf.zero_entries_;
    }
  brdf.rgb_resolution_ = {rgb.shape[3], rgb.shape[4]};
  auto grid = [](const TensorFile::Field& f, std::vector<float> values, std::vector<std::vector<float>> axes,
                 bool normalise) {
    return ParametricGrid2D(int(f.shape.back()), int(f.shape[f.shape.size() - 2]), std::move(values), std::move(axes),
                            normalise);
  };
  brdf.ndf_ = grid(ndf, std::move(ndf_values), {}, false);
  brdf.sigma_ = grid(sigma, std::move(sigma_values), {}, false);
  brdf.vndf_ = grid(vndf, std::move(vndf_values), {phi_axis, theta_axis}, true);
  brdf.rgb_ = grid(rgb, std::move(rgb_values), {phi_axis, theta_axis, {0, 1, 2}}, false);
  return brdf;
}

Rgb<double> RglBrdf::tabulated(const Vec3& wi, const Vec3& wo) const {
  if (!(wi.z() > 0.0 && wo.z() > 0.0)) return Rgb<double>::Zero();
  const Vec3 wm = (wi + wo).normalized();
  const double theta_i = elevation(wi), phi_i = std::atan2(wi.y(), wi.x());
  const double theta_m = elevation(wm), phi_m = std::atan2(wm.y(), wm.x());
  const double um_x = theta_to_u(theta_m);
  double um_y = phi_to_u(isotropic_ ? phi_m - phi_i : phi_m);
  um_y -= std::floor(um_y);
  const double incident[2] = {phi_i, theta_i};
  const std::array<double, 2> sample = vndf_.invert(um_x, um_y, incident);
  const double scale =
      ndf_.eval(um_x, um_y, nullptr) / (4.0 * sigma_.eval(theta_to_u(theta_i), phi_to_u(phi_i), nullptr));
  Rgb<double> value;
  for (int c = 0; c < 3; ++c) {
    const double incident_and_channel[3] = {phi_i, theta_i, double(c)};
    value[c] = std::max(0.0, rgb_.eval(sample[0], sample[1], incident_and_channel)) * scale;
  }
  return value;
}

Rgb<double> RglBrdf::eval(const Vec3& l, const Vec3& v) const {
  const Vec3 light = l.normalized();
  // The table at (wi = view, wo = light) holds f·cosθ of the light (see the head of rgl.h).
  return tabulated(v.normalized(), light) / std::max(light.z(), kMinCosLight);
}

SampleSet RglBrdf::samples(const SamplingOptions& options) const {
  const HalfDiffGrid grid{kSampleGrid[0], kSampleGrid[1], kSampleGrid[2], kPi};
  AzimuthSpread spread;
  SampleSet set;
  set.source = path_;
  set.weighting = "solid-angle";
  set.isotropic = isotropic_;
  grid.for_each_bin_above_horizon([&](int, int, int, Vec3 l, Vec3 v, double weight) {
    spread.turn(l, v);
    // The shaded value f·cosθl is what the table holds: no division by a vanishing cosine.
    if (within_angle_limit(options, l, v)) set.samples.push_back({l, v, tabulated(v, l), weight});
  });
  apply_sampling_options(set, options);
  return set;
}

TableInfo RglBrdf::info() const {
  TableInfo info;
  info.format = "rgl";
  info.resolution = fmt::format("{}x{} incident, {}x{} rgb ({})", incident_resolution_[0], incident_resolution_[1],
                                rgb_resolution_[0], rgb_resolution_[1], isotropic_ ? "isotropic" : "anisotropic");
  info.valid = incident_resolution_[0] * incident_resolution_[1] * rgb_resolution_[0] * rgb_resolution_[1];
  info.zero = zero_entries_;
  info.isotropic = isotropic_;
  info.isotropy = "file";  // its φi grid: one or two values
  // The range of f within 80° of the normal: beyond, f is a small tabulated value over a
  // vanishing cosine.
  SamplingOptions within_80;
  within_80.max_angle_deg = 80;
  for (const Sample& s : samples(within_80).samples) info.include_in_range(s.value / s.l.z());
  info.albedo = directional_albedo(*this, Vec3(0, 0, 1));
  return info;
}

}  // namespace brdffit
