// Wrap lighting with contrast.
//
//   shade = albedo · saturate((n·l + wrap) / (1 + wrap))^contrast
//
// Seed: 002_eea2a3e804e47e17.txt (Shader Story, half-Lambertian with wrap and contrast).
// wrap = 0, contrast = 1 is Lambert's n·l. Stylised: no BRDF.
// Contains: lambert exactly (wrap = 0, contrast = 1, albedo = Lambert's albedo/π).
#pragma once

#include "brdffit/models/common.h"

namespace brdffit::models {

struct Wrap {
  static constexpr const char* kName = "wrap";
  static constexpr const char* kSummary = "albedo·saturate((n·l+wrap)/(1+wrap))^contrast: wrap lighting";
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 3;
  enum : int { kAlbedo = 0, kWrap = 3, kContrast = 4, kNumValues = 5 };

  static std::vector<ParamSpec> parameters() {
    return {shader_albedo_param(),
            {"wrap", 1, 0.0, 1.0, 0.5, "how far light wraps past the terminator (0: Lambert)", Role::Wrap},
            {"contrast", 1, 0.1, 8.0, 1.0, "exponent of the wrapped term: larger is a sharper falloff", Role::Exponent,
             false, false, Spacing::Log}};
  }

  // The recovery tests' material (model.h): a contrast of 3, whose falloff separates it from
  // wrap (at contrast 1.4 wrap scattered by 1.3 %).
  static RecoveryFacts recovery_facts() { return {/*material=*/{"contrast=3"}}; }

  static std::vector<Nesting> nestings() {
    return {lambert_in_shader({{"wrap", 0.0}, {"contrast", 1.0}}, "wrap = 0, contrast = 1")};
  }

  template <class T>
  static Rgb<T> shade(const T* p, const Vec3& l, const Vec3& /*v*/) {
    const T wrapped = saturate(T((l.z() + p[kWrap]) / (1.0 + p[kWrap])));
    // Below 1e-300 (wrap = 0 and a subnormal n·l) the term is taken as 0: the Jet's log would
    // overflow its derivative, and the value left out is at most (1e-300)^0.1 = 1e-30.
    if (!(wrapped > 1e-300)) return Rgb<T>(T(0.0), T(0.0), T(0.0));
    return colour(p + kAlbedo) * pow_pos(wrapped, p[kContrast]);
  }
};

}  // namespace brdffit::models
