// Ashikhmin-Shirley's specular lobe (2000), isotropic, in the convention of Ngan et al. 2005,
// over a Lambert base (Ngan used a Lambertian instead of Ashikhmin-Shirley's coupled diffuse).
//
//   f = albedo/π + specular · (n+1)/(8π) · (n·h)^n · F(l·h) / ((l·h) · max(n·l, n·v))
//   F = f0 + (1 - f0)(1 - l·h)^5                                          Schlick
//
// Ngan's published "NganAshikhminShirley(albedo, fresnelReflectance, sharpness)" maps to
// specular = albedo, f0 = fresnelReflectance, n = sharpness; their Lambertian(albedo) is our
// albedo. The lobe's albedo stays near F but is not bounded by 1 at every angle.
#pragma once

#include "brdffit/models/common.h"

namespace brdffit::models {

struct AshikhminShirley {
  static constexpr const char* kName = "ashikhmin-shirley";
  static constexpr const char* kSummary =
      "albedo/π + specular·(n+1)/(8π)·(n·h)^n·F/(l·h·max(n·l,n·v)): Ashikhmin-Shirley (Ngan 2005)";
  static constexpr bool kEnergyConserving = false;
  enum : int { kAlbedo = 0, kSpecular = 3, kF0 = 6, kN = 7, kNumValues = 8 };

  static std::vector<ParamSpec> parameters() {
    return {albedo_param(), specular_param(1.0, 0.2, "scale of the specular lobe per channel"),
            {"f0", 1, 0.0, 1.0, 0.1, "Fresnel reflectance at normal incidence (Schlick)", Role::F0},
            {"n", 1, 0.1, 100000.0, 50.0, "Phong-like exponent on n·h: larger is a sharper lobe", Role::Exponent, false,
             false, Spacing::Log}};
  }

  template <class T>
  static Rgb<T> brdf(const T* p, const Vec3& l, const Vec3& v) {
    Rgb<T> f = lambert_term(p + kAlbedo);
    const double nl = l.z(), nv = v.z();
    if (nl <= 0.0 || nv <= 0.0) return f;
    const Vec3 h = half_vector(l, v);
    const double lh = l.dot(h);
    const T lobe = (p[kN] + 1.0) / (8.0 * kPi) * pow_of_direction_term(h.z(), p[kN]) * schlick_fresnel(p[kF0], lh) /
                   (lh * std::max(nl, nv));
    return f + colour(p + kSpecular) * lobe;
  }
};

}  // namespace brdffit::models
