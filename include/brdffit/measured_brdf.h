// A measured BRDF, whatever its format (MERL .binary: merl.h, RGL .bsdf: rgl.h), and the summary
// and checks of a table for `brdffit info`. Choosing the reader for a path is measured.h's job.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "brdffit/math.h"
#include "brdffit/samples.h"

namespace brdffit {

// Summary of a table for `brdffit info`.
struct TableInfo {
  std::string format;                                                // "merl", "rgl", "csv"
  std::string resolution;                                            // e.g. "90x90x180"
  size_t valid = 0;                                                  // bins (or rows) with a measurement
  size_t invalid = 0;                                                // bins with none (negative in MERL files)
  Rgb<double> min = Rgb<double>::Zero(), max = Rgb<double>::Zero();  // over valid values of f
  Rgb<double> albedo = Rgb<double>::Zero();                          // directional albedo at normal incidence
  size_t zero = 0;  // valid entries that are 0 in every channel (RGL: clipped out-of-gamut entries too)

  // Checks of the measurement itself (MeasuredBrdf::describe; left NaN/empty for a CSV), so that a
  // user learns a table is suspect before fitting it.
  struct AlbedoAt {
    double theta_deg;
    Rgb<double> albedo;
  };
  std::vector<AlbedoAt> albedo_by_incidence;  // directional albedo at θ = 0, 30, 60, 75°
  // Reciprocity, per channel over random pairs with cosθ ≥ 0.2 both ways and values above 1e-3 of
  // the channel's largest: the median |ln f(l,v)/f(v,l)| (matte measurements a few hundredths,
  // glossy ones up to a few tenths), and where cosθv/cosθl > e^0.5 the median ln f(l,v)/f(v,l)
  // as a share of the median ln(cosθv/cosθl): ≈ 0 for a BRDF, ≈ 1 for values that are f·cosθo.
  double reciprocity = NAN, reciprocity_cosine_share = NAN;
  bool isotropic = true;
  std::string isotropy;               // how that is known: "format" (MERL) or "file" (RGL's φi grid)
  double anisotropy = NAN;            // median |ln f(R l, R v)/f(l, v)| over random turns R about the normal
  std::vector<std::string> warnings;  // one line each: what makes the measurement suspect

  // Widens [min, max] to include a valid value (the first one sets both).
  void include_in_range(const Rgb<double>& f) {
    min = has_range_ ? Rgb<double>(min.cwiseMin(f)) : f;
    max = has_range_ ? Rgb<double>(max.cwiseMax(f)) : f;
    has_range_ = true;
  }

 private:
  bool has_range_ = false;
};

// A measured BRDF that can be evaluated at any pair of directions.
class MeasuredBrdf {
 public:
  virtual ~MeasuredBrdf() = default;
  virtual const std::string& path() const = 0;
  virtual TableInfo info() const = 0;
  // info() and the checks of the measurement itself: reciprocity, directional albedo by
  // incidence (above 1: not energy conserving), the share of zero entries, isotropy.
  TableInfo describe() const;
  // f(l, v) in 1/sr for unit directions in the local frame (n = +z); zero below the horizon.
  virtual Rgb<double> eval(const Vec3& l, const Vec3& v) const = 0;
  // The samples a fit uses (values are f·cosθi), with this source's weights.
  virtual SampleSet samples(const SamplingOptions& options) const = 0;
};

// ∫ f(l, v) cosθl dωl over the hemisphere for a fixed v: the fraction of light from v reflected
// (by reciprocity, also the albedo for light arriving from v). Stratified cosine-weighted
// quadrature with 128x128 points.
Rgb<double> directional_albedo(const MeasuredBrdf& brdf, const Vec3& v);

}  // namespace brdffit
