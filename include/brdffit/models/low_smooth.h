// Löw et al. 2012's smooth-surface ("ABC") model over a Lambert base, in the convention of BBM's
// include/bsdfmodel/lowsmooth.h (the one the published low_lowsmooth_E2.fit values were made for):
//
//   f = albedo/π + A · (1 + B·|l_xy + v_xy|²)^(−C) · F_ck(η, cosθd)
//   cosθd = √(max(0, 1 − ¼|l_xy − v_xy|²))         (BBM's eq. 14 form, projected directions)
// and 0 for the lobe when a direction is below the horizon. F_ck is Cook's dielectric Fresnel
// (cook_terms.h). There is no 1/(n·l n·v): A is an unnormalised scale (values over 1000 are
// common for shiny materials), B and C shape the lobe around the mirror direction.
//
// Published "Aggregate(Lambertian(albedo), LowSmooth(A, B, C, eta))" maps 1:1 onto albedo, A, B,
// C, eta. Reciprocal (symmetric in l and v); not energy conserving (A is unbounded by design).
//
// Contains `lambert` exactly: A = 0 switches the lobe off.
#pragma once

#include "brdffit/models/cook_terms.h"
#include "brdffit/models/over_lambert.h"

namespace brdffit::models {

struct LowSmoothLobe : Lobe {
  static constexpr const char* kName = "low-smooth";
  static constexpr const char* kSummary =
      "albedo/π + A·(1+B|l_xy+v_xy|²)^(−C)·F_ck(η, cosθd): Löw 2012 smooth-surface ABC model (BBM lowsmooth)";
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 4;
  enum : int { kA = 0, kB = 3, kC = 4, kEta = 5, kNumValues = 6 };

  static std::vector<ParamSpec> parameters() {
    return {{"A", 3, 0.0, 10000.0, 1.0, "unnormalised scale of the lobe per channel (Löw's A)", Role::SpecularColour,
             /*linear=*/true},
            {"B", 1, 1.0, 1e7, 100.0, "sharpness: how fast the lobe falls away from the mirror direction (Löw's B)",
             Role::Roughness, false, false, Spacing::Log},
            {"C", 1, 0.0, 3.0, 1.0, "exponent of the fall-off: the shape of the lobe's tail (Löw's C)", Role::Shape},
            {"eta", 1, 1.0, 12.0, 1.5, "index of refraction of Cook's Fresnel (Löw's eta)", Role::F0}};
  }

  static std::vector<Nesting> nestings() { return {lambert_under_lobe("A")}; }

  // The recovery tests' material (model.h): as in Löw's fits. The middle of A's range (0 to 10⁴)
  // is a lobe a thousand times the albedo, under which the samples do not determine the albedo.
  static RecoveryFacts recovery_facts() { return {/*material=*/{"A=3,4,5", "B=50"}}; }

  // Evaluated at the horizon too, as BBM's lowsmooth (its formula is finite there).
  static bool lobe_vanishes(const Vec3& l, const Vec3& v) { return l.z() < 0.0 || v.z() < 0.0; }

  template <class T>
  static Rgb<T> lobe(const T* p, const Vec3& l, const Vec3& v) {
    using std::pow;
    const double sum_x = l.x() + v.x(), sum_y = l.y() + v.y();
    const double diff_x = l.x() - v.x(), diff_y = l.y() - v.y();
    const double cos_theta_d = std::sqrt(std::max(0.0, 1.0 - 0.25 * (diff_x * diff_x + diff_y * diff_y)));
    const T unscaled = pow(1.0 + p[kB] * (sum_x * sum_x + sum_y * sum_y), -p[kC]) * cook_fresnel(p[kEta], cos_theta_d);
    return colour(p + kA) * unscaled;
  }
};
using LowSmooth = OverLambert<LowSmoothLobe>;

}  // namespace brdffit::models
