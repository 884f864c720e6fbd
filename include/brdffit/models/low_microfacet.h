// Löw et al. 2012's microfacet model over a Lambert base, in the convention of BBM's
// include/bsdfmodel/lowmicrofacet.h with the normalisation of their published fits
// ("LowMicrofacetFit" in BBM's low.h):
//
//   f = albedo/π + A · S(h) · G · F_ck(η, l·h) / (π (n·l)(n·v))
//   S = (1 + B(1 − cosθh))^(−C)                       unnormalised "ABC" distribution of normals
//   G = V-groove masking-shadowing, F_ck = Cook's Fresnel (cook_terms.h)
// and 0 for the lobe when a direction is below the horizon.
//
// About the π: Löw's paper (eq. 15) has no normalisation factor (A is unnormalised anyway), but
// the MERL fits of their supplemental material, hence low_lowmicrofacet_E2.fit, were made with
// Cook-Torrance's 1/π; we keep that π so the published A plug in unchanged.
//
// Published "Aggregate(Lambertian(albedo), LowMicrofacetFit(A, B, C, eta))" maps 1:1.
// Reciprocal; not energy conserving (A is unbounded).
//
// Contains `lambert` exactly: A = 0 switches the lobe off.
#pragma once

#include "brdffit/models/cook_terms.h"
#include "brdffit/models/over_lambert.h"

namespace brdffit::models {

struct LowMicrofacetLobe : Lobe {
  static constexpr const char* kName = "low-microfacet";
  static constexpr const char* kSummary =
      "albedo/π + A·(1+B(1−cosθh))^(−C)·G·F_ck(η,l·h)/(π n·l n·v): Löw 2012 microfacet (BBM LowMicrofacetFit)";
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 4;
  enum : int { kA = 0, kB = 3, kC = 4, kEta = 5, kNumValues = 6 };

  static std::vector<ParamSpec> parameters() {
    return {{"A", 3, 0.0, 10000.0, 1.0, "unnormalised scale of the lobe per channel (Löw's A)", Role::SpecularColour,
             /*linear=*/true},
            {"B", 1, 1.0, 1e7, 100.0, "sharpness of the distribution of facet normals (Löw's B)", Role::Roughness,
             false, false, Spacing::Log},
            {"C", 1, 0.0, 3.0, 1.0, "exponent of the distribution's fall-off: the shape of its tail (Löw's C)",
             Role::Shape},
            {"eta", 1, 1.0, 12.0, 1.5, "index of refraction of Cook's Fresnel (Löw's eta)", Role::F0}};
  }

  static std::vector<Nesting> nestings() { return {lambert_under_lobe("A")}; }

  // The recovery tests' material (model.h): as in Löw's fits. The middle of A's range (0 to 10⁴)
  // is a lobe a thousand times the albedo, under which the samples do not determine the albedo.
  static RecoveryFacts recovery_facts() { return {/*material=*/{"A=3,4,5", "B=50"}}; }

  template <class T>
  static Rgb<T> lobe(const T* p, const Vec3& l, const Vec3& v) {
    using std::pow;
    const double nl = l.z(), nv = v.z();
    const Vec3 h = half_vector(l, v);
    const double nh = h.z(), lh = l.dot(h);
    if (nh <= 0.0 || lh <= 0.0) return Rgb<T>::Zero();
    const T s = pow(1.0 + p[kB] * (1.0 - nh), -p[kC]);
    const T unscaled = s * vgroove_masking(nh, nl, nv, lh) * cook_fresnel(p[kEta], lh) / (kPi * nl * nv);
    return colour(p + kA) * unscaled;
  }
};
using LowMicrofacet = OverLambert<LowMicrofacetLobe>;

}  // namespace brdffit::models
