// Löw et al. 2012's Cook-Torrance over a Lambert base: Cook & Torrance 1982 as they wrote it,
// with an index of refraction, in the convention of BBM's include/bsdfmodel/cooktorrance.h
// ("LowCookTorrance" in BBM's low.h):
//
//   f = albedo/π + specular · D · G · F_ck(η, l·h) / (π (n·l)(n·v))
//   D = exp(−tan²θh/m²) / (m² cos⁴θh)                  Beckmann WITHOUT the 1/π of its normalised form
//   G = V-groove masking-shadowing, F_ck = Cook's Fresnel (cook_terms.h)
// and 0 for the lobe when a direction is below the horizon. Compared with our `cook-torrance`
// (Ngan's convention) the differences are D's missing 1/π (so `specular` is π times smaller for
// the same lobe) and Cook's Fresnel with η instead of Schlick's with f0.
//
// Published "Aggregate(Lambertian(albedo), LowCookTorrance(albedo, roughness, eta))"
// (low_cooktorrance_E1/E2.fit) maps onto albedo, specular = their lobe's albedo, m = roughness,
// eta. Reciprocal; not energy conserving.
//
// Contains `lambert` exactly: specular = 0 switches the lobe off.
#pragma once

#include "brdffit/models/cook_terms.h"
#include "brdffit/models/over_lambert.h"

namespace brdffit::models {

struct LowCookTorranceLobe : Lobe {
  static constexpr const char* kName = "low-cook-torrance";
  static constexpr const char* kSummary =
      "albedo/π + specular·D·G·F_ck(η,l·h)/(π n·l n·v): Beckmann D without 1/π, V-groove G, Cook's Fresnel (Löw 2012)";
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 3;
  enum : int { kSpecular = 0, kM = 3, kEta = 4, kNumValues = 5 };

  static std::vector<ParamSpec> parameters() {
    return {specular_param(2.0, 0.1, "scale of the specular lobe per channel (Löw's LowCookTorrance albedo)"),
            {"m", 1, 0.001, 2.5, 0.2, "Beckmann roughness: RMS slope of the microfacets (Löw's roughness)",
             Role::Roughness, false, false, Spacing::Log},
            {"eta", 1, 1.0, 12.0, 1.5, "index of refraction of Cook's Fresnel (Löw's eta)", Role::F0}};
  }

  static std::vector<Nesting> nestings() { return {lambert_under_lobe("specular")}; }

  // The recovery tests' material (model.h): a glossy width as in Löw's fits; at the middle of the
  // log range, a near-mirror, specular scattered by 9 % over 8 noise seeds (against eta).
  static RecoveryFacts recovery_facts() { return {/*material=*/{"m=0.3"}}; }

  template <class T>
  static Rgb<T> lobe(const T* p, const Vec3& l, const Vec3& v) {
    const double nl = l.z(), nv = v.z();
    const Vec3 h = half_vector(l, v);
    const double nh = h.z(), lh = l.dot(h);
    if (lh <= 0.0) return Rgb<T>::Zero();
    // π·beckmann_ndf is D without its 1/π; it cancels the π of the denominator.
    const T unscaled =
        beckmann_ndf(nh, p[kM]) * vgroove_masking(nh, nl, nv, lh) * cook_fresnel(p[kEta], lh) / (nl * nv);
    return colour(p + kSpecular) * unscaled;
  }
};
using LowCookTorrance = OverLambert<LowCookTorranceLobe>;

}  // namespace brdffit::models
