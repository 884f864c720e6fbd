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

}  // namespace

MerlTable MerlTable::read(const std::string& path) { return parse(read_file(path), path); }

MerlTable MerlTable::parse(const std::string& bytes, const std::string& name) {
  if (bytes.size() < kHeaderBytes)
    fail("{}: not a MERL table: {} bytes, shorter than the 12-byte header", name, bytes.size());
  int32_t dims[3];
  std::memcpy(dims, bytes.data(), kHeaderBytes);
  if (dims[0] != 90 || dims[1] != 90 || (dims[2] != 180 && dims[2] != 360))
    fail("{}: not a MERL table: dimensions {}x{}x{}, expected 90x90x180 or 90x90x360", name, dims[0], dims[1], dims[2]);
  MerlTable table;
  table.path_ = name;
  table.dims_ = {dims[0], dims[1], dims[2]};
  const size_t expected = kHeaderBytes + 3 * table.bins() * sizeof(double);
  if (bytes.size() < expected)
    fail("{}: truncated MERL table: {} bytes, the {}x{}x{} header needs {}", name, bytes.size(), dims[0], dims[1], dims[2],
         expected);
  if (bytes.size() > expected)
    fail("{}: oversized MERL table: {} bytes, the {}x{}x{} header needs {} ({} extra)", name, bytes.size(), dims[0],
         dims[1], dims[2], expected, bytes.size() - expected);
  table.raw_.resize(3 * table.bins());
  std::memcpy(table.raw_.data(), bytes.data() + kHeaderBytes, table.raw_.size() * sizeof(double));
  const size_t non_finite =
      std::count_if(table.raw_.begin(), table.raw_.end(), [](double x) { return !std::isfinite(x); });
  if (non_finite > 0) fail("{}: {} NaN or infinite values in the MERL table", name, non_finite);
  for (size_t bin = 0; bin < table.bins(); ++bin) table.invalid_ += !table.valid(bin);
  return table;
}

bool MerlTable::valid(size_t bin) const {
  return raw_[bin] >= 0.0 && raw_[bins() + bin] >= 0.0 && raw_[2 * bins() + bin] >= 0.0;
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
  if (l.z() <= 0.0 || v.z() <= 0.0) return Rgb<double>::Zero();
  const std::array<double, 3> x = coordinates(l.normalized(), v.normalized());
  auto clamp_index = [](int i, int n) { return std::clamp(i, 0, n - 1); };
  auto wrap_index = [](int i, int n) { return ((i % n) + n) % n; };  // φd is periodic
  auto value = [&](size_t bin) {
    return Rgb<double>(raw_[bin] * kScale[0], raw_[bins() + bin] * kScale[1], raw_[2 * bins() + bin] * kScale[2]);
  };

  if (interpolation == Interpolation::Nearest) {
    const size_t bin = bin_index(clamp_index(static_cast<int>(std::floor(x[0] + 0.5)), dims_[0]),
                                 clamp_index(static_cast<int>(std::floor(x[1] + 0.5)), dims_[1]),
                                 wrap_index(static_cast<int>(std::floor(x[2] + 0.5)), dims_[2]));
    return valid(bin) ? value(bin) : Rgb<double>::Zero();
  }
  // Trilinear between the eight surrounding bin centres; neighbours without a measurement are
  // left out and the weights of the others renormalised.
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
    const size_t bin = bin_index(clamp_index(index[0], dims_[0]), clamp_index(index[1], dims_[1]),
                                 wrap_index(index[2], dims_[2]));
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
  set.samples.reserve(bins() - invalid_);
  const HalfDiffGrid g = grid();
  g.for_each_bin_above_horizon([&](int ih, int id, int ip, const Vec3& l, const Vec3& v) {
    const size_t bin = bin_index(ih, id, ip);
    if (!valid(bin)) return;
    Sample s{l, v, {}, g.weight(ih, id, ip)};
    for (int c = 0; c < 3; ++c) s.value[c] = raw_[c * bins() + bin] * kScale[c] * l.z();
    set.samples.push_back(s);
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
    if (valid(bin))
      info.include_in_range(
          Rgb<double>(raw_[bin] * kScale[0], raw_[bins() + bin] * kScale[1], raw_[2 * bins() + bin] * kScale[2]));
  info.albedo = directional_albedo(*this, Vec3(0, 0, 1));
  return info;
}

void write_merl(const std::string& path, const std::function<Rgb<double>(const Vec3& l, const Vec3& v)>& brdf,
                int phi_d_bins) {
  if (phi_d_bins != 180 && phi_d_bins != 360) fail("{}: MERL tables have 180 or 360 φd bins, not {}", path, phi_d_bins);
  const int32_t dims[3] = {90, 90, phi_d_bins};
  const HalfDiffGrid grid{90, 90, phi_d_bins, phi_d_period(phi_d_bins)};
  const size_t bins = size_t(90) * 90 * phi_d_bins;
  std::vector<double> raw(3 * bins);
  for (int ih = 0; ih < 90; ++ih)
    for (int id = 0; id < 90; ++id)
      for (int ip = 0; ip < phi_d_bins; ++ip) {
        const size_t bin = (size_t(ih) * 90 + id) * phi_d_bins + ip;
        Vec3 l, v;
        from_half_diff(grid.centre(ih, id, ip), l, v);
        const bool above = l.z() > 0.0 && v.z() > 0.0;
        const Rgb<double> f = above ? brdf(l, v) : Rgb<double>::Zero();
        for (int c = 0; c < 3; ++c) {
          if (above && !std::isfinite(f[c])) fail("{}: the BRDF to write is not finite at a bin centre", path);
          raw[c * bins + bin] = above ? f[c] / MerlTable::kScale[c] : -1.0;
        }
      }
  std::string bytes(kHeaderBytes + raw.size() * sizeof(double), '\0');
  std::memcpy(bytes.data(), dims, kHeaderBytes);
  std::memcpy(bytes.data() + kHeaderBytes, raw.data(), raw.size() * sizeof(double));
  write_file_atomic(path, bytes);
}

}  // namespace brdffit
