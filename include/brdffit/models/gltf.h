// glTF 2.0 metallic-roughness, exactly as the specification's Appendix B ("BRDF
// Implementation") defines it:
//
//   f = (1-m)·dielectric + m·metal
//   dielectric = (1 - F_d)·baseColor/π + F_d·V·D       F_d = 0.04 + 0.96·(1 - |v·h|)^5   (ior 1.5)
//   metal      = F_m·V·D                                F_m = baseColor + (1 - baseColor)(1 - |v·h|)^5
//   D = α² / (π ((n·h)²(α²-1) + 1)²)                   α = roughness²
//   V = G/(4 |n·l||n·v|) = 1 / (2 (|n·v|√(α² + (1-α²)(n·l)²) + |n·l|√(α² + (1-α²)(n·v)²)))
//                                                      (height-correlated Smith)
// m = metallic. Single scattering, no energy compensation (the Appendix only suggests it).
//
// Beside brdffit's `ggx` (models/ggx.h) the specular lobe differs only in G (height-correlated
// Smith instead of Schlick-Smith with k = α/2), and the diffuse term is weighted by 1 - F(v·h)
// instead of being a separate albedo; the Fresnel is tied to baseColor through metallic.
//
// Nesting: it does not contain `lambert` exactly (a dielectric keeps its 4% specular lobe and
// its 1 - F diffuse weight); Lambert's albedo as baseColor with metallic 0 and roughness 1 is
// only a start. The fitter's guarantee therefore does not hold against lambert; `gltf-specular`
// (specular = 0) does contain lambert exactly.
#pragma once

#include <type_traits>

#include "brdffit/model.h"
#include "brdffit/models/common.h"
#include "brdffit/models/microfacet.h"

namespace brdffit::models {

// Appendix B's specular_brdf without its Fresnel, V·D (GGX with α = roughness², height-correlated
// Smith V), for l and v above the surface; KHR_materials_clearcoat's lobe is this one.
template <class T>
T gltf_specular_vd(const T& roughness, const Vec3& l, const Vec3& v) {
  const double nl = l.z(), nv = v.z(), nh = half_vector(l, v).z();
  return of_one_parameter(roughness, [&](const auto& r) {
    using R = std::decay_t<decltype(r)>;
    using std::sqrt;
    const R alpha = r * r, alpha2 = alpha * alpha;
    const R denom = nh * nh * (alpha2 - 1.0) + 1.0;
    const R d = nh > 0.0 ? R(alpha2 / (kPi * denom * denom)) : R(0.0);
    const R vis =
        1.0 / (2.0 * (nv * sqrt(alpha2 + (1.0 - alpha2) * (nl * nl)) + nl * sqrt(alpha2 + (1.0 - alpha2) * (nv * nv))));
    return R(vis * d);
  });
}

// The metallic-roughness BRDF with the dielectric Fresnel of KHR_materials_specular
// (extensions/2.0/Khronos/KHR_materials_specular): per channel
//   F_d = f0 + (f90 - f0)(1 - |v·h|)^5,   dielectric = F_d·V·D + (1 - max(F_d))·baseColor/π,
// which is Appendix B's for f0 = 0.04 (grey) and f90 = 1. `specular` is the lobe's V·D:
// gltf_specular_vd, or KHR_materials_anisotropy's (gltf_anisotropy.h). F0 and F90 are doubles
// where they are constants (Appendix B's): on Jets they would carry derivatives of zeros.
template <class T, class F>
Rgb<T> gltf_metallic_roughness(const T* base_color, const T& metallic, const T& specular, const Rgb<F>& dielectric_f0,
                               const F& dielectric_f90, const Vec3& l, const Vec3& v) {
  const double nl = l.z(), nv = v.z();
  Rgb<T> f(T(0.0), T(0.0), T(0.0));
  if (nl <= 0.0 || nv <= 0.0) return f;
  const double vh = std::abs(v.dot(half_vector(l, v)));
  const double w = schlick_weight(vh);
  Rgb<F> dielectric_fresnel;
  for (int c = 0; c < 3; ++c) dielectric_fresnel[c] = dielectric_f0[c] + (dielectric_f90 - dielectric_f0[c]) * w;
  F fresnel_max = dielectric_fresnel[0];
  for (int c = 1; c < 3; ++c)
    if (dielectric_fresnel[c] > fresnel_max) fresnel_max = dielectric_fresnel[c];
  for (int c = 0; c < 3; ++c) {
    const T dielectric = dielectric_fresnel[c] * specular + (1.0 - fresnel_max) * base_color[c] * kInvPi;
    const T metal = (base_color[c] + (1.0 - base_color[c]) * w) * specular;
    f[c] = (1.0 - metallic) * dielectric + metallic * metal;
  }
  return f;
}

inline ParamSpec gltf_base_color_param() {
  return {"baseColor",
          3,
          0.0,
          1.0,
          0.5,
          "glTF baseColorFactor (linear RGB): diffuse colour of the dielectric, F0 of the metal",
          Role::DiffuseColour,
          /*linear=*/true};
}
inline ParamSpec gltf_metallic_param() {
  return {"metallic", 1, 0.0, 1.0, 0.0, "glTF metallicFactor: 0 dielectric, 1 metal, mixed linearly in between"};
}
inline ParamSpec gltf_roughness_param() {
  return {"roughness",     1,     0.01,  1.0,         0.5, "glTF roughnessFactor; the GGX width is alpha = roughness²",
          Role::Roughness, false, false, Spacing::Log};
}

struct Gltf {
  static constexpr const char* kName = "gltf";
  static constexpr const char* kSummary =
      "glTF 2.0 metallic-roughness (spec Appendix B): GGX α = roughness², height-correlated Smith, F0 0.04 / baseColor";
  // Not energy conserving although each term alone reflects at most 1: the dielectric lobe is
  // always there, and the diffuse under it is weighted by 1 - F(v·h) at each microfacet rather
  // than by what the lobe leaves, so baseColor 1 with metallic 0 and roughness 0.01 reflects 1.35
  // at θo = 80°.
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 3;
  enum : int { kBaseColor = 0, kMetallic = 3, kRoughness = 4, kNumValues = 5 };

  static std::vector<ParamSpec> parameters() {
    return {gltf_base_color_param(), gltf_metallic_param(), gltf_roughness_param()};
  }

  template <class T>
  static Rgb<T> brdf(const T* p, const Vec3& l, const Vec3& v) {
    if (l.z() <= 0.0 || v.z() <= 0.0) return Rgb<T>(T(0.0), T(0.0), T(0.0));
    return gltf_metallic_roughness(p + kBaseColor, p[kMetallic], gltf_specular_vd(p[kRoughness], l, v),
                                   Rgb<double>(0.04, 0.04, 0.04), 1.0, l, v);
  }

  // The recovery tests' material (model.h): a glossy roughness; at the middle of the log range,
  // a near-mirror, baseColor scattered by 2 % over 8 noise seeds.
  static RecoveryFacts recovery_facts() { return {/*material=*/{"roughness=0.4"}}; }

  static std::vector<Nesting> nestings() {
    return {{"lambert",
             {{"baseColor", "albedo"}},
             {{"metallic", 0.0}, {"roughness", 1.0}},
             /*exact=*/false,
             "a rough dielectric with Lambert's albedo as baseColor (its 4% specular lobe remains)"}};
  }
};

}  // namespace brdffit::models
