// Pieces shared by the model files: the standard parameters and the Lambert base.
#pragma once

#include <type_traits>

#include "brdffit/math.h"
#include "brdffit/model.h"
#include "brdffit/param.h"

namespace brdffit::models {

inline ParamSpec albedo_param(double default_value = 0.5) {
  return {"albedo",
          3,
          0.0,
          1.0,
          default_value,
          "diffuse reflectance per channel (directional albedo of the Lambert term)",
          Role::DiffuseColour,
          /*linear=*/true};
}

// The albedo of the stylised shading models (seed shaders: half-Lambert, wrap, Phong, Blinn-Phong,
// banded, Minnaert, Oren-Nayar's approximation, toon), which multiply n·l by it with no 1/π: the
// same surface has a stylised albedo 1/π times its Lambert albedo (a white Lambert surface, albedo
// 1, is 0.318 here), and its upper bound 1 is π times as bright as Lambert's.
inline ParamSpec shader_albedo_param(double default_value = 0.5) {
  ParamSpec p = albedo_param(default_value);
  p.meaning = "diffuse colour per channel as the shader multiplies n·l (no 1/π: Lambert's albedo/π)";
  return p;
}

inline ParamSpec specular_param(double upper, double default_value, const char* meaning) {
  return {"specular", 3, 0.0, upper, default_value, meaning, Role::SpecularColour, /*linear=*/true};
}

// Lambert BRDF albedo/π of a colour stored at p[0..2].
template <class T>
Rgb<T> lambert_term(const T* albedo) {
  return Rgb<T>(albedo[0] * kInvPi, albedo[1] * kInvPi, albedo[2] * kInvPi);
}

// Beckmann's normal distribution, normalised (∫ D cosθh dωh = 1):
//   D(h) = exp(-tan²θh/m²) / (π m² cos⁴θh).
// Zero where n·h ≤ 1e-6: there the exponential is 0 in double precision anyway, and cos⁴θh
// would underflow towards 0/0.
template <class T>
T beckmann_ndf(double cos_theta_h, const T& m) {
  using std::exp;
  if (cos_theta_h <= 1e-6) return T(0.0);
  const double cos2 = cos_theta_h * cos_theta_h, tan2 = (1.0 - cos2) / cos2;
  const T m2 = m * m;
  return exp(-tan2 / m2) / (kPi * m2 * cos2 * cos2);
}

// Schlick's weight (1 - u)⁵ with u clamped to [0, 1] (u = a cosine), as Burley's and Mitsuba's
// principled materials write their Fresnel and retro-reflection terms.
template <class T>
T schlick_weight(const T& u) {
  const T m = saturate(T(1.0 - u));
  const T m2 = m * m;
  return m2 * m2 * m;
}

// The rotation φ₀ of an anisotropic lobe's tangent frame about the normal, in degrees: the
// angle from the table's x axis to the lobe's x axis, counter-clockwise seen from above. A lobe
// is unchanged by φ₀ + 180°, and by φ₀ + 90° with its x and y widths exchanged, so [0°, 90°]
// holds every lobe once (a lobe turned by 120° is found at 30° with its widths exchanged) and
// fits of the same data agree.
inline ParamSpec tangent_rotation_param() {
  return {"phi0",
          1,
          0.0,
          90.0,
          30.0,
          "rotation of the lobe's x axis about the normal from the table's x axis, in degrees (x, y widths "
          "exchanged: +90°)",
          Role::Orientation};
}

// The components of a direction d along the tangent frame turned by phi0_degrees about the normal.
template <class T>
struct TangentXY {
  T x, y;
};
template <class T>
TangentXY<T> in_tangent_frame(const Vec3& d, const T& phi0_degrees) {
  using std::cos;
  using std::sin;
  const T phi0 = phi0_degrees * (kPi / 180.0);
  const T c = cos(phi0), s = sin(phi0);
  return {d.x() * c + d.y() * s, d.y() * c - d.x() * s};
}

// Nestings (model.h): the simpler models a model contains, declared in each model's nestings().

// Lambert inside a lobe over the same Lambert base: the lobe's linear scale at 0 leaves exactly
// albedo/π.
inline Nesting lambert_under_lobe(const std::string& scale = "specular") {
  return {"lambert",
          {{"albedo", "albedo"}},
          {{scale, 0.0}},
          true,
          "lambert: " + scale + " = 0 switches the lobe off and leaves the same Lambert base"};
}

// Stylised models return the shader's albedo·n·l without Lambert's 1/π (the light's intensity
// carries it), so Lambert's albedo a is their albedo a/π.
inline double lambert_albedo_to_shader_albedo(double a) { return a * kInvPi; }
inline Nesting lambert_in_shader(std::vector<std::pair<std::string, double>> fixed, const std::string& why) {
  return {"lambert",
          {{"albedo", "albedo", lambert_albedo_to_shader_albedo}},
          std::move(fixed),
          true,
          "lambert: " + why + " gives albedo·n·l, Lambert with its albedo/π"};
}

// Widths of the microfacet families in each other's terms, for approximate nestings: GGX's
// α = roughness² and Beckmann's m (Ward's α, Cook-Torrance's m) are both RMS-slope-like widths
// that agree for narrow lobes (Walter et al. 2007 compare them at α = m).
inline double beckmann_m_to_ggx_roughness(double m) { return std::sqrt(m); }
inline double ggx_roughness_to_beckmann_m(double roughness) { return roughness * roughness; }

// Whether a and b are the same number with the same derivatives (ceres::Jet's == compares the
// numbers only).
template <class T>
bool identical(const T& a, const T& b) {
  if constexpr (std::is_arithmetic_v<T>)
    return a == b;
  else
    return a.a == b.a && a.v == b.v;
}

template <class T>
Rgb<T> colour(const T* c) {
  return Rgb<T>(c[0], c[1], c[2]);
}

}  // namespace brdffit::models
