// Ward's isotropic Gaussian lobe (Ward 1992, original normalisation) in the convention of Ngan,
// Durand & Matusik 2005, over a Lambert base.
//
//   f = albedo/π + specular · exp(-tan²θh/α²) / (4π α² √((n·l)(n·v)))
// and 0 for the lobe when either direction is below the horizon.
//
// Source and convention (BBM: "NganWard" in include/bsdfmodel/ngan.h is the isotropic case of
// include/bsdfmodel/ward.h): the lobe is the original Ward 1992 one, normalised by
// 4π α² √(cosθi cosθo). Ngan also fitted the Ward-Duer variant (Dür 2006: 4π α² cosθi cosθo;
// "NganWardDuer", include/bsdfmodel/wardduer.h, ngan_wardduer.fit); that is a different BRDF for
// the same parameters and maps onto no brdffit model.
//
// Published "NganWard(albedo, roughness)" (ngan_ward.fit) maps 1:1: specular = albedo (per
// channel), alpha = roughness; their Lambertian(albedo) is our albedo (BBM's Lambertian is
// albedo/π too). Their values over MERL: albedo ≤ 0.279, roughness ∈ [0.0058, 0.5] (0.5 looks
// like the upper limit of Ngan's search), inside our bounds.
//
// Not energy conserving: the lobe's directional albedo is about cosθo for narrow lobes and stays
// below 1 up to θo ≈ 89°, but 1/√(n·v) makes it grow without bound at grazing view (at α = 0.5:
// 1.48 at θo = 89.9°, 4.7 at 89.99°).
// Contains: lambert exactly (specular = 0); cook-torrance and beckmann approximately (alpha = m,
// a start only).
#pragma once

#include "brdffit/models/over_lambert.h"

namespace brdffit::models {

struct WardLobe : Lobe {
  static constexpr const char* kName = "ward";
  static constexpr const char* kSummary = "albedo/π + specular·exp(-tan²θh/α²)/(4πα²√(n·l n·v)): isotropic Ward";
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 2;
  enum : int { kSpecular = 0, kAlpha = 3, kNumValues = 4 };

  static std::vector<ParamSpec> parameters() {
    return {specular_param(1.0, 0.2, "specular reflectance of the lobe per channel (Ngan's NganWard albedo)"),
            {"alpha", 1, 0.001, 1.0, 0.2, "RMS slope of the surface: the width of the lobe (Ngan's roughness)",
             Role::Roughness, false, false, Spacing::Log}};
  }

  static std::vector<Nesting> nestings() {
    return {
        lambert_under_lobe(),
        {"cook-torrance", {{"albedo", "albedo"}, {"alpha", "m"}}, {}, false, "cook-torrance, approximately: alpha = m"},
        {"beckmann", {{"albedo", "albedo"}, {"alpha", "m"}}, {}, false, "beckmann, approximately: alpha = m"}};
  }

  // The recovery tests' material (model.h): a glossy width as in Ngan's fits; the middle of the
  // log range, α = 0.011, is a near-mirror that random directions rarely see.
  static RecoveryFacts recovery_facts() { return {/*material=*/{"alpha=0.15"}}; }

  template <class T>
  static Rgb<T> lobe(const T* p, const Vec3& l, const Vec3& v) {
    const double nl = l.z(), nv = v.z();
    // exp(-tan²θh/α²)/(πα²) is Beckmann's D times cos⁴θh.
    const double nh = half_vector(l, v).z();
    const T unscaled = beckmann_ndf(nh, p[kAlpha]) * std::pow(nh, 4) / (4.0 * std::sqrt(nl * nv));
    return colour(p + kSpecular) * unscaled;
  }
};
using Ward = OverLambert<WardLobe>;

}  // namespace brdffit::models
