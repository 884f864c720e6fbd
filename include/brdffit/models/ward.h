// Ward's isotropic Gaussian lobe (Ward 1992) in the convention of Ngan et al. 2005, over a
// Lambert base.
//
//   f = albedo/π + specular · exp(-tan²θh/α²) / (4π α² √((n·l)(n·v)))
//
// Ngan's published "NganWard(albedo, roughness)" (ngan_ward.fit; the original Ward
// normalisation, not Ward-Duer's 1/(n·l n·v)) maps to specular = albedo, alpha = roughness;
// their Lambertian(albedo) is our albedo. The 1/√(n·l n·v) factor lets the albedo exceed 1 at
// grazing angles, so the lobe is not strictly energy conserving.
#pragma once

#include "brdffit/models/common.h"

namespace brdffit::models {

struct Ward {
  static constexpr const char* kName = "ward";
  static constexpr const char* kSummary = "albedo/π + specular·exp(-tan²θh/α²)/(4πα²√(n·l n·v)): isotropic Ward";
  static constexpr bool kEnergyConserving = false;
  enum : int { kAlbedo = 0, kSpecular = 3, kAlpha = 6, kNumValues = 7 };

  static std::vector<ParamSpec> parameters() {
    return {albedo_param(), specular_param(1.0, 0.2, "specular reflectance of the lobe per channel"),
            {"alpha", 1, 0.001, 1.0, 0.2, "RMS slope of the surface: the width of the lobe", Role::Roughness, false,
             false, Spacing::Log}};
  }

  template <class T>
  static Rgb<T> brdf(const T* p, const Vec3& l, const Vec3& v) {
    Rgb<T> f = lambert_term(p + kAlbedo);
    const double nl = l.z(), nv = v.z();
    if (nl <= 0.0 || nv <= 0.0) return f;
    // exp(-tan²θh/α²)/(πα²) is Beckmann's D times cos⁴θh.
    const double nh = half_vector(l, v).z();
    const T lobe = beckmann_ndf(nh, p[kAlpha]) * std::pow(nh, 4) / (4.0 * std::sqrt(nl * nv));
    return f + colour(p + kSpecular) * lobe;
  }
};

}  // namespace brdffit::models
