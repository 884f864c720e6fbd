#include "brdffit/merl.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "brdffit/error.h"
#include "brdffit/io.h"

namespace brdffit {

namespace {

constexpr double kHalfPi = kPi / 2;
constexpr size_t kHeaderBytes = 3 * sizeof(int32_t);

// The φd period of a table: π for 180 bins (reciprocity folds φd+π onto φd), 2π for 360.
double phi_d_period(int phi_d_bins) { return phi_d_bins == 360 ? 2 * kPi : kPi; }

double degrees(double radians) { return radians * 180.0 / kPi; }

// The bytes of a MERL file: the header, then the R, G and B blocks.
std::string merl_file_bytes(const std::array<int, 3>& dims, const std::vector<double>& raw) {
  const int32_t header[3] = {dims[0], dims[1], dims[2]};
  std::string bytes(kHeaderBytes + raw.size() * sizeof(double), '\0');
  std::memcpy(bytes.data(), header, kHeaderBytes);
  std::memcpy(bytes.data() + kHeaderBytes, raw.data(), raw.size() * sizeof(double));
  return bytes;
}

}  // namespace

MerlTable MerlTable::read(const std::string& path) { return parse(read_file(path), path); }

uint64_t MerlTable::file_size(const std::string& head, const std::string& name) {
  if (head.size() < kHeaderBytes)
    fail("{}: not a MERL table: {} bytes, shorter than the 12-byte header", name, head.size());
  int32_t dims[3];
  std::memcpy(dims, head.data(), kHeaderBytes);
  if (dims[0] != 90 || dims[1] != 90 || (dims[2] != 180 && dims[2] != 360))
    fail("{}: not a MERL table: dimensions {}x{}x{}, expected 90x90x180 or 90x90x360", name, dims[0], dims[1], dims[2]);
  return kHeaderBytes + uint64_t{3} * dims[0] * dims[1] * dims[2] * sizeof(double);
}

MerlTable MerlTable::parse(const std::string& bytes, const std::string& name) {
  const size_t expected = file_size(bytes, name);
  int32_t dims[3];
  std::memcpy(dims, bytes.data(), kHeaderBytes);
  MerlTable table;
  table.path_ = name;
  table.dims_ = {dims[0], dims[1], dims[2]};
  if (bytes.size() < expected)
    fail("{}: truncated MERL table: {} bytes, the {}x{}x{} header needs {}", name, bytes.size(), dims[0], dims[1],
         dims[2], expected);
  if (bytes.size() > expected)
    fail("{}: oversized MERL table: {} bytes, the {}x{}x{} header needs {} ({} extra)", name, bytes.size(), dims[0],
         dims[1], dims[2], expected, bytes.size() - expected);
  table.raw_.resize(3 * table.bins());
  std::memcpy(table.raw_.data(), bytes.data() + kHeaderBytes, table.raw_.size() * sizeof(double));

  const size_t nan = std::count_if(table.raw_.begin(), table.raw_.end(), [](double x) { return std::isnan(x); });
  const size_t infinite = std::count_if(table.raw_.begin(), table.raw_.end(), [](double x) { return std::isinf(x); });
  if (nan + infinite > 0) {
    const size_t first =
        std::find_if(table.raw_.begin(), table.raw_.end(), [](double x) { return !std::isfinite(x); }) -
        table.raw_.begin();
    fail("{}: {} NaN and {} infinite values in the MERL table (the first in channel {} of bin {})", name, nan, infinite,
         "RGB"[first / table.bins()], first % table.bins());
  }
  for (size_t bin = 0; bin < table.bins(); ++bin) table.invalid_ += !table.valid(bin);
  return table;
}

void MerlTable::write(const std::string& path) const { write_file_atomic(path, merl_file_bytes(dims_, raw_)); }

bool MerlTable::valid(size_t bin) const {
  return raw_[bin] >= 0.0 && raw_[bins() + bin] >= 0.0 && raw_[2 * bins() + bin] >= 0.0;
}

Rgb<double> MerlTable::value(size_t bin) const {
  return {raw_[bin] * kScale[0], raw_[bins() + bin] * kScale[1], raw_[2 * bins() + bin] * kScale[2]};
}

HalfDiffGrid MerlTable::grid() const { return {dims_[0], dims_[1], dims_[2], phi_d_period(dims_[2])}; }

std::array<double, 3> MerlTable::coordinates(const Vec3& l, const Vec3& v) const {
  const HalfDiff a = to_half_diff(l, v);
  const double period = phi_d_period(dims_[2]);
  double phi_d = std::fmod(a.phi_d, period);
  if (phi_d < 0) phi_d += period;
  return {std::sqrt(std::max(a.theta_h, 0.0) / kHalfPi) * dims_[0] - 0.5, a.theta_d / kHalfPi * dims_[1] - 0.5,
          phi_d / period * dims_[2] - 0.5};
}

Rgb<double> MerlTable::lookup(const Vec3& l, const Vec3& v, Interpolation interpolation) const {
  if (!(l.z() > 0.0 && v.z() > 0.0)) return Rgb<double>::Zero();
  const std::array<double, 3> x = coordinates(l.normalized(), v.normalized());
  auto clamp_index = [](int i, int n) { return std::clamp(i, 0, n - 1); };
  auto wrap_index = [](int i, int n) { return ((i % n) + n) % n; };  // φd is periodic
  auto bin_at = [&](const int(&i)[3]) {
    return bin_index(clamp_index(i[0], dims_[0]), clamp_index(i[1], dims_[1]), wrap_index(i[2], dims_[2]));
  };

  if (interpolation == Interpolation::Nearest) {
    // The bin holding the pair: coordinates round to the nearest centre, as ⌊·⌋ of the
    // edge-based coordinates in MERL's reader.
    const int nearest[3] = {static_cast<int>(std::floor(x[0] + 0.5)), static_cast<int>(std::floor(x[1] + 0.5)),
                            static_cast<int>(std::floor(x[2] + 0.5))};
    const size_t bin = bin_at(nearest);
    return valid(bin) ? value(bin) : Rgb<double>::Zero();
  }
  Rgb<double> sum = Rgb<double>::Zero();
  double weight_sum = 0.0;
  const int base[3] = {static_cast<int>(std::floor(x[0])), static_cast<int>(std::floor(x[1])),
                       static_cast<int>(std::floor(x[2]))};
  for (int corner = 0; corner < 8; ++corner) {
    double weight = 1.0;
    int index[3];
    for (int axis = 0; axis < 3; ++axis) {
      const int offset = (corner >> axis) & 1;
      const double t = x[axis] - base[axis];
      weight *= offset ? t : 1.0 - t;
      index[axis] = base[axis] + offset;
    }
    if (weight <= 0.0) continue;
    const size_t bin = bin_at(index);
    if (!valid(bin)) continue;
    sum += weight * value(bin);
    weight_sum += weight;
  }
  return weight_sum > 0.0 ? Rgb<double>(sum / weight_sum) : Rgb<double>::Zero();
}

SampleSet MerlTable::samples(const SamplingOptions& options) const {
  SampleSet set;
  set.source = path_;
  set.weighting = "solid-angle";
  set.isotropic = true;  // the format stores no φh
  set.samples.reserve(bins() - invalid_);
  const HalfDiffGrid g = grid();
  AzimuthSpread spread;
  g.for_each_bin_above_horizon([&](int ih, int id, int ip, Vec3 l, Vec3 v, double weight) {
    const size_t bin = bin_index(ih, id, ip);
    spread.turn(l, v);
    if (valid(bin) && within_angle_limit(options, l, v)) set.samples.push_back({l, v, value(bin) * l.z(), weight});
  });
  apply_sampling_options(set, options);
  return set;
}

TableInfo MerlTable::info() const {
  TableInfo info;
  info.format = "merl";
  info.resolution = std::to_string(dims_[0]) + "x" + std::to_string(dims_[1]) + "x" + std::to_string(dims_[2]);
  info.invalid = invalid_;
  info.valid = bins() - invalid_;
  for (size_t bin = 0; bin < bins(); ++bin)
    if (valid(bin)) {
      const Rgb<double> f = value(bin);
      info.include_in_range(f);
      if ((f.array() <= 0.0).all()) ++info.zero;
    }
  info.isotropic = true;
  info.isotropy = "format";  // MERL stores no φh
  info.albedo = directional_albedo(*this, Vec3(0, 0, 1));
  return info;
}

void write_merl(const std::string& path, const std::function<Rgb<double>(const Vec3& l, const Vec3& v)>& brdf,
                int phi_d_bins) {
  if (phi_d_bins != 180 && phi_d_bins != 360) fail("{}: MERL tables have 180 or 360 φd bins, not {}", path, phi_d_bins);
  const std::array<int, 3> dims = {90, 90, phi_d_bins};
  const HalfDiffGrid grid{dims[0], dims[1], dims[2], phi_d_period(phi_d_bins)};
  const size_t bins = size_t(dims[0]) * dims[1] * dims[2];
  std::vector<double> raw(3 * bins, -1.0);  // -1: no measurement (below the horizon)
  grid.for_each_bin_above_horizon([&](int ih, int id, int ip, const Vec3& l, const Vec3& v, double /*weight*/) {
    const Rgb<double> f = brdf(l, v);
    if (!f.allFinite() || (f.array() < 0.0).any()) {
      const HalfDiff a = grid.centre(ih, id, ip);
      fail(
          "{}: cannot write f = ({}, {}, {}) at θh {:.3f}°, θd {:.3f}°, φd {:.3f}°: MERL values must be finite and "
          "non-negative (negative marks a bin without a measurement)",
          path, f[0], f[1], f[2], degrees(a.theta_h), degrees(a.theta_d), degrees(a.phi_d));
    }
    const size_t bin = (size_t(ih) * dims[1] + id) * dims[2] + ip;
    for (int c = 0; c < 3; ++c) raw[c * bins + bin] = f[c] / MerlTable::kScale[c];
  });
  write_file_atomic(path, merl_file_bytes(dims, raw));
}

}  // namespace brdffit
