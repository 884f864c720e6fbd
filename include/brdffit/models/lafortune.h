// One Lafortune lobe (Lafortune et al. 1997), isotropic, in the convention of Ngan et al. 2005,
// over a Lambert base.
//
//   f = albedo/π + specular · (n+2)/(2π) · (max(cxy(lx·vx + ly·vy) + cz·lz·vz, 0) / c)^n,
//   c = max(|cxy|, |cz|)
//
// Ngan normalise the generalised cosine lobe by (n+2)/(2π·c^n); writing it as (…/c)^n keeps
// it finite for the exponents they publish (thousands). Their "NganLafortune(albedo, Cxy, Cz,
// sharpness)" maps to specular = albedo, cxy = Cxy, cz = Cz, n = sharpness; their
// Lambertian(albedo) is our albedo. cxy < 0 < cz is the usual forward-scattering lobe;
// cxy = -cz is a Phong lobe about the mirror direction. One lobe only (Ngan fitted one).
// Under this normalisation only the direction of (cxy, cz) matters, not its length: a fit
// determines their ratio and reports each as not identifiable on its own.
#pragma once

#include "brdffit/models/common.h"

namespace brdffit::models {

struct Lafortune {
  static constexpr const char* kName = "lafortune";
  static constexpr const char* kSummary =
      "albedo/π + specular·(n+2)/(2π)·(max(cxy(lx vx+ly vy)+cz lz vz, 0)/max|c|)^n: one Lafortune lobe (Ngan 2005)";
  static constexpr bool kEnergyConserving = false;
  enum : int { kAlbedo = 0, kSpecular = 3, kCxy = 6, kCz = 7, kN = 8, kNumValues = 9 };

  static std::vector<ParamSpec> parameters() {
    return {albedo_param(), specular_param(1.0, 0.2, "scale of the lobe per channel"),
            {"cxy", 1, -1.0, 1.0, -0.6, "lobe axis weight in the tangent plane (negative: forward scattering)",
             Role::Shape},
            {"cz", 1, 0.01, 1.0, 0.55, "lobe axis weight along the normal", Role::Shape},
            {"n", 1, 0.1, 100000.0, 20.0, "lobe exponent: larger is a sharper lobe", Role::Exponent, false, false,
             Spacing::Log}};
  }

  template <class T>
  static Rgb<T> brdf(const T* p, const Vec3& l, const Vec3& v) {
    const Rgb<T> f = lambert_term(p + kAlbedo);
    if (l.z() <= 0.0 || v.z() <= 0.0) return f;
    const T dot = p[kCxy] * (l.x() * v.x() + l.y() * v.y()) + p[kCz] * (l.z() * v.z());
    const T c = abs_value(p[kCxy]) > abs_value(p[kCz]) ? abs_value(p[kCxy]) : abs_value(p[kCz]);
    const T lobe = (p[kN] + 2.0) / (2.0 * kPi) * pow_pos(T(dot / c), p[kN]);
    return f + colour(p + kSpecular) * lobe;
  }
};

}  // namespace brdffit::models
