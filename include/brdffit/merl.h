// MERL BRDF database tables (Matusik et al. 2003, "A Data-Driven Reflectance Model").
//
// File layout: three int32 dimensions (θh, θd, φd bins: 90, 90, 180; 360 φd bins also occur),
// then float64 blocks for R, G and B, each θh-major: index = (iθh·nθd + iθd)·nφd + iφd.
// Stored values times the channel scales 1/1500, 1.15/1500, 1.66/1500 give f in 1/sr;
// negative values mark bins with no measurement (below the horizon, or not measured).
// Bins (as in MERL's BRDFRead.cpp), for the half/difference angles of rusinkiewicz.h:
//   iθh = ⌊√(θh/(π/2))·90⌋   (square-root spacing: most bins near the specular peak)
//   iθd = ⌊θd/(π/2)·90⌋
//   iφd = ⌊φd/π·180⌋ with φd folded into [0, π) (reciprocity: φd and φd+π are the same bin);
//         for 360 bins, ⌊φd/2π·360⌋ with φd in [0, 2π)
// each index clamped to its range. A bin's value belongs to its centre (index + ½ in each of
// the coordinates above); trilinear lookups interpolate between centres in those coordinates.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "brdffit/measured_brdf.h"
#include "brdffit/rusinkiewicz.h"

namespace brdffit {

enum class Interpolation { Nearest, Trilinear };

class MerlTable final : public MeasuredBrdf {
 public:
  static constexpr double kScale[3] = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

  // Reads a file; throws Error naming the file and the problem (short or long for its header,
  // wrong dimensions, NaN or infinite values).
  static MerlTable read(const std::string& path);
  // The size of the file whose first bytes are `head` (at least the 12-byte header), as its
  // dimensions imply; throws Error naming `name` when they are not a MERL table's.
  static uint64_t file_size(const std::string& head, const std::string& name);
  // Parses the bytes of a file called `name` (for messages).
  static MerlTable parse(const std::string& bytes, const std::string& name);

  // Writes the table as read, atomically: the bytes equal those of the file it came from.
  void write(const std::string& path) const;

  const std::string& path() const override { return path_; }
  TableInfo info() const override;
  Rgb<double> eval(const Vec3& l, const Vec3& v) const override { return lookup(l, v, Interpolation::Trilinear); }
  // Every valid bin whose centre pair lies above the horizon (and within the angle limit), with
  // the solid-angle measure of the bin as its weight (HalfDiffGrid::weight).
  SampleSet samples(const SamplingOptions& options) const override;

  // f in 1/sr; zero below the horizon. Directions need not be normalised. Nearest: the bin
  // holding the pair, zero when it has no measurement. Trilinear: the eight surrounding bin
  // centres (φd wraps around, θh and θd clamp at the table's ends), leaving out neighbours
  // without a measurement and renormalising the weights of the others.
  Rgb<double> lookup(const Vec3& l, const Vec3& v, Interpolation interpolation) const;

  int theta_h_bins() const { return dims_[0]; }
  int theta_d_bins() const { return dims_[1]; }
  int phi_d_bins() const { return dims_[2]; }
  size_t bins() const { return static_cast<size_t>(dims_[0]) * dims_[1] * dims_[2]; }
  size_t invalid_bins() const { return invalid_; }
  // The stored (unscaled) value of channel c in a bin.
  double raw(int channel, size_t bin) const { return raw_[channel * bins() + bin]; }
  size_t bin_index(int i_theta_h, int i_theta_d, int i_phi_d) const {
    return (static_cast<size_t>(i_theta_h) * dims_[1] + i_theta_d) * dims_[2] + i_phi_d;
  }
  // The table's bins (centres and weights).
  HalfDiffGrid grid() const;

 private:
  MerlTable() = default;
  bool valid(size_t bin) const;
  Rgb<double> value(size_t bin) const;  // f of a bin: the stored values times the scales
  // Continuous bin coordinates of a direction pair (bin centres at integers).
  std::array<double, 3> coordinates(const Vec3& l, const Vec3& v) const;

  std::string path_;
  std::array<int, 3> dims_{};
  std::vector<double> raw_;  // R, G, B blocks as stored
  size_t invalid_ = 0;       // bins with a negative value in any channel
};

// Writes a MERL table (90x90xphi_d_bins, phi_d_bins 180 or 360) of f(l, v) in 1/sr at every bin
// centre, atomically; bins whose centre lies below the horizon get -1 as in MERL files. Throws
// Error naming the file when f is negative or not finite at a centre above the horizon (a
// negative value would read back as a bin without a measurement).
void write_merl(const std::string& path, const std::function<Rgb<double>(const Vec3& l, const Vec3& v)>& brdf,
                int phi_d_bins = 180);

}  // namespace brdffit
