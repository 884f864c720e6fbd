// glTF 2.0 metallic-roughness (models/gltf.h) with KHR_materials_ior and
// KHR_materials_specular (KhronosGroup/glTF, extensions/2.0/Khronos/*/README.md):
//
//   dielectric_f0  = min(((ior-1)/(ior+1))² · specularColor, 1) · specular     per channel
//   dielectric_f90 = specular
//   F_d = dielectric_f0 + (dielectric_f90 - dielectric_f0)(1 - |v·h|)^5
//   dielectric = F_d·V·D + (1 - max(F_d))·baseColor/π;   the metal part is unchanged.
//
// ior is limited to [1, 3] (the extension's special value 0, "infinitely reflective", is not
// fitted). ior and specularColor both scale F0: only their product is determined by data, so
// the fit reports one of them as not identifiable when both move.
//
// Nestings (exact): `gltf` with ior 1.5, specular 1 and specularColor 1 (then F_d is Appendix B's
// grey 0.04 + 0.96·(1 - v·h)^5); `lambert` with specular 0 and metallic 0 (F_d = 0: the
// dielectric is baseColor/π alone).
#pragma once

#include "brdffit/models/gltf.h"

namespace brdffit::models {

struct GltfSpecular {
  static constexpr const char* kName = "gltf-specular";
  static constexpr const char* kSummary =
      "glTF 2.0 metallic-roughness with KHR_materials_ior and KHR_materials_specular (ior, specular, specularColor)";
  // Not energy conserving although each term alone reflects at most 1: the dielectric lobe is
  // always there, and the diffuse under it is weighted by 1 - F(v·h) at each microfacet rather
  // than by what the lobe leaves, so baseColor 1 with metallic 0 and roughness 0.01 reflects 1.35
  // at θo = 80°.
  static constexpr bool kEnergyConserving = false;
  enum : int {
    kBaseColor = 0,
    kMetallic = 3,
    kRoughness = 4,
    kIor = 5,
    kSpecular = 6,
    kSpecularColor = 7,
    kNumValues = 10
  };

  static std::vector<ParamSpec> parameters() {
    return {
        gltf_base_color_param(),
        gltf_metallic_param(),
        gltf_roughness_param(),
        {"ior", 1, 1.0, 3.0, 1.5, "KHR_materials_ior: index of refraction; dielectric F0 = ((ior-1)/(ior+1))²"},
        {"specular", 1, 0.0, 1.0, 1.0, "KHR_materials_specular specularFactor: strength of the dielectric reflection"},
        {"specularColor", 3, 0.0, 1.0, 1.0, "KHR_materials_specular specularColorFactor: tint of the dielectric F0",
         Role::SpecularColour}};
  }

  template <class T>
  static Rgb<T> brdf(const T* p, const Vec3& l, const Vec3& v) {
    const T r = (p[kIor] - 1.0) / (p[kIor] + 1.0);
    Rgb<T> f0;
    for (int c = 0; c < 3; ++c) {
      const T tinted = r * r * p[kSpecularColor + c];
      f0[c] = (tinted < T(1.0) ? tinted : T(1.0)) * p[kSpecular];
    }
    if (l.z() <= 0.0 || v.z() <= 0.0) return Rgb<T>(T(0.0), T(0.0), T(0.0));
    return gltf_metallic_roughness(p + kBaseColor, p[kMetallic], gltf_specular_vd(p[kRoughness], l, v), f0,
                                   p[kSpecular], l, v);
  }

  // Fits of its own values (model.h): KHR_materials_ior and specularColor both scale the
  // dielectric F0, exactly; baseColor and metallic then move by 3-6 % along a direction of almost
  // equal cost, so a fit reproduces the material's reflectance rather than its values.
  static RecoveryFacts recovery_facts() {
    return {/*material=*/{}, /*not_identifiable=*/{"ior", "specularColor"},
            RecoveryFacts::TradeOff{/*max_relative_error=*/0.005, /*max_error_over_truth=*/1.001}};
  }

  static std::vector<Nesting> nestings() {
    return {{"gltf",
             {{"baseColor", "baseColor"}, {"metallic", "metallic"}, {"roughness", "roughness"}},
             {{"ior", 1.5}, {"specular", 1.0}, {"specularColor", 1.0}},
             /*exact=*/true,
             "ior 1.5, specular 1 and specularColor 1 are the core material"},
            {"lambert",
             {{"baseColor", "albedo"}},
             {{"metallic", 0.0}, {"specular", 0.0}},
             /*exact=*/true,
             "specular 0 and metallic 0 leave baseColor/π alone"}};
  }
};

}  // namespace brdffit::models
