// RGL EPFL material database BRDFs (.bsdf; Dupuy & Jakob 2018, "An Adaptive Parameterization
// for Efficient Material Acquisition and Rendering").
//
// The file stores, per incident direction (φi, θi) of a grid, the RGB BRDF on a grid over a
// 2D "sample" domain [0,1]². A pair (wi, wo) is looked up through the microfacet normal
// wm = normalize(wi + wo): its spherical coordinates map to the unit square as
// u = (√(θm/(π/2)), (φm - φi + π)/(2π) mod 1) (φm alone for anisotropic files), and the
// inverse of the visible-NDF warp (a marginal/conditional 2D distribution, bilinear per patch,
// interpolated linearly over φi and θi) maps u to the sample coordinates of the RGB grid. Then
//   f = rgb(sample) · D(u) / (4 σ(θi, φi)),
// with D the tabulated NDF and σ the projected area, both bilinear over their unit squares.
// Negative RGB (spectral data out of gamut) is clipped to 0 as the public loader does.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "brdffit/measured.h"

namespace brdffit {

// A density over [0,1]² sampled on an nx × ny grid of vertices, bilinear between them, in
// slices indexed by up to three parameters with linear interpolation between slices.
class ParametricGrid2D {
 public:
  ParametricGrid2D() = default;
  // data: [param0][param1]...[y][x]; axes: each parameter's grid values (ascending).
  // normalise: scale each slice to integrate to 1 and build the CDFs invert() needs.
  ParametricGrid2D(int nx, int ny, std::vector<float> data, std::vector<std::vector<float>> axes, bool normalise);

  double eval(double ux, double uy, const double* params) const;
  // The sample coordinates that the warp maps to (ux, uy): the inverse of sampling.
  std::array<double, 2> invert(double ux, double uy, const double* params) const;

 private:
  struct SliceBlend {
    std::array<size_t, 8> slice{};
    std::array<double, 8> weight{};
    int count = 0;
  };
  SliceBlend blend(const double* params) const;
  // Blended value of `table` at `index` within a slice of `slice_size` entries.
  static double at(const std::vector<double>& table, const SliceBlend& b, size_t slice_size, size_t index);

  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<float>> axes_;
  std::vector<double> data_, conditional_cdf_, marginal_cdf_;
};

class RglBrdf final : public MeasuredBrdf {
 public:
  static RglBrdf read(const std::string& path);
  static RglBrdf parse(const std::string& bytes, const std::string& name);

  const std::string& path() const override { return path_; }
  TableInfo info() const override;
  Rgb<double> eval(const Vec3& l, const Vec3& v) const override;
  // Samples on a half/difference grid (θh 64 bins √-spaced, θd 64, φd 90 over [0, π)), each
  // weighted by the solid-angle measure it covers, like MERL bins.
  SampleSet samples(const SamplingOptions& options) const override;

  bool isotropic() const { return isotropic_; }

 private:
  RglBrdf() = default;
  std::string path_, description_;
  bool isotropic_ = true;
  std::array<int, 2> rgb_resolution_{};
  std::array<size_t, 2> incident_resolution_{};
  ParametricGrid2D ndf_, sigma_, vndf_, rgb_;
};

}  // namespace brdffit
