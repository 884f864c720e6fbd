// GGX (Trowbridge-Reitz) microfacet specular over a Lambert base.
//
//   f(l,v) = albedo/π + D(h)·F(l·h)·G(l,v) / (4 (n·l)(n·v))
//   D = α² / (π ((n·h)²(α²-1) + 1)²)            α = roughness²  (Burley 2012 remapping)
//   F = f0 + (1-f0)(1-l·h)^5                     Schlick
//   G = G1(n·l)·G1(n·v),  G1(x) = x / (x(1-k) + k),  k = α/2   (Schlick-Smith, as the seed)
//
// Seed: 004_e79c30797da74a89.txt (John Hable's brdf_ggx). The seed returns n·l·D·F·vis with
// vis = G/((n·l)(n·v)) and leaves out the microfacet denominator's 1/4; brdffit keeps the 1/4
// (Walter et al. 2007) so the lobe is normalised: its directional albedo is at most 1.
// f0 is a colour so that metals (coloured specular) can be fitted.
// Contains: nothing exactly. Schlick's F = f0 + (1-f0)(1-l·h)^5 is not 0 at f0 = 0, so no value
// of f0 switches the lobe off: lambert only approximately (f0 = 0, roughness 1: what remains is
// a faint grazing term); beckmann and cook-torrance approximately (roughness = √m). A fit of
// ggx on a Lambertian material can therefore end slightly above Lambert's error (the verdict
// judges by how much).
#pragma once

#include "brdffit/models/over_lambert.h"

namespace brdffit::models {

struct GgxLobe : Lobe {
  static constexpr const char* kName = "ggx";
  static constexpr const char* kSummary =
      "albedo/π + D·F·G/(4 n·l n·v): GGX/Trowbridge-Reitz, Schlick F, Schlick-Smith G, α = roughness²";
  static constexpr bool kEnergyConserving = true;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 2;
  static constexpr bool kScaledByLinearParameter = false;  // Schlick's F is affine in f0, not 0 at f0 = 0
  enum : int { kRoughness = 0, kF0 = 1, kNumValues = 4 };

  static std::vector<ParamSpec> parameters() {
    return {{"roughness", 1, 0.01, 1.0, 0.5, "perceptual roughness; the GGX width is alpha = roughness²",
             Role::Roughness, false, false, Spacing::Log},
            {"f0", 3, 0.0, 1.0, 0.04, "specular reflectance at normal incidence per channel (Schlick F0)", Role::F0,
             /*linear=*/true}};
  }

  static std::vector<Nesting> nestings() {
    return {{"lambert",
             {{"albedo", "albedo"}},
             {{"f0", 0.0}, {"roughness", 1.0}},
             false,
             "lambert, approximately: f0 = 0 leaves Schlick's (1-l·h)^5 grazing term; roughness 1 spreads it"},
            {"beckmann",
             {{"albedo", "albedo"}, {"roughness", "m", beckmann_m_to_ggx_roughness}},
             {},
             false,
             "beckmann, approximately: roughness = √m"},
            {"cook-torrance",
             {{"albedo", "albedo"}, {"roughness", "m", beckmann_m_to_ggx_roughness}},
             {},
             false,
             "cook-torrance, approximately: roughness = √m"}};
  }

  // The recovery tests' material (model.h): a glossy width as in published fits of MERL. The
  // middle of the log range, α = 0.006, is a near-mirror that random directions rarely see: there
  // f0 scattered by 2.6 % over 8 noise seeds.
  static RecoveryFacts recovery_facts() { return {/*material=*/{"roughness=0.4"}}; }

  template <class T>
  static Rgb<T> lobe(const T* p, const Vec3& l, const Vec3& v) {
    const double nl = l.z(), nv = v.z();
    const Vec3 h = half_vector(l, v);
    const double nh = h.z(), lh = l.dot(h);
    const T alpha = p[kRoughness] * p[kRoughness];
    const T alpha2 = alpha * alpha;
    const T denom = nh * nh * (alpha2 - 1.0) + 1.0;
    const T d = alpha2 / (kPi * denom * denom);
    const T k = alpha * 0.5;
    const T g = nl / (nl * (1.0 - k) + k) * (nv / (nv * (1.0 - k) + k));
    const T dg = d * g / (4.0 * nl * nv);
    Rgb<T> f;
    for (int c = 0; c < 3; ++c) f[c] = dg * schlick_fresnel(p[kF0 + c], lh);
    return f;
  }
};
using Ggx = OverLambert<GgxLobe>;

}  // namespace brdffit::models
