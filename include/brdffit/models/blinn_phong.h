// Blinn-Phong: Lambert diffuse plus a lobe around the half vector.
//
//   shade = albedo · max(n·l, 0) + specular · max(n·h, 0)^gloss,   h = normalize(l + v)
//
// Seed: 000_45877382eab04cd5.txt (Blinn 1977 as shaders write it: no n·l on the specular term).
// The specular term is gated to lit points (n·l > 0), like phong (seed 001); seed 000 does not
// gate it. `gloss` is the exponent on n·h (seed 000's _SpecularGloss). `specular` is seed 000's
// _SpecularPower·_SpecularColor, an intensity in [0, 100] (see phong.h); gloss is in [1, 1e5]
// (Ngan et al.'s Blinn-Phong fits of MERL reach 1.2e5). Stylised: no BRDF.
// Contains: lambert exactly (specular = 0, albedo = Lambert's albedo/π: the shader omits 1/π);
// phong approximately (gloss ≈ 4·shininess, a start only).
#pragma once

#include "brdffit/models/common.h"

namespace brdffit::models {

struct BlinnPhong {
  static constexpr const char* kName = "blinn-phong";
  static constexpr const char* kSummary = "albedo·n·l + specular·(n·h)^gloss: Blinn-Phong shading";
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 3;
  enum : int { kAlbedo = 0, kSpecular = 3, kGloss = 6, kNumValues = 7 };

  static std::vector<ParamSpec> parameters() {
    return {
        shader_albedo_param(),
        specular_param(100.0, 0.2, "highlight intensity per channel (the shader's specular power × specular colour)"),
        {"gloss", 1, 1.0, 100000.0, 64.0, "Blinn exponent on n·h: larger is a smaller, sharper highlight",
         Role::Exponent, false, false, Spacing::Log}};
  }

  static std::vector<Nesting> nestings() {
    return {lambert_in_shader({{"specular", 0.0}}, "specular = 0"),
            {"phong",
             {{"albedo", "albedo"}, {"specular", "specular"}, {"gloss", "shininess", times_four}},
             {},
             false,
             "phong, approximately: a Blinn exponent of 4x the Phong one gives a similar highlight"}};
  }
  static double times_four(double x) { return 4.0 * x; }

  template <class T>
  static Rgb<T> shade(const T* p, const Vec3& l, const Vec3& v) {
    if (l.z() <= 0.0) return Rgb<T>::Zero();
    const T lobe = pow_of_direction_term(half_vector(l, v).z(), p[kGloss]);
    return colour(p + kAlbedo) * l.z() + colour(p + kSpecular) * lobe;
  }
};

}  // namespace brdffit::models
