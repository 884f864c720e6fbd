// RGL EPFL material database BRDFs (.bsdf; Dupuy & Jakob 2018, "An Adaptive Parameterization
// for Efficient Material Acquisition and Rendering"), read as the public RGL loader
// (github.com/rgl-epfl/brdf-loader, powitacq_rgb) reads them.
//
// The file (a tensor file, tensor_file.h) stores, per incident direction on a grid
// (fields phi_i, theta_i), the RGB BRDF on a grid over a 2D "sample" domain [0,1]² (field rgb,
// [φi, θi, 3, ny, nx]). A pair (wi, wo) is looked up through the microfacet normal
// wm = normalize(wi + wo), whose spherical coordinates map to the unit square as
//   u = (√(θm/(π/2)), (φm - φi + π)/(2π) mod 1)        (φm instead of φm - φi if anisotropic)
// and the inverse of the visible-NDF warp (field vndf, [φi, θi, ny, nx]: a marginal/conditional
// 2D distribution, bilinear per patch, interpolated linearly over φi and θi) maps u to the
// sample coordinates of the RGB grid. Then the table's value is
//   f·cosθo = max(rgb(sample), 0) · D(u) / (4 σ(√(θi/(π/2)), (φi + π)/(2π)))
// with D (field ndf) the tabulated NDF and σ (field sigma) the projected area, both bilinear
// over their unit squares. Negative RGB (spectral data out of gamut) is clipped to 0 as the
// public loader does by default. Every grid may have any resolution of at least 2x2.
//
// Convention: the table holds f·cosθo, not f, where (Mitsuba's naming) wi points towards the
// viewer and wo towards the light: the public loader documents its eval() as "Evaluate f_r * cos"
// (powitacq_rgb.h), and its Mitsuba plugin returns that value from a BSDF eval() whose contract is
// f·cosθo, rendered with wi the direction to the sensor. So the table at (wi = v, wo = l) is the
// shaded value f(l,v)·cosθl itself: samples() takes it as it is, and eval() divides it by cosθl to
// return the BRDF f (1/sr), reciprocal like any BRDF. The evidence on the six shared files (brdffit
// info, tests/test_measurement_truth.cc): taken as f, the table's median |ln f(l,v)/f(v,l)| is
// 0.31-0.40 and tracks ln(cosθv/cosθl) (correlation 0.84-0.99); divided by the cosine it is
// 0.02-0.04 on matte files and no longer tracks it. Read as f, white paper's Lambert albedo came out
// 0.42 where its directional albedo at normal incidence is 0.82.
// Files with more than two φi values are anisotropic; they are evaluated when their φi grid
// spans 2π (as the public loader does) and refused otherwise (symmetry-reduced files).
// The fields luminance (for importance sampling) and valid are not used.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "brdffit/measured_brdf.h"

namespace brdffit {

// A function over [0,1]² sampled on an nx × ny grid of vertices, bilinear between them, in
// slices indexed by up to three parameters with linear interpolation between slices.
class ParametricGrid2D {
 public:
  ParametricGrid2D() = default;
  // data: [param0][param1]...[y][x]; axes: each parameter's grid values (strictly ascending).
  // normalise: scale each slice to integrate to 1 and build the CDFs invert() needs.
  // Throws std::invalid_argument when the sizes do not fit together.
  ParametricGrid2D(int nx, int ny, std::vector<float> data, std::vector<std::vector<float>> axes, bool normalise);

  // Coordinates outside [0,1] clamp to the grid; parameters outside an axis clamp to its ends.
  double eval(double ux, double uy, const double* params) const;
  // The sample coordinates that the warp maps to (ux, uy): the inverse of sampling.
  std::array<double, 2> invert(double ux, double uy, const double* params) const;

 private:
  // The (up to 2³) slices to blend for a parameter point, and their weights.
  struct SliceBlend {
    std::array<size_t, 8> slice{};
    std::array<double, 8> weight{};
    int count = 0;
  };
  SliceBlend blend(const double* params) const;
  // Blended value of `table` at `index` within a slice of `slice_size` entries.
  template <class Value>
  static double at(const std::vector<Value>& table, const SliceBlend& b, size_t slice_size, size_t index);

  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<float>> axes_;
  // The tables in single precision, as the file stores them: a large anisotropic file's vndf
  // and its CDF are most of the memory a fit of it takes. Sums are formed in double.
  std::vector<float> data_, conditional_cdf_;
  std::vector<double> marginal_cdf_;
};

class RglBrdf final : public MeasuredBrdf {
 public:
  // Reads a file; throws Error naming the file and the problem (container errors from
  // TensorFile, missing fields, wrong types or shapes, NaN or infinite values, negative
  // densities, non-ascending angle grids, symmetry-reduced anisotropic files).
  static RglBrdf read(const std::string& path);
  static RglBrdf parse(const std::string& bytes, const std::string& name);

  const std::string& path() const override { return path_; }
  const std::string& description() const { return description_; }
  // Valid: the RGB table entries (φi × θi × ny × nx); invalid: 0. The range of f is taken over
  // the sample grid within 80° of the normal, as the tables hold warped values.
  TableInfo info() const override;
  // The BRDF f(l, v) (1/sr): the table's value at wi = v, wo = l divided by cosθl (see above).
  // cosθl is taken as at least kMinCosLight, where the table's values vanish.
  Rgb<double> eval(const Vec3& l, const Vec3& v) const override;
  static constexpr double kMinCosLight = 1e-3;
  // Samples on a regular half/difference grid like a MERL table's (θh 64 bins √-spaced over
  // [0, π/2), θd 64 bins over [0, π/2), φd 90 bins over [0, π)), one at each bin centre whose
  // pair lies above the horizon, weighted by the solid-angle measure of its bin
  // (HalfDiffGrid::weight). Isotropic files put every half vector at φh = 0; anisotropic ones
  // turn each pair about the normal by a low-discrepancy φh so that the set covers φh too.
  SampleSet samples(const SamplingOptions& options) const override;
  static constexpr int kSampleGrid[3] = {64, 64, 90};

  bool isotropic() const { return isotropic_; }

 private:
  RglBrdf() = default;
  // The table's value at (wi, wo), as the public loader's BRDF::eval returns it: f·cosθo.
  Rgb<double> tabulated(const Vec3& wi, const Vec3& wo) const;
  std::string path_, description_;
  bool isotropic_ = true;
  std::array<size_t, 2> incident_resolution_{};  // φi, θi
  std::array<size_t, 2> rgb_resolution_{};       // ny, nx
  size_t zero_entries_ = 0;                      // RGB entries ≤ 0 in every channel
  ParametricGrid2D ndf_, sigma_, vndf_, rgb_;
};

}  // namespace brdffit
