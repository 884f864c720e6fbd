// The checks of a measured BRDF for `brdffit info` (measured_brdf.h).
#include "brdffit/measured_brdf.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <fmt/format.h>

#include "brdffit/rusinkiewicz.h"

namespace brdffit {

Rgb<double> directional_albedo(const MeasuredBrdf& brdf, const Vec3& v) {
  const int n = 128;
  Rgb<double> sum = Rgb<double>::Zero();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      // Cosine-weighted: pdf = cosθ/π, so ∫ f cosθ dω = π · mean(f).
      const double u1 = (i + 0.5) / n, u2 = (j + 0.5) / n;
      const double r = std::sqrt(u1), phi = 2 * kPi * u2;
      const Vec3 l(r * std::cos(phi), r * std::sin(phi), std::sqrt(1 - u1));
      sum += brdf.eval(l, v);
    }
  return sum * (kPi / (n * n));
}

namespace {

// A direction above the horizon with cosθ ≥ min_cos, uniform over that cap.
Vec3 random_direction(std::mt19937_64& rng, double min_cos) {
  std::uniform_real_distribution<double> uniform;
  const double z = min_cos + (1.0 - min_cos) * uniform(rng), phi = 2 * kPi * uniform(rng);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

double median_of(std::vector<double> xs) {
  if (xs.empty()) return NAN;
  std::nth_element(xs.begin(), xs.begin() + xs.size() / 2, xs.end());
  return xs[xs.size() / 2];
}

// Values below this fraction of their channel's largest are left out of the ratios below: a
// ratio of two values near zero measures noise (and RGL's clipping of out-of-gamut entries).
constexpr double kRatioFloor = 1e-3;

void check_reciprocity(const MeasuredBrdf& brdf, TableInfo& info) {
  std::mt19937_64 rng(7);
  std::vector<double> abs_log_ratios, tilted_log_ratios, tilted_log_cosines;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 l = random_direction(rng, 0.2), v = random_direction(rng, 0.2);
    const Rgb<double> forward = brdf.eval(l, v), backward = brdf.eval(v, l);
    const double log_cosines = std::log(v.z() / l.z());
    for (int c = 0; c < 3; ++c) {
      const double floor = kRatioFloor * info.max[c];
      if (!(forward[c] > floor && backward[c] > floor)) continue;
      const double log_ratio = std::log(forward[c] / backward[c]);
      abs_log_ratios.push_back(std::abs(log_ratio));
      // Pairs whose cosines differ by a factor above e^0.5: there a table of f·cosθo read as f is
      // off by the whole ln(cosθv/cosθl), a BRDF only by its noise.
      if (log_cosines > 0.5) {
        tilted_log_ratios.push_back(log_ratio);
        tilted_log_cosines.push_back(log_cosines);
      }
    }
  }
  info.reciprocity = median_of(abs_log_ratios);
  info.reciprocity_cosine_share = median_of(tilted_log_ratios) / median_of(tilted_log_cosines);
  // Measured RGL files: 0.02-0.04 for matte ones, up to 0.26 for glossy coatings (noise where the
  // lobe falls off); the shared files read as f·cosθo were 0.3-0.55.
  constexpr double kSuspect = 0.35;
  if (info.reciprocity > kSuspect)
    info.warnings.push_back(fmt::format(
        "not reciprocal: the median |ln f(l,v)/f(v,l)| is {:.3g} (measurements: 0.02 to 0.3)", info.reciprocity));
  if (std::abs(info.reciprocity_cosine_share) > 0.5)
    info.warnings.push_back(
        fmt::format("f(l,v)/f(v,l) tracks (cosθv/cosθl)^{:.2f}: the values look like f·cosθ, not the BRDF f",
                    info.reciprocity_cosine_share));
}

void check_isotropy(const MeasuredBrdf& brdf, TableInfo& info) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> turn(0.0, 2 * kPi);
  const double floor = kRatioFloor * info.max.sum();
  std::vector<double> log_ratios;
  for (int i = 0; i < 1000; ++i) {
    const Vec3 l = random_direction(rng, 0.2), v = random_direction(rng, 0.2);
    const double angle = turn(rng);
    const double before = brdf.eval(l, v).sum(), after = brdf.eval(rotate_z(l, angle), rotate_z(v, angle)).sum();
    if (before > floor && after > floor) log_ratios.push_back(std::abs(std::log(after / before)));
  }
  info.anisotropy = median_of(log_ratios);
}

void check_energy(const MeasuredBrdf& brdf, TableInfo& info) {
  // The quadrature's own error on a Lambertian table is below 1e-3; measurements above 1 by more
  // than a percent reflect more light than they receive.
  constexpr double kAboveOne = 1.01;
  for (const double theta_deg : {0.0, 30.0, 60.0, 75.0}) {
    const double t = theta_deg * kPi / 180;
    const Rgb<double> albedo = directional_albedo(brdf, Vec3(std::sin(t), 0, std::cos(t)));
    info.albedo_by_incidence.push_back({theta_deg, albedo});
    if (albedo.maxCoeff() > kAboveOne)
      info.warnings.push_back(fmt::format(
          "not energy conserving: the directional albedo at θ = {:g}° is {:.3g} {:.3g} {:.3g}, above 1 (a calibration "
          "problem: the table reflects more light than it receives)",
          theta_deg, albedo[0], albedo[1], albedo[2]));
  }
}

}  // namespace

TableInfo MeasuredBrdf::describe() const {
  TableInfo info = this->info();
  check_reciprocity(*this, info);
  check_isotropy(*this, info);
  check_energy(*this, info);
  const double zero_share = info.valid ? double(info.zero) / info.valid : 0.0;
  if (zero_share > 0.2)
    info.warnings.push_back(fmt::format("{:.0f}% of the valid entries are zero in every channel", 100 * zero_share));
  if (info.isotropic && info.anisotropy > 0.1)
    info.warnings.push_back(fmt::format(
        "declared isotropic, but turning both directions about the normal changes f by {:.3g} (median |ln ratio|)",
        info.anisotropy));
  return info;
}

}  // namespace brdffit
