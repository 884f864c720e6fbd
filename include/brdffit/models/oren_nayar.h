// Oren-Nayar rough diffuse, in the shader approximation of the seed.
//
//   A = 1 - 0.5·σ²/(σ²+0.33),  B = 0.17·σ²/(σ²+0.13),  C = 0.45·σ²/(σ²+0.09)
//   s = saturate(l·v) - n·l·n·v;  s /= max(n·l, n·v) when s > 0
//   shade = albedo · n·l · (A + albedo·B + C·s)
//
// Seed: 000_45877382eab04cd5.txt, term for term: its "diffuseColor·B" stands in for Oren and
// Nayar's interreflection term, which makes the model quadratic in albedo (so albedo is not a
// linear parameter here). σ = roughness, the slope deviation in radians. Stylised (no 1/π, and
// the seed's quadratic albedo term is not a reflectance), so it defines shade() only, not a BRDF:
// the reciprocity test does not apply (shade/n·l is in fact symmetric in l and v).
// Unlit points (n·l ≤ 0) return 0 before the division by max(n·l, n·v), which is 0 when both
// directions are below the horizon (the seed would produce 0·∞ = NaN there).
// Contains: lambert exactly (σ = 0 gives A = 1, B = C = 0; albedo = Lambert's albedo/π).
#pragma once

#include "brdffit/models/common.h"

namespace brdffit::models {

struct OrenNayar {
  static constexpr const char* kName = "oren-nayar";
  static constexpr const char* kSummary = "albedo·n·l·(A + albedo·B + C·s): Oren-Nayar rough diffuse (shader form)";
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 2;
  enum : int { kAlbedo = 0, kRoughness = 3, kNumValues = 4 };

  static std::vector<ParamSpec> parameters() {
    ParamSpec albedo = shader_albedo_param();
    albedo.linear = false;  // albedo also multiplies the B term
    return {albedo,
            {"roughness", 1, 0.0, 1.5, 0.3, "σ, the standard deviation of facet slopes (radians)", Role::Roughness}};
  }

  static std::vector<Nesting> nestings() { return {lambert_in_shader({{"roughness", 0.0}}, "roughness = 0")}; }

  template <class T>
  static Rgb<T> shade(const T* p, const Vec3& l, const Vec3& v) {
    const double nl = saturate(l.z()), nv = saturate(v.z());
    if (nl <= 0.0) return Rgb<T>(T(0.0), T(0.0), T(0.0));
    const T s2 = p[kRoughness] * p[kRoughness];
    const T a = 1.0 - 0.5 * s2 / (s2 + 0.33), b = 0.17 * s2 / (s2 + 0.13), c = 0.45 * s2 / (s2 + 0.09);
    double s = saturate(l.dot(v)) - nl * nv;
    // n·l·s, with the seed's division by max(n·l, n·v) as the ratio n·l/max ≤ 1: dividing s
    // first overflows when both directions are within 1e-308 of the horizon.
    const double nl_s = s > 0.0 ? s * (nl / std::max(nl, nv)) : s * nl;
    Rgb<T> out;
    for (int k = 0; k < 3; ++k) out[k] = p[kAlbedo + k] * (nl * (a + p[kAlbedo + k] * b) + c * nl_s);
    return out;
  }
};

}  // namespace brdffit::models
