// Lambert: ideal diffuse reflection.
//
//   f(l,v) = albedo / π          shade = albedo/π · max(n·l, 0)
//
// Seed: 000_45877382eab04cd5.txt (LambertDiffuse = NdotL · SurfaceColor). The seed's shader
// folds π into the light's intensity; brdffit keeps the 1/π so that `albedo` is the surface's
// reflectance (its directional albedo), as every measured-BRDF fit reports it. Every
// physically-based model below uses this same Lambert term as its diffuse base.
#pragma once

#include "brdffit/models/common.h"

namespace brdffit::models {

struct Lambert {
  static constexpr const char* kName = "lambert";
  static constexpr const char* kSummary = "albedo/π · max(n·l,0): ideal diffuse (Lambert 1760)";
  static constexpr bool kEnergyConserving = true;
  // Declared by a model whose channel c depends on its scalars and on component c of each colour
  // only (no luminance, no maximum over channels), with its number of parameters: the fitter then
  // carries one derivative per parameter rather than per value (src/internal/brdffit/separate_channels.h).
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 1;
  enum : int { kAlbedo = 0, kNumValues = 3 };

  static std::vector<ParamSpec> parameters() { return {albedo_param()}; }

  template <class T>
  static Rgb<T> brdf(const T* p, const Vec3& /*l*/, const Vec3& /*v*/) {
    return lambert_term(p + kAlbedo);
  }
};

}  // namespace brdffit::models
