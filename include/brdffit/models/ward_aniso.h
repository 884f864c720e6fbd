// Ward's anisotropic Gaussian lobe (Ward 1992, "Measuring and modeling anisotropic reflection",
// eq. 5, original normalisation) over a Lambert base, with the tangent frame's rotation about
// the normal fitted. The convention is Ngan, Durand & Matusik 2005's and BBM's
// (include/bsdfmodel/ward.h, whose isotropic case is `ward`):
//
//   f = albedo/π + specular · exp(-((h_x/α_x)² + (h_y/α_y)²)/h_z²) / (4π α_x α_y √((n·l)(n·v)))
//
// and 0 for the lobe when either direction is below the horizon; (h_x, h_y) are the half
// vector's components along the tangent frame turned by phi0 about the normal (common.h). The
// exponent is Ward's -tan²θh (cos²φh/α_x² + sin²φh/α_y²). With α_x = α_y = alpha the model is
// `ward` exactly, whatever phi0.
//
// Contains (nestings): `ward` (α_x = α_y = alpha, exact) and `lambert` (specular = 0, exact).
// Not energy conserving, for the reason given in ward.h (1/√(n·v) at grazing view).
#pragma once

#include "brdffit/models/over_lambert.h"

namespace brdffit::models {

struct WardAnisoLobe : Lobe {
  static constexpr const char* kName = "ward-aniso";
  static constexpr const char* kSummary =
      "albedo/π + specular·exp(-tan²θh(cos²φh/α_x²+sin²φh/α_y²))/(4πα_xα_y√(n·l n·v)): anisotropic Ward, frame "
      "rotation phi0";
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 4;
  enum : int { kSpecular = 0, kAlphaX = 3, kAlphaY = 4, kPhi0 = 5, kNumValues = 6 };

  static std::vector<ParamSpec> parameters() {
    auto width = [](const char* name, const char* meaning) {
      return ParamSpec{name, 1, 0.001, 1.0, 0.2, meaning, Role::Roughness, false, false, Spacing::Log};
    };
    return {specular_param(1.0, 0.2, "specular reflectance of the lobe per channel"),
            width("alpha_x", "RMS slope along the tangent (x) axis"),
            width("alpha_y", "RMS slope along the bitangent (y) axis"), tangent_rotation_param()};
  }

  static std::vector<Nesting> nestings() {
    return {{"ward",
             {{"albedo", "albedo"}, {"specular", "specular"}, {"alpha_x", "alpha"}, {"alpha_y", "alpha"}},
             {{"phi0", 0.0}},
             true,
             "equal widths α_x = α_y = alpha"},
            lambert_under_lobe()};
  }

  template <class T>
  static Rgb<T> lobe(const T* p, const Vec3& l, const Vec3& v) {
    using std::exp;
    const double nl = l.z(), nv = v.z();
    const Vec3 h = half_vector(l, v);
    if (h.z() <= 1e-6) return Rgb<T>::Zero();  // the exponential is 0 in double precision
    const T ax = p[kAlphaX], ay = p[kAlphaY];
    const TangentXY<T> ht = in_tangent_frame(h, p[kPhi0]);
    const T exponent = ((ht.x / ax) * (ht.x / ax) + (ht.y / ay) * (ht.y / ay)) / (h.z() * h.z());
    const T unscaled = exp(-exponent) / (4.0 * kPi * ax * ay * std::sqrt(nl * nv));
    return colour(p + kSpecular) * unscaled;
  }
};
using WardAniso = OverLambert<WardAnisoLobe>;

}  // namespace brdffit::models
