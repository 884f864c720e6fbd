// Half-Lambert (Valve's diffuse wrap).
//
//   shade = albedo · (n·l · w + (1 - w))²        w = wrap in [0.5, 1]
//
// Seed: 000_45877382eab04cd5.txt (pow(NdotL·wrapValue + (1 - wrapValue), 2)). The seed's code
// clamps N·L to 0 first; brdffit uses the raw N·L, as Half-Life did, so the side facing away
// from the light keeps its shading instead of a flat (1-w)². w = 0.5 is the classic half-Lambert;
// w = 1 is (n·l)², a darker Lambert. Consequence of the raw n·l: for w > 0.5 the term is not
// monotone on the back; it is 0 at n·l = -(1-w)/w and rises again to (1-2w)² at n·l = -1 (1 for
// w = 1). Only w = 0.5 (Valve's value) is monotone over the whole sphere. Stylised: no BRDF.
// Contains: nothing. (n·l·w + 1 - w)² with w in [0.5, 1] is never n·l.
#pragma once

#include "brdffit/models/common.h"

namespace brdffit::models {

struct HalfLambert {
  static constexpr const char* kName = "half-lambert";
  static constexpr const char* kSummary = "albedo·(n·l·w + 1-w)²: Valve's half-Lambert wrap on the raw n·l";
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 2;
  enum : int { kAlbedo = 0, kWrap = 3, kNumValues = 4 };

  static std::vector<ParamSpec> parameters() {
    return {shader_albedo_param(),
            {"wrap", 1, 0.5, 1.0, 0.5, "how the shading wraps past the terminator: 0.5 half-Lambert, 1 (n·l)²",
             Role::Wrap}};
  }

  template <class T>
  static Rgb<T> shade(const T* p, const Vec3& l, const Vec3& /*v*/) {
    const T wrapped = l.z() * p[kWrap] + (1.0 - p[kWrap]);
    const T term = wrapped * wrapped;
    return colour(p + kAlbedo) * term;
  }
};

}  // namespace brdffit::models
