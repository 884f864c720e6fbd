// Toon (cel) shading with a hard-edged highlight and rim light.
//
//   light = smoothstep(0, 0.01, n·l)
//   spec  = smoothstep(0.005, 0.01, (n·h · light)^(glossiness²)) · specular
//   rim   = smoothstep(rim_amount ± 0.01, (1 - v·n) · (n·l)^rim_threshold)
//   shade = albedo · (light + spec + rim)
//
// Seed: 003_154856537c4c670e.txt (the roystan.net toon shader), without its ambient colour,
// texture and light colour; the rim colour is white. Smoothsteps make the shading flat almost
// everywhere, so only the band edges inform a fit: the multi-start grid does the work.
// n·l is clamped to 0 before the rim's pow (the seed's pow of a negative n·l is NaN in HLSL).
// Bounds follow the tutorial's defaults: glossiness in [1, 100], default 32 (exponent 1024; the
// exponent is glossiness², so 100 already gives 10⁴), log-spaced; rim_amount in [0, 1], default
// 0.716; rim_threshold in [0.01, 2], default 0.1. specular is multiplied by albedo in the seed,
// so only albedo is a linear parameter; the highlight's height is albedo·specular, so a dark
// glossy material needs specular > 1: it is in [0, 10] (a bound of 1 held all 9 shared
// materials at the bound; with 10 the four matte ones fit inside it, at 0.9-3.1, and the glossy
// ones still reach it). Stylised: no BRDF.
// Contains: nothing. Its lit term is a smoothstep of n·l, not n·l.
#pragma once

#include "brdffit/models/common.h"

namespace brdffit::models {

struct Toon {
  static constexpr const char* kName = "toon";
  static constexpr const char* kSummary = "albedo·(light + spec + rim): cel shading with hard highlight and rim";
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 5;
  enum : int { kAlbedo = 0, kSpecular = 3, kGlossiness = 6, kRimAmount = 7, kRimThreshold = 8, kNumValues = 9 };

  static std::vector<ParamSpec> parameters() {
    ParamSpec specular = specular_param(10.0, 0.5, "colour of the highlight (multiplied by albedo)");
    specular.linear = false;  // multiplied by albedo
    return {shader_albedo_param(),
            specular,
            {"glossiness", 1, 1.0, 100.0, 32.0, "highlight exponent is glossiness²: larger is a smaller highlight",
             Role::Exponent, false, false, Spacing::Log},
            {"rim_amount", 1, 0.0, 1.0, 0.716, "rim light appears where (1-v·n)·(n·l)^rim_threshold exceeds this",
             Role::Shape},
            {"rim_threshold", 1, 0.01, 2.0, 0.1, "how far the rim extends into the lit side", Role::Shape}};
  }

  template <class T>
  static Rgb<T> shade(const T* p, const Vec3& l, const Vec3& v) {
    const double light = smoothstep(0.0, 0.01, l.z());
    const T highlight = pow_of_direction_term(half_vector(l, v).z() * light, p[kGlossiness] * p[kGlossiness]);
    const T spec = smoothstep(0.005, 0.01, highlight);
    const T rim_intensity = (1.0 - v.z()) * pow_of_direction_term(std::max(l.z(), 0.0), p[kRimThreshold]);
    const T rim = smoothstep(p[kRimAmount] - 0.01, p[kRimAmount] + 0.01, rim_intensity);
    Rgb<T> out;
    for (int c = 0; c < 3; ++c) out[c] = p[kAlbedo + c] * (light + spec * p[kSpecular + c] + rim);
    return out;
  }
};

}  // namespace brdffit::models
