// One Lafortune lobe (Lafortune et al. 1997, eq. 4), isotropic, in the convention of Ngan,
// Durand & Matusik 2005, over a Lambert base.
//
//   f = albedo/π + specular · (n+2)/(2π) · (max(cxy(lx·vx + ly·vy) + cz·lz·vz, 0) / c)^n
//   c = max(|cxy|, |cz|)
//
// Source and convention (BBM: include/bsdfmodel/lafortune.h and the NganLafortune wrapper in
// include/bsdfmodel/ngan.h): Lafortune's lobe ρs·(Cx ux vx + Cy uy vy + Cz uz vz)^n with
// Cx = Cy = Cxy (isotropic), times Ngan's normalisation (n+2) / (2π · max(Cz², Cxy²)^(n/2)).
// Zero when either direction is below the horizon. We write the normalisation as (…/c)^n, which
// is the same number but stays finite for the exponents Ngan publish (thousands: c^n itself
// underflows to 0 in double precision, and the product to 0/0). The base is at most 1 (a
// weighted dot product of unit vectors with weights at most c), so the lobe is at most
// specular·(n+2)/(2π). cxy < 0 < cz is the usual forward-scattering lobe, cxy = -cz is a Phong
// lobe about the mirror direction with the Phong normalisation, cxy > 0 a retro-reflective one.
//
// Published "NganLafortune(albedo, Cxy, Cz, sharpness)" (ngan_lafortune.fit) maps 1:1:
// specular = albedo (per channel), cxy = Cxy, cz = Cz, n = sharpness; their Lambertian(albedo)
// is our albedo (BBM's Lambertian is albedo/π too). Ngan fitted one lobe, as we do; a fit with
// several lobes cannot be represented and is not mapped. Caution with sharp published lobes:
// Cxy and Cz are printed to 3 digits, and the BRDF depends on (Cz/|Cxy|)^n; for blue-acrylic
// (Cxy = -0.577, Cz = 0.577, n = 4060) the rounding alone allows Cz/|Cxy| ∈ [0.9983, 1.0017],
// i.e. up to a factor e^7 ≈ 1000 on the highlight (at normal incidence if Cz < |Cxy|, towards
// grazing if Cz > |Cxy|). The printed values give a Phong lobe about the mirror direction;
// Ngan's unrounded fit may differ a lot.
//
// Bounds: Ngan's values over MERL are Cxy ∈ [-0.707, -0.577], Cz ∈ [1e-10, 0.577], sharpness
// ∈ [2.3, 16600], albedo up to 1.71 (black-phenolic): hence cz ≥ 0 (down to a lobe axis in the
// tangent plane, as Ngan fit for fabrics) and specular up to 10. When cxy = cz = 0 the lobe is
// undefined and taken as 0.
//
// Not energy conserving inside the bounds, because specular must go past 1 to hold Ngan's
// values. At specular ≤ 1 the lobe's directional albedo stayed ≤ 1 at every corner of cxy ∈
// {-1, 0, 1}, cz ∈ {0, 0.01, 1}, n ∈ {0.1, 2, 20} we integrated (θo up to 89°), reaching 1 at
// normal view with the lobe axis on the normal: (n+2)/(2π) is the normalisation of a cosine lobe.
// Under this normalisation only the direction of (cxy, cz) matters, not its length: data
// determine their ratio only (the Jacobian has a null direction along (cxy, cz)).
// Contains: lambert exactly (specular = 0).
#pragma once

#include "brdffit/models/over_lambert.h"

namespace brdffit::models {

struct LafortuneLobe : Lobe {
  static constexpr const char* kName = "lafortune";
  static constexpr const char* kSummary =
      "albedo/π + specular·(n+2)/(2π)·(max(cxy(lx vx+ly vy)+cz lz vz, 0)/max(|cxy|,|cz|))^n: one Lafortune lobe "
      "(Ngan 2005)";
  static constexpr bool kEnergyConserving = false;
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 4;
  enum : int { kSpecular = 0, kCxy = 3, kCz = 4, kN = 5, kNumValues = 6 };

  static std::vector<ParamSpec> parameters() {
    return {specular_param(10.0, 0.2, "scale of the lobe per channel (Ngan's NganLafortune albedo)"),
            {"cxy", 1, -1.0, 1.0, -0.6,
             "lobe weight of the tangent-plane components (negative: forward scattering; Ngan's Cxy)", Role::Shape},
            {"cz", 1, 0.0, 1.0, 0.55, "lobe weight of the normal component (Ngan's Cz)", Role::Shape},
            {"n", 1, 0.1, 100000.0, 20.0, "lobe exponent: larger is a sharper lobe (Ngan's sharpness)", Role::Exponent,
             false, false, Spacing::Log}};
  }

  static std::vector<Nesting> nestings() { return {lambert_under_lobe()}; }

  // Only the direction of (cxy, cz) enters the lobe: fits determine their ratio, not each.
  static RecoveryFacts recovery_facts() { return {/*material=*/{}, /*not_identifiable=*/{"cxy", "cz"}}; }

  template <class T>
  static Rgb<T> lobe(const T* p, const Vec3& l, const Vec3& v) {
    const T c = abs_value(p[kCxy]) > abs_value(p[kCz]) ? abs_value(p[kCxy]) : abs_value(p[kCz]);
    if (!(c > T(0.0))) return Rgb<T>::Zero();
    const T base = (p[kCxy] * (l.x() * v.x() + l.y() * v.y()) + p[kCz] * (l.z() * v.z())) / c;
    // Below 1e-200 the lobe is under 1e-20 for every n in the bounds: taken as 0, so that the
    // derivative of log(base) cannot overflow for a subnormal base and give 0·∞ = NaN.
    if (!(base > T(1e-200))) return Rgb<T>::Zero();
    const T unscaled = (p[kN] + 2.0) / (2.0 * kPi) * pow_pos(base, p[kN]);
    return colour(p + kSpecular) * unscaled;
  }
};
using Lafortune = OverLambert<LafortuneLobe>;

}  // namespace brdffit::models
