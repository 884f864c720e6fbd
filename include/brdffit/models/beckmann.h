// Beckmann microfacet distribution as a specular lobe over a Lambert base.
//
//   f = albedo/π + specular · exp(-tan²θh/m²) / (π m² cos⁴θh)
//
// Seed: 004_e79c30797da74a89.txt (brdf_beckmann), used as the specular term of a BRDF. The
// lobe is the normalised NDF D(h) (∫ D cosθh dωh = 1) without Fresnel or shadowing, so its
// BRDF albedo is not bounded by 1: `specular` is a plain scale. tanθh is computed from n·h
// (tan² = (1-cos²)/cos²) rather than the seed's |n×h|/n·h, the same value; where n·h is about 0
// (only possible with a direction below the horizon) the lobe is 0 instead of the seed's 0/0.
// Contains: lambert exactly (specular = 0); ggx approximately (m = roughness², a start only).
#pragma once

#include "brdffit/models/over_lambert.h"

namespace brdffit::models {

struct BeckmannLobe : Lobe {
  static constexpr const char* kName = "beckmann";
  static constexpr const char* kSummary = "albedo/π + specular·D_Beckmann(h; m): Beckmann lobe";
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 2;
  enum : int { kSpecular = 0, kM = 3, kNumValues = 4 };

  static std::vector<ParamSpec> parameters() {
    return {specular_param(10.0, 0.2, "scale of the Beckmann lobe per channel"),
            {"m", 1, 0.005, 1.5, 0.3, "Beckmann roughness: RMS slope of the microfacets", Role::Roughness, false, false,
             Spacing::Log}};
  }

  static std::vector<Nesting> nestings() {
    return {lambert_under_lobe(),
            {"ggx",
             {{"albedo", "albedo"}, {"m", "roughness", ggx_roughness_to_beckmann_m}},
             {},
             false,
             "ggx, approximately: m = roughness²"}};
  }

  // The recovery tests' material (model.h): a glossy width; under the near-mirror of the middle
  // of the log range the albedo scattered by 1-2 % over 8 noise seeds.
  static RecoveryFacts recovery_facts() { return {/*material=*/{"m=0.2"}}; }

  // The seed's lobe is a function of h alone, evaluated for any directions.
  static bool lobe_vanishes(const Vec3& /*l*/, const Vec3& /*v*/) { return false; }

  template <class T>
  static Rgb<T> lobe(const T* p, const Vec3& l, const Vec3& v) {
    return colour(p + kSpecular) * beckmann_ndf(half_vector(l, v).z(), p[kM]);
  }
};
using Beckmann = OverLambert<BeckmannLobe>;

}  // namespace brdffit::models
