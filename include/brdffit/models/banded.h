// Banded (cel) lighting: n·l quantised into a number of bands.
//
//   shade = albedo · ⌈max(n·l, 0) · steps⌉ / steps
//
// Seed: 000_45877382eab04cd5.txt. The seed's code treats _LightSteps as a band width in 0-256
// units, but its author describes it as the number of bands, which is what users set: here
// `steps` lit bands of equal width in n·l, each shaded at its upper edge, plus black where n·l ≤ 0.
// With the seed's band width w = 256/steps its floor((256·n·l + w/2)/w)·w/256 rounds n·l to the
// nearest multiple of 1/steps: steps+1 levels, with half-width bands at 0 and 1. The ceiling
// used here gives exactly `steps` equal lit bands (levels 1/steps … 1), so steps = 1 is flat
// lighting of every lit point. steps is an integer, searched over its range by the fitter (its
// derivative is 0: it is read through value_of). Stylised: no BRDF.
// Contains: lambert only approximately (32 bands, albedo/π): quantised n·l is never n·l.
#pragma once

#include <cmath>

#include "brdffit/models/common.h"

namespace brdffit::models {

struct Banded {
  static constexpr const char* kName = "banded";
  static constexpr const char* kSummary = "albedo·⌈n·l·steps⌉/steps: n·l quantised into bands";
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 2;
  enum : int { kAlbedo = 0, kSteps = 3, kNumValues = 4 };

  static std::vector<ParamSpec> parameters() {
    return {shader_albedo_param(),
            {"steps", 1, 1.0, 32.0, 4.0, "number of light bands n·l is quantised into", Role::Shape, false, true}};
  }

  static std::vector<Nesting> nestings() {
    return {{"lambert",
             {{"albedo", "albedo", lambert_albedo_to_shader_albedo}},
             {{"steps", 32.0}},
             false,
             "lambert, approximately: 32 bands of n·l"}};
  }

  template <class T>
  static Rgb<T> shade(const T* p, const Vec3& l, const Vec3& /*v*/) {
    if (l.z() <= 0.0) return Rgb<T>::Zero();
    const double steps = std::max(1.0, std::round(value_of(p[kSteps])));
    const double banded = std::ceil(l.z() * steps - 1e-12) / steps;
    return colour(p + kAlbedo) * banded;
  }
};

}  // namespace brdffit::models
