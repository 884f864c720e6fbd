// Ashikhmin-Shirley's specular lobe (Ashikhmin & Shirley 2000), isotropic (nu = nv = n), in the
// convention of Ngan, Durand & Matusik 2005, over a Lambert base (Ngan used a Lambertian instead
// of Ashikhmin-Shirley's coupled diffuse term).
//
//   f = albedo/π + specular · (n+1)/(8π) · (n·h)^n · F(l·h) / ((l·h) · max(n·l, n·v))
//   F = f0 + (1 - f0)(1 - l·h)^5                                          Schlick
// and 0 for the lobe when either direction is below the horizon.
//
// Source and convention (BBM: "NganAshikhminShirley" in include/bsdfmodel/ngan.h is the
// isotropic include/bsdfmodel/ashikhminshirley.h, whose isotropic normalisation is (n+1)/(8π)
// and exponent n, with Schlick's Fresnel taking one reflectance at normal incidence shared by
// the channels, scaled by a per-channel albedo).
//
// Published "NganAshikhminShirley(albedo, fresnelReflectance, sharpness)"
// (ngan_ashikhminshirley.fit) maps 1:1: specular = albedo (per channel), f0 = fresnelReflectance,
// n = sharpness; their Lambertian(albedo) is our albedo (BBM's Lambertian is albedo/π too).
// Their values over MERL: albedo ≤ 0.773, fresnelReflectance ∈ [0.012, 0.999], sharpness
// ∈ [0.5, 78200], inside our bounds.
//
// Energy conserving within the bounds (specular ≤ 1, f0 ≤ 1 so F ≤ 1): with dωl = 4(l·h) dωh,
// the lobe's directional albedo is (n+1)/(2π) ∫ (n·h)^n F (n·l)/max(n·l, n·v) dωh over the h
// that keep l above the horizon, at most (n+1)/(2π) ∫ (n·h)^n dωh = 1 over the hemisphere.
// Contains: lambert exactly (specular = 0); blinn-phong approximately (n = gloss, a start only).
#pragma once

#include "brdffit/models/over_lambert.h"

namespace brdffit::models {

struct AshikhminShirleyLobe : Lobe {
  static constexpr const char* kName = "ashikhmin-shirley";
  static constexpr const char* kSummary =
      "albedo/π + specular·(n+1)/(8π)·(n·h)^n·F/(l·h·max(n·l,n·v)): Ashikhmin-Shirley (Ngan 2005)";
  static constexpr bool kEnergyConserving = true;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 3;
  enum : int { kSpecular = 0, kF0 = 3, kN = 4, kNumValues = 5 };

  static std::vector<ParamSpec> parameters() {
    return {specular_param(1.0, 0.2, "scale of the specular lobe per channel (Ngan's NganAshikhminShirley albedo)"),
            {"f0", 1, 0.0, 1.0, 0.1, "Fresnel reflectance at normal incidence (Schlick; Ngan's fresnelReflectance)",
             Role::F0, false, false, Spacing::Linear, "specular"},
            {"n", 1, 0.1, 100000.0, 50.0, "exponent on n·h: larger is a sharper lobe (Ngan's sharpness)",
             Role::Exponent, false, false, Spacing::Log}};
  }

  static std::vector<Nesting> nestings() {
    return {lambert_under_lobe(),
            {"blinn-phong", {{"n", "gloss"}}, {}, false, "blinn-phong, approximately: n = gloss"}};
  }

  template <class T>
  static Rgb<T> lobe(const T* p, const Vec3& l, const Vec3& v) {
    const double nl = l.z(), nv = v.z();
    const Vec3 h = half_vector(l, v);
    const double lh = l.dot(h);
    const T unscaled = (p[kN] + 1.0) / (8.0 * kPi) * pow_of_direction_term(h.z(), p[kN]) * schlick_fresnel(p[kF0], lh) /
                       (lh * std::max(nl, nv));
    return colour(p + kSpecular) * unscaled;
  }
};
using AshikhminShirley = OverLambert<AshikhminShirleyLobe>;

}  // namespace brdffit::models
