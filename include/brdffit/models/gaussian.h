// Gaussian specular lobe over a Lambert base.
//
//   f = albedo/π + specular · 1.2·exp(-(θh/m)²),   θh = angle(n, h)
//
// Seed: 004_e79c30797da74a89.txt (brdf_gaussian), used as the specular term of a BRDF. The
// lobe is not normalised (its albedo depends on m), so `specular` is a plain scale. The lobe
// peaks at 1.2·specular whatever m, so a narrow highlight needs a large scale: specular is in
// [0, 1000] (1/sr; the MERL blue-acrylic proxy fits 16 at m = 0.006, and a bound of 10 held it).
// θh is acos of a clamped double: no derivative flows through it, only through m.
// Contains: lambert exactly (specular = 0).
#pragma once

#include <cmath>

#include "brdffit/models/over_lambert.h"

namespace brdffit::models {

struct GaussianLobe : Lobe {
  static constexpr const char* kName = "gaussian";
  static constexpr const char* kSummary = "albedo/π + specular·1.2·exp(-(θh/m)²): Gaussian lobe in the half angle";
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 2;
  enum : int { kSpecular = 0, kM = 3, kNumValues = 4 };

  static std::vector<ParamSpec> parameters() {
    return {specular_param(1000.0, 0.2, "scale of the Gaussian lobe per channel (1/sr)"),
            {"m", 1, 0.005, 1.5, 0.3, "width of the lobe in radians of the half angle", Role::Roughness, false, false,
             Spacing::Log}};
  }

  static std::vector<Nesting> nestings() { return {lambert_under_lobe()}; }

  // The recovery tests' material (model.h): a glossy lobe with a peak a few times the albedo.
  // Under the middle of the ranges' (a peak 1.2·specular of 400-800) the albedo scattered by 1-2 %.
  static RecoveryFacts recovery_facts() { return {/*material=*/{"specular=3,4,5", "m=0.2"}}; }

  // The seed's lobe is a function of h alone, evaluated for any directions.
  static bool lobe_vanishes(const Vec3& /*l*/, const Vec3& /*v*/) { return false; }

  template <class T>
  static Rgb<T> lobe(const T* p, const Vec3& l, const Vec3& v) {
    using std::exp;
    const double theta_h = std::acos(std::min(1.0, half_vector(l, v).z()));
    const T x = theta_h / p[kM];
    return colour(p + kSpecular) * (1.2 * exp(-x * x));
  }
};
using Gaussian = OverLambert<GaussianLobe>;

}  // namespace brdffit::models
