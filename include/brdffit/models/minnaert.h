// Minnaert's lunar reflectance.
//
//   shade = albedo · saturate(n·l · (n·l · n·v)^roughness)
//
// Seed: 000_45877382eab04cd5.txt (the "moon shader"). roughness = 0 is Lambert's n·l; larger
// values darken the limb, as velvet and the moon do. Stylised: no 1/π, no BRDF.
// Contains: lambert exactly (roughness k = 0, albedo = Lambert's albedo/π).
#pragma once

#include "brdffit/models/common.h"

namespace brdffit::models {

struct Minnaert {
  static constexpr const char* kName = "minnaert";
  static constexpr const char* kSummary = "albedo·saturate(n·l·(n·l·n·v)^roughness): Minnaert limb darkening";
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 2;
  enum : int { kAlbedo = 0, kRoughness = 3, kNumValues = 4 };

  static std::vector<ParamSpec> parameters() {
    return {
        shader_albedo_param(),
        {"roughness", 1, 0.0, 2.0, 0.5, "Minnaert exponent k: 0 is Lambert, larger darkens the limb", Role::Roughness}};
  }

  static std::vector<Nesting> nestings() { return {lambert_in_shader({{"roughness", 0.0}}, "roughness = 0")}; }

  template <class T>
  static Rgb<T> shade(const T* p, const Vec3& l, const Vec3& v) {
    const double nl = std::max(l.z(), 0.0), nv = std::max(v.z(), 0.0);
    const T power = pow_of_direction_term(nl * nv, p[kRoughness]);
    const T term = saturate(T(nl * power));
    return colour(p + kAlbedo) * term;
  }
};

}  // namespace brdffit::models
