// Phong: Lambert diffuse plus the mirror-direction lobe.
//
//   shade = albedo · max(n·l, 0) + specular · max(r·v, 0)^shininess,   r = reflect(-l, n)
//
// Seeds: 000_45877382eab04cd5.txt and 001_e1a041759553c440.txt (Phong 1975 as shaders write it:
// the specular term is not multiplied by n·l). The specular term is gated to lit points
// (n·l > 0) as seed 001 does ("light on the wrong side - no specular"); seed 000 does not gate
// it, and without the gate a light below the horizon would still give a highlight. Seed 000
// raises r·v to _SpecularGloss/4; `shininess` is the exponent itself (seed 001's _Shininess).
// `specular` is seed 000's _SpecularPower·_SpecularColor, an intensity rather than a [0,1]
// colour, in [0, 100]: glossy measured materials have shaded peaks of tens to hundreds (a bound
// of 1 held 4 of the 9 shared materials at the bound; the MERL blue-acrylic proxy fits 28).
// shininess is in [1, 1e5], like the literature models' exponents (Ngan et al.'s Blinn-Phong
// fits of MERL reach 1.2e5; blue-acrylic fits 2.4e4).
// Stylised: no BRDF.
// Contains: lambert exactly (specular = 0, albedo = Lambert's albedo/π: the shader omits 1/π).
#pragma once

#include "brdffit/models/common.h"

namespace brdffit::models {

struct Phong {
  static constexpr const char* kName = "phong";
  static constexpr const char* kSummary = "albedo·n·l + specular·(r·v)^shininess: Phong shading";
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 3;
  enum : int { kAlbedo = 0, kSpecular = 3, kShininess = 6, kNumValues = 7 };

  static std::vector<ParamSpec> parameters() {
    return {
        shader_albedo_param(),
        specular_param(100.0, 0.2, "highlight intensity per channel (the shader's specular power × specular colour)"),
        {"shininess", 1, 1.0, 100000.0, 32.0, "Phong exponent: larger is a smaller, sharper highlight", Role::Exponent,
         false, false, Spacing::Log}};
  }

  static std::vector<Nesting> nestings() { return {lambert_in_shader({{"specular", 0.0}}, "specular = 0")}; }

  template <class T>
  static Rgb<T> shade(const T* p, const Vec3& l, const Vec3& v) {
    if (l.z() <= 0.0) return Rgb<T>::Zero();
    const T lobe = pow_of_direction_term(reflect_about_normal(l).dot(v), p[kShininess]);
    return colour(p + kAlbedo) * l.z() + colour(p + kSpecular) * lobe;
  }
};

}  // namespace brdffit::models
