// A lobe over the Lambert base, the shape of most physically based models here:
//
//   f(l,v) = albedo/π + lobe(l,v)        the lobe 0 where a direction is below the horizon
//
// Such a model's file writes its lobe alone (ggx.h, beckmann.h, ...):
//
//   struct GgxLobe : Lobe {
//     kName, kSummary, kEnergyConserving        the model's (model_adapter.h)
//     kSeparateChannels, kNumParameters         the lobe's, of its own parameters (model_adapter.h)
//     enum { kRoughness = 0, ..., kNumValues }  offsets of the lobe's own values, from 0
//     parameters()                              the lobe's own, in the model's order after albedo
//     lobe<T>(p, l, v)                          the lobe's f (1/sr) at its own values p, T double or ceres::Jet
//     nestings(), recovery_facts(), lobe_vanishes(l, v),
//     kScaledByLinearParameter: optional, Lobe's below otherwise
//   };
//   using Ggx = OverLambert<GgxLobe>;          the model, one line in the registry
//
// OverLambert puts albedo first (values 0..2) and adds albedo/π, alone where lobe_vanishes(l, v);
// lobe() is called only elsewhere, so it need not test the horizon. Two-lobe composites
// (two_lobes.h) take exactly these models: Model::is_lobe_over_lambert() says which.
#pragma once

#include <type_traits>
#include <vector>

#include "brdffit/models/common.h"

namespace brdffit::models {

// What a lobe declares unless it says otherwise.
struct Lobe {
  static constexpr bool kSeparateChannels = false;
  static constexpr int kNumParameters = 0;  // declared with kSeparateChannels
  // Where the lobe is 0 without being evaluated: a direction at or below the horizon. A lobe its
  // source evaluates there too declares its own (beckmann, gaussian, low-smooth).
  static bool lobe_vanishes(const Vec3& l, const Vec3& v) { return l.z() <= 0.0 || v.z() <= 0.0; }
  // Whether the lobe's linear parameter, if it has one (specular, A), scales it: lobe(q) = q·lobe(1).
  // Variable projection then takes the lobe's part from one evaluation on doubles at q = 1
  // (model_adapter.h). A lobe merely affine in it declares false (ggx's Schlick f0).
  static constexpr bool kScaledByLinearParameter = true;
  static std::vector<Nesting> nestings() { return {}; }
  static RecoveryFacts recovery_facts() { return {}; }
};

template <class L>
struct OverLambert {
  static_assert(std::is_base_of_v<Lobe, L>, "a lobe derives from models::Lobe");
  static constexpr const char* kName = L::kName;
  static constexpr const char* kSummary = L::kSummary;
  static constexpr bool kEnergyConserving = L::kEnergyConserving;
  // The Lambert term's channel c reads albedo's component c only.
  static constexpr bool kSeparateChannels = L::kSeparateChannels;
  static constexpr int kNumParameters = 1 + L::kNumParameters;
  static constexpr bool kLobeScaledByLinearParameter = L::kScaledByLinearParameter;
  enum : int { kAlbedo = 0, kLobe = 3, kNumValues = kLobe + L::kNumValues };

  static std::vector<ParamSpec> parameters() {
    std::vector<ParamSpec> params{albedo_param()};
    for (ParamSpec& p : L::parameters()) params.push_back(std::move(p));
    return params;
  }
  static std::vector<Nesting> nestings() { return L::nestings(); }
  static RecoveryFacts recovery_facts() { return L::recovery_facts(); }

  template <class T>
  static Rgb<T> brdf(const T* p, const Vec3& l, const Vec3& v) {
    const Rgb<T> base = lambert_term(p + kAlbedo);
    if (L::lobe_vanishes(l, v)) return base;
    return base + L::lobe(p + kLobe, l, v);
  }
};

template <class M>
struct IsOverLambert : std::false_type {};
template <class L>
struct IsOverLambert<OverLambert<L>> : std::true_type {};

}  // namespace brdffit::models
