// Ashikhmin-Shirley's anisotropic specular lobe (Ashikhmin & Shirley 2000, "An anisotropic Phong
// BRDF model", eq. 4) in the convention of Ngan, Durand & Matusik 2005 and BBM
// (include/bsdfmodel/ashikhminshirley.h; `ashikhmin-shirley` is its isotropic case) over a
// Lambert base, with the tangent frame's rotation about the normal fitted:
//
//   f = albedo/π + specular · √((n_u+1)(n_v+1))/(8π) · (n·h)^e · F(l·h) / ((l·h) max(n·l, n·v))
//   e = (n_u h_x² + n_v h_y²) / (1 - (n·h)²)       (= n_u cos²φh + n_v sin²φh)
//   F = f0 + (1 - f0)(1 - l·h)^5                   Schlick
// and 0 for the lobe when either direction is below the horizon; (h_x, h_y) are the half
// vector's components along the tangent frame turned by phi0 about the normal (common.h). At
// h = n, where φh is undefined, (n·h)^e = 1 for any e. With n_u = n_v = n the model is
// `ashikhmin-shirley` exactly, whatever phi0.
//
// Contains (nestings): `ashikhmin-shirley` (n_u = n_v = n, exact) and `lambert` (specular = 0, exact).
// Energy conserving: as in ashikhmin_shirley.h the lobe's directional albedo is at most
// √((n_u+1)(n_v+1))/(2π) ∫ (n·h)^e dωh = √(ab)/(2π) ∫ dφ/(a cos²φ + b sin²φ) = 1, with
// a = n_u+1, b = n_v+1.
#pragma once

#include "brdffit/models/over_lambert.h"

namespace brdffit::models {

struct AshikhminShirleyAnisoLobe : Lobe {
  static constexpr const char* kName = "ashikhmin-shirley-aniso";
  static constexpr const char* kSummary =
      "albedo/π + specular·√((n_u+1)(n_v+1))/(8π)·(n·h)^(n_u cos²φh+n_v sin²φh)·F/(l·h·max(n·l,n·v)): "
      "anisotropic Ashikhmin-Shirley 2000, frame rotation phi0";
  static constexpr bool kEnergyConserving = true;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 5;
  enum : int { kSpecular = 0, kF0 = 3, kNu = 4, kNv = 5, kPhi0 = 6, kNumValues = 7 };

  static std::vector<ParamSpec> parameters() {
    auto exponent = [](const char* name, const char* meaning) {
      return ParamSpec{name, 1, 0.1, 100000.0, 50.0, meaning, Role::Exponent, false, false, Spacing::Log};
    };
    return {specular_param(1.0, 0.2, "scale of the specular lobe per channel"),
            {"f0", 1, 0.0, 1.0, 0.1, "Fresnel reflectance at normal incidence (Schlick)", Role::F0},
            exponent("n_u", "exponent along the tangent (x) axis: larger is sharper"),
            exponent("n_v", "exponent along the bitangent (y) axis"),
            tangent_rotation_param()};
  }

  static std::vector<Nesting> nestings() {
    return {{"ashikhmin-shirley",
             {{"albedo", "albedo"}, {"specular", "specular"}, {"f0", "f0"}, {"n_u", "n"}, {"n_v", "n"}},
             {{"phi0", 0.0}},
             true,
             "equal exponents n_u = n_v = n"},
            lambert_under_lobe()};
  }

  template <class T>
  static Rgb<T> lobe(const T* p, const Vec3& l, const Vec3& v) {
    using std::sqrt;
    const double nl = l.z(), nv = v.z();
    const Vec3 h = half_vector(l, v);
    const double lh = l.dot(h), sin2 = h.x() * h.x() + h.y() * h.y();
    const TangentXY<T> ht = in_tangent_frame(h, p[kPhi0]);
    const T e = sin2 > 0.0 ? T((p[kNu] * ht.x * ht.x + p[kNv] * ht.y * ht.y) / sin2) : T(p[kNu]);
    const T unscaled = sqrt((p[kNu] + 1.0) * (p[kNv] + 1.0)) / (8.0 * kPi) * pow_of_direction_term(h.z(), e) *
                       schlick_fresnel(p[kF0], lh) / (lh * std::max(nl, nv));
    return colour(p + kSpecular) * unscaled;
  }
};
using AshikhminShirleyAniso = OverLambert<AshikhminShirleyAnisoLobe>;

}  // namespace brdffit::models
