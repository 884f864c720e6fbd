// Anisotropic GGX (Trowbridge-Reitz) microfacet specular over a Lambert base, with the tangent
// frame's rotation about the normal fitted (brushed metals, satins).
//
//   f(l,v) = albedo/π + D(h)·F(l·h)·G(l,v) / (4 (n·l)(n·v))
//   D = 1 / (π α_x α_y ((h_x/α_x)² + (h_y/α_y)² + h_z²)²)    Walter et al. 2007, eq. 33 in
//       the form of Heitz 2014 ("Understanding the masking-shadowing function", eq. 85)
//   F = f0 + (1-f0)(1-l·h)^5                                   Schlick
//   G = G1(l)·G1(v),  G1(d) = d_z / (d_z(1-k) + k),  k = α_d/2  Schlick-Smith as in `ggx`, with
//       α_d = √((d_x² α_x² + d_y² α_y²)/(d_x² + d_y²)) the width seen along d's azimuth
//       (Heitz 2014, eq. 80; any value at d = n, where G1 = 1)
// where (h_x, h_y), (d_x, d_y) are components along the tangent frame turned by phi0 about the
// normal (common.h: in_tangent_frame).
//
// Parameters are Walter's widths α_x, α_y themselves (not the perceptual roughness of `ggx`,
// whose α = roughness²). With α_x = α_y = roughness² the model is `ggx` exactly, whatever phi0:
// D, α_d and so G reduce to ggx.h's expressions.
//
// Contains (nestings): `ggx` (α_x = α_y = roughness², exact) and `lambert` (f0 = 0, widths 1;
// not exact: Schlick's F keeps (1-l·h)^5 at f0 = 0, so the lobe does not vanish).
// Energy conserving in model.h's sense, as `ggx`: the lobe alone reflects at most 1 (D is
// normalised, F and G are at most 1; tests/test_model_physics.cc integrates it over the whole
// box of widths), and so does the albedo term; their sum can exceed 1 (albedo 1 with the
// (1-l·h)^5 term that f0 = 0 leaves reflects 1.39 at θo = 80° for α_x = α_y = 1e-4).
#pragma once

#include "brdffit/models/over_lambert.h"

namespace brdffit::models {

struct GgxAnisoLobe : Lobe {
  static constexpr const char* kName = "ggx-aniso";
  static constexpr const char* kSummary =
      "albedo/π + D·F·G/(4 n·l n·v): anisotropic GGX (Walter 2007) with widths α_x, α_y and frame rotation phi0";
  static constexpr bool kEnergyConserving = true;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 4;
  static constexpr bool kScaledByLinearParameter = false;  // Schlick's F is affine in f0, not 0 at f0 = 0
  enum : int { kF0 = 0, kAlphaX = 3, kAlphaY = 4, kPhi0 = 5, kNumValues = 6 };

  static std::vector<ParamSpec> parameters() {
    auto width = [](const char* name, const char* meaning) {
      return ParamSpec{name, 1, 1e-4, 1.0, 0.25, meaning, Role::Roughness, false, false, Spacing::Log};
    };
    return {{"f0", 3, 0.0, 1.0, 0.04, "specular reflectance at normal incidence per channel (Schlick F0)", Role::F0,
             /*linear=*/true},
            width("alpha_x", "GGX width along the tangent (x) axis (ggx's roughness²)"),
            width("alpha_y", "GGX width along the bitangent (y) axis"),
            tangent_rotation_param()};
  }

  static std::vector<Nesting> nestings() {
    return {{"ggx",
             {{"albedo", "albedo"}, {"f0", "f0"}, {"alpha_x", "roughness", square}, {"alpha_y", "roughness", square}},
             {{"phi0", 0.0}},
             true,
             "equal widths α_x = α_y = roughness²"},
            {"lambert",
             {{"albedo", "albedo"}},
             {{"f0", 0.0}, {"alpha_x", 1.0}, {"alpha_y", 1.0}},
             false,
             "lambert, approximately: f0 = 0 leaves Schlick's (1-l·h)^5 grazing term; widths 1 spread it"}};
  }

  // The recovery tests' material (model.h): glossy widths as in published fits of MERL. The
  // middle of the log range, α_x = 0.0025, is a near-mirror: there f0 scattered by 4.7 %.
  static RecoveryFacts recovery_facts() { return {/*material=*/{"alpha_x=0.1", "alpha_y=0.2"}}; }

  template <class T>
  static Rgb<T> lobe(const T* p, const Vec3& l, const Vec3& v) {
    using std::sqrt;
    const double nl = l.z(), nv = v.z();
    const Vec3 h = half_vector(l, v);
    const T ax = p[kAlphaX], ay = p[kAlphaY];
    const TangentXY<T> ht = in_tangent_frame(h, p[kPhi0]);
    const T stretched = (ht.x / ax) * (ht.x / ax) + (ht.y / ay) * (ht.y / ay) + h.z() * h.z();
    const T d = 1.0 / (kPi * ax * ay * stretched * stretched);
    const T dg = d * smith_g1(l, p) * smith_g1(v, p) / (4.0 * nl * nv);
    Rgb<T> f;
    for (int c = 0; c < 3; ++c) f[c] = dg * schlick_fresnel(p[kF0 + c], l.dot(h));
    return f;
  }

 private:
  static double square(double x) { return x * x; }

  // Schlick-Smith G1 with the width seen along d's azimuth.
  template <class T>
  static T smith_g1(const Vec3& d, const T* p) {
    using std::sqrt;
    const double sin2 = d.x() * d.x() + d.y() * d.y();
    if (sin2 <= 0.0) return T(1.0);
    const TangentXY<T> dt = in_tangent_frame(d, p[kPhi0]);
    const T k = 0.5 * sqrt((dt.x * dt.x * p[kAlphaX] * p[kAlphaX] + dt.y * dt.y * p[kAlphaY] * p[kAlphaY]) / sin2);
    return d.z() / (d.z() * (1.0 - k) + k);
  }
};
using GgxAniso = OverLambert<GgxAnisoLobe>;

}  // namespace brdffit::models
