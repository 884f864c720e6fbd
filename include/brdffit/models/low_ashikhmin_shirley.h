// Löw et al. 2012's Ashikhmin-Shirley over a Lambert base: the isotropic specular lobe of
// Ashikhmin & Shirley 2000 with Cook's Fresnel and an index of refraction, in the convention of
// BBM's include/bsdfmodel/ashikhminshirley.h ("LowAshikhminShirley" in BBM's low.h):
//
//   f = albedo/π + specular · (n+1)/(8π) · (n·h)^n · F_ck(η, l·h) / ((l·h) max(n·l, n·v))
// and 0 for the lobe when a direction is below the horizon. Our `ashikhmin-shirley` (Ngan's
// convention) is the same lobe with Schlick's Fresnel of f0.
//
// Published "Aggregate(Lambertian(albedo), LowAshikhminShirley(albedo, sharpness,
// fresnelReflectance))" (low_ashikhminshirley_E1/E2.fit) maps onto albedo, specular = their lobe's
// albedo, n = sharpness and eta = fresnelReflectance, which, despite its name, BBM reads as an
// index of refraction (ior::ior; published values 1.1 to 10). Reciprocal; not energy conserving
// for specular > 1.
//
// Contains `lambert` exactly: specular = 0 switches the lobe off.
#pragma once

#include "brdffit/models/cook_terms.h"
#include "brdffit/models/over_lambert.h"

namespace brdffit::models {

struct LowAshikhminShirleyLobe : Lobe {
  static constexpr const char* kName = "low-ashikhmin-shirley";
  static constexpr const char* kSummary =
      "albedo/π + specular·(n+1)/(8π)·(n·h)^n·F_ck(η,l·h)/(l·h·max(n·l,n·v)): Ashikhmin-Shirley, Cook's Fresnel (Löw "
      "2012)";
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 3;
  enum : int { kSpecular = 0, kN = 3, kEta = 4, kNumValues = 5 };

  static std::vector<ParamSpec> parameters() {
    return {specular_param(5.0, 0.2, "scale of the specular lobe per channel (Löw's LowAshikhminShirley albedo)"),
            {"n", 1, 0.001, 1e6, 50.0, "exponent on n·h: larger is a sharper lobe (Löw's sharpness)", Role::Exponent,
             false, false, Spacing::Log},
            {"eta", 1, 1.0, 12.0, 1.5, "index of refraction of Cook's Fresnel (Löw's fresnelReflectance)", Role::F0}};
  }

  static std::vector<Nesting> nestings() { return {lambert_under_lobe("specular")}; }

  template <class T>
  static Rgb<T> lobe(const T* p, const Vec3& l, const Vec3& v) {
    const double nl = l.z(), nv = v.z();
    const Vec3 h = half_vector(l, v);
    const double lh = l.dot(h);
    if (lh <= 0.0) return Rgb<T>::Zero();
    const T unscaled = (p[kN] + 1.0) / (8.0 * kPi) * pow_of_direction_term(h.z(), p[kN]) * cook_fresnel(p[kEta], lh) /
                       (lh * std::max(nl, nv));
    return colour(p + kSpecular) * unscaled;
  }
};
using LowAshikhminShirley = OverLambert<LowAshikhminShirleyLobe>;

}  // namespace brdffit::models
