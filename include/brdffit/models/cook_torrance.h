// Cook-Torrance (Cook & Torrance 1982) in the convention of Ngan, Durand & Matusik 2005, over a
// Lambert base.
//
//   f = albedo/π + specular · D(h) · G · F(l·h) / (π (n·l)(n·v))
//   D = exp(-tan²θh/m²) / (π m² cos⁴θh)                     Beckmann, normalised (∫ D cosθh dω = 1)
//   G = min(1, 2(n·h)(n·l)/(l·h), 2(n·h)(n·v)/(v·h))        V-groove masking-shadowing
//   F = f0 + (1 - f0)(1 - l·h)^5                            Schlick
// and 0 for the lobe when either direction is below the horizon.
//
// Source and convention (BBM: "NganCookTorrance" in include/bsdfmodel/ngan.h is a scaled
// microfacet model of include/bsdfmodel/microfacet.h with the Beckmann NDF normalised by 1/π,
// the V-groove G, Schlick's Fresnel and the normalisation constant microfacet_n::Cook = π):
// the denominator is Cook and Torrance's π, not the 4 of Walter et al. 2007. Ngan's "eta" is,
// despite its name, not an index of refraction: BBM's Schlick Fresnel takes its parameter as
// ior::reflectance (the reflectance at normal incidence), one value shared by the channels.
//
// Published "NganCookTorrance(albedo, eta, roughness)" (ngan_cooktorrance.fit) maps 1:1:
// specular = albedo (per channel), f0 = eta, m = roughness; their Lambertian(albedo) is our
// albedo (BBM's Lambertian is albedo/π too). Their values over MERL: albedo ≤ 0.981,
// eta ∈ [0.0017, 0.999], roughness ∈ [0.0051, 0.943], all inside our bounds.
//
// f0 is not linear: specular·F is a product of the two. Not energy conserving: with the π
// denominator the lobe's directional albedo reaches 4/π ≈ 1.27 (specular = f0 = 1, small m).
#pragma once

#include "brdffit/models/cook_terms.h"
#include "brdffit/models/over_lambert.h"

namespace brdffit::models {

struct CookTorranceLobe : Lobe {
  static constexpr const char* kName = "cook-torrance";
  static constexpr const char* kSummary =
      "albedo/π + specular·D·G·F/(π n·l n·v): Beckmann D, V-groove G, Schlick F (Ngan 2005)";
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 3;
  enum : int { kSpecular = 0, kF0 = 3, kM = 4, kNumValues = 5 };

  static std::vector<ParamSpec> parameters() {
    return {specular_param(1.0, 0.2, "scale of the specular lobe per channel (Ngan's NganCookTorrance albedo)"),
            {"f0", 1, 0.0, 1.0, 0.1, "Fresnel reflectance at normal incidence (Schlick); Ngan's 'eta'", Role::F0, false,
             false, Spacing::Linear, "specular"},
            {"m", 1, 0.001, 1.0, 0.2, "Beckmann roughness: RMS slope of the microfacets (Ngan's roughness)",
             Role::Roughness, false, false, Spacing::Log}};
  }

  // The recovery tests' material (model.h): a glossy width as in Ngan's fits. The middle of the
  // log range, m = 0.022, is a near-mirror: there specular scattered by 9 % over 8 noise seeds
  // (26 % at worst, against f0).
  static RecoveryFacts recovery_facts() { return {/*material=*/{"m=0.3"}}; }

  template <class T>
  static Rgb<T> lobe(const T* p, const Vec3& l, const Vec3& v) {
    const double nl = l.z(), nv = v.z();
    const Vec3 h = half_vector(l, v);
    const double nh = h.z(), lh = l.dot(h);
    const T d = beckmann_ndf(nh, p[kM]);
    const T unscaled = d * vgroove_masking(nh, nl, nv, lh) * schlick_fresnel(p[kF0], lh) / (kPi * nl * nv);
    return colour(p + kSpecular) * unscaled;
  }
};
using CookTorrance = OverLambert<CookTorranceLobe>;

}  // namespace brdffit::models
