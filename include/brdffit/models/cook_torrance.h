// Cook-Torrance in the convention of Ngan, Durand & Matusik 2005, over a Lambert base.
//
//   f = albedo/π + specular · D(h) · G · F(l·h) / (π (n·l)(n·v))
//   D = exp(-tan²θh/m²) / (π m² cos⁴θh)                     Beckmann, normalised
//   G = min(1, 2(n·h)(n·l)/(l·h), 2(n·h)(n·v)/(v·h))        V-groove masking-shadowing
//   F = f0 + (1 - f0)(1 - l·h)^5                            Schlick
//
// The denominator π (not the 4 of Walter et al.) is Cook and Torrance's and Ngan's; so the lobe
// is not normalised (its albedo can reach 4/π). Ngan's published "NganCookTorrance(albedo, eta,
// roughness)" maps to specular = albedo, f0 = eta (a reflectance, despite its name: BBM's
// Schlick Fresnel takes the reflectance at normal incidence), m = roughness; their
// Lambertian(albedo) is our albedo (f = albedo/π).
#pragma once

#include "brdffit/models/common.h"

namespace brdffit::models {

struct CookTorrance {
  static constexpr const char* kName = "cook-torrance";
  static constexpr const char* kSummary =
      "albedo/π + specular·D·G·F/(π n·l n·v): Beckmann D, V-groove G, Schlick F (Ngan 2005)";
  static constexpr bool kEnergyConserving = false;
  enum : int { kAlbedo = 0, kSpecular = 3, kF0 = 6, kM = 7, kNumValues = 8 };

  static std::vector<ParamSpec> parameters() {
    return {albedo_param(), specular_param(1.0, 0.2, "scale of the specular lobe per channel"),
            {"f0", 1, 0.0, 1.0, 0.1, "Fresnel reflectance at normal incidence (Schlick); Ngan's 'eta'", Role::F0},
            {"m", 1, 0.001, 1.0, 0.2, "Beckmann roughness: RMS slope of the microfacets", Role::Roughness, false,
             false, Spacing::Log}};
  }

  template <class T>
  static Rgb<T> brdf(const T* p, const Vec3& l, const Vec3& v) {
    Rgb<T> f = lambert_term(p + kAlbedo);
    const double nl = l.z(), nv = v.z();
    if (nl <= 0.0 || nv <= 0.0) return f;
    const Vec3 h = half_vector(l, v);
    const double nh = h.z(), lh = l.dot(h);
    const T d = beckmann_ndf(nh, p[kM]);
    const double g = std::min({1.0, 2.0 * nh * nl / lh, 2.0 * nh * nv / lh});
    const T lobe = d * g * schlick_fresnel(p[kF0], lh) / (kPi * nl * nv);
    return f + colour(p + kSpecular) * lobe;
  }
};

}  // namespace brdffit::models
