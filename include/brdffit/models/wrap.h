// Wrap lighting with contrast.
//
//   shade = albedo · saturate((n·l + wrap) / (1 + wrap))^contrast
//
// Seed: 002_eea2a3e804e47e17.txt (Shader Story, half-Lambertian with wrap and contrast).
// wrap = 0, contrast = 1 is Lambert's n·l. Stylised: no BRDF.
#pragma once

#include "brdffit/models/common.h"

namespace brdffit::models {

struct Wrap {
  static constexpr const char* kName = "wrap";
  static constexpr const char* kSummary = "albedo·saturate((n·l+wrap)/(1+wrap))^contrast: wrap lighting";
  static constexpr bool kEnergyConserving = false;
  enum : int { kAlbedo = 0, kWrap = 3, kContrast = 4, kNumValues = 5 };

  static std::vector<ParamSpec> parameters() {
    return {albedo_param(),
            {"wrap", 1, 0.0, 1.0, 0.5, "how far light wraps past the terminator (0: Lambert)", Role::Wrap},
            {"contrast", 1, 0.1, 8.0, 1.0, "exponent of the wrapped term: larger is a sharper falloff", Role::Exponent,
             false, false, Spacing::Log}};
  }

  template <class T>
  static Rgb<T> shade(const T* p, const Vec3& l, const Vec3& /*v*/) {
    const T wrapped = saturate(T((l.z() + p[kWrap]) / (1.0 + p[kWrap])));
    return colour(p + kAlbedo) * pow_pos(wrapped, p[kContrast]);
  }
};

}  // namespace brdffit::models
