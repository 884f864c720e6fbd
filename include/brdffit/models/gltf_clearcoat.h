// glTF 2.0 metallic-roughness (models/gltf.h) under the clear coat of KHR_materials_clearcoat
// (KhronosGroup/glTF, extensions/2.0/Khronos/KHR_materials_clearcoat/README.md, "Clearcoat" and
// its "Implementation": the layering formula as written there):
//
//   coated_material = mix(material, clearcoat_brdf, clearcoat · clearcoat_fresnel)
//                   = (1 - c·F_c)·material + c·F_c·clearcoat_brdf
//   material          = the core glTF BRDF (Appendix B, models/gltf.h) of baseColor, metallic, roughness
//   clearcoat_fresnel = F_c = f0 + (1 - f0)(1 - |v·n_c|)^5,   f0 = ((1 - ior)/(1 + ior))² = 0.04 (ior 1.5)
//   clearcoat_brdf    = D(α_c)·G(α_c) / (4 |v·n_c| |l·n_c|) = V·D of Appendix B,   α_c = clearcoatRoughness²
// c = clearcoatFactor, n_c = the clear coat's normal: the geometric normal (no clearcoatNormalTexture),
// v towards the viewer. Textures are not fitted (factors only).
//
// Not reciprocal: the extension weights both layers by the Fresnel of the view's angle, |v·n_c|
// (its "Discussion": NdotV instead of VdotH, so that a simple mix conserves energy), so f(l, v)
// and f(v, l) differ by c·(F_c(n·v) - F_c(n·l))·(clearcoat_brdf - material). This is what glTF
// viewers draw; a measured table is reciprocal, and the fit finds the coat that matches it best.
//
// Not energy conserving, only because the base is not (gltf.h): the mix reflects at most the
// larger of its two layers' albedos, the coat's V·D lobe at most 1, and the core material 1.35
// with baseColor 1, metallic 0 and roughness 0.01 at θo = 80°.
//
// Named gltf+clearcoat (glTF's extensions are joined to `gltf` by '+': gltf+sheen, gltf+clearcoat+sheen in
// models/gltf_sheen.h); gltf-clearcoat, its first name, is still accepted (registry.cc).
//
// Nesting (exact): `gltf` with clearcoatFactor 0 ("the whole clearcoat layer is disabled", whatever
// clearcoatRoughnessFactor). clearcoatRoughnessFactor's lower bound is gltf's roughness bound
// 0.01 (the extension's default 0 is a mirror, a lobe no table resolves).
#pragma once

#include "brdffit/models/gltf.h"

namespace brdffit::models {

// mix(material, clearcoat_brdf, clearcoat · clearcoat_fresnel) of the extension, for l and v above the
// surface: what the coat makes of the material under it (the core material here, the sheen's in
// gltf+clearcoat+sheen).
template <class T>
Rgb<T> gltf_clearcoat_mix(const Rgb<T>& material, const T& clearcoat, const T& clearcoat_roughness, const Vec3& l,
                          const Vec3& v) {
  // No coat: the material as it is (math.h).
  if (constant_zero(clearcoat)) return material;
  constexpr double kClearcoatIor = 1.5;  // the extension's, fixed
  const double r = (1.0 - kClearcoatIor) / (1.0 + kClearcoatIor), f0 = r * r;
  const double clearcoat_fresnel = f0 + (1.0 - f0) * schlick_weight(std::abs(v.z()));  // n_c = n
  const T clearcoat_brdf = gltf_specular_vd(clearcoat_roughness, l, v);
  const T weight = clearcoat * clearcoat_fresnel;
  Rgb<T> f;
  for (int c = 0; c < 3; ++c) f[c] = (1.0 - weight) * material[c] + weight * clearcoat_brdf;
  return f;
}

struct GltfClearcoat {
  static constexpr const char* kName = "gltf+clearcoat";  // also accepted as gltf-clearcoat (registry.cc)
  static constexpr const char* kSummary =
      "core glTF + KHR_materials_clearcoat: metallic-roughness under a GGX coat (ior 1.5), mixed by c·F(n·v)";
  static constexpr bool kEnergyConserving = false;  // as gltf's base; the coat alone reflects at most 1
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 5;
  enum : int { kBaseColor = 0, kMetallic = 3, kRoughness = 4, kClearcoat = 5, kClearcoatRoughness = 6, kNumValues = 7 };
  static_assert(int{kBaseColor} == int{Gltf::kBaseColor} && int{kMetallic} == int{Gltf::kMetallic} &&
                    int{kRoughness} == int{Gltf::kRoughness},
                "the base's values are laid out as gltf's, so that Gltf::brdf evaluates them");

  static std::vector<ParamSpec> parameters() {
    return {gltf_base_color_param(),
            gltf_metallic_param(),
            gltf_roughness_param(),
            {"clearcoatFactor", 1, 0.0, 1.0, 0.0,
             "KHR_materials_clearcoat clearcoatFactor: strength of the clear coat (0: the core material)"},
            {"clearcoatRoughnessFactor", 1, 0.01, 1.0, 0.1,
             "KHR_materials_clearcoat clearcoatRoughnessFactor; the coat's GGX width is alpha = roughness²",
             Role::Roughness, false, false, Spacing::Log}};
  }

  template <class T>
  static Rgb<T> brdf(const T* p, const Vec3& l, const Vec3& v) {
    if (l.z() <= 0.0 || v.z() <= 0.0) return Rgb<T>(T(0.0), T(0.0), T(0.0));
    // The core material, of this model's first five values, on Jets of its three parameters'
    // derivatives only (math.h).
    const Rgb<T> material = on_leading_slots<Gltf::kNumParameters, Gltf::kNumValues>(
        [&l, &v](const auto* q) { return Gltf::brdf(q, l, v); }, p);
    return gltf_clearcoat_mix(material, p[kClearcoat], p[kClearcoatRoughness], l, v);
  }

  // The recovery tests' material (model.h): glossy as in fits of MERL, the coat (α = 0.04) over
  // the base's 0.16.
  static RecoveryFacts recovery_facts() { return {/*material=*/{"roughness=0.4", "clearcoatRoughnessFactor=0.2"}}; }

  static std::vector<Nesting> nestings() {
    return {{"gltf",
             {{"baseColor", "baseColor"}, {"metallic", "metallic"}, {"roughness", "roughness"}},
             {{"clearcoatFactor", 0.0}},
             /*exact=*/true,
             "clearcoatFactor 0 disables the coat: the core material"}};
  }
};

}  // namespace brdffit::models
