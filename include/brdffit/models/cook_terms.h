// Terms of Cook & Torrance 1982 shared by the models that follow their paper literally (Löw et
// al. 2012's variants): Cook's exact dielectric Fresnel with an index of refraction, and the
// V-groove masking-shadowing.
#pragma once

#include <algorithm>
#include <cmath>

#include "brdffit/math.h"

namespace brdffit::models {

// Cook & Torrance's Fresnel reflectance of a dielectric with index of refraction η (unpolarised),
// for c = cosine between the light and the facet normal (l·h):
//   g = √(η² + c² − 1),  F = ½ ((g−c)/(g+c))² · (1 + ((c(g+c) − 1)/(c(g−c) + 1))²)
// as BBM's fresnel::cook (which also clamps F ≥ 0 and takes √ of max(·, 0)). F(η, 1) =
// ((η−1)/(η+1))², F(1, c) = 0 (no interface), F → 1 at grazing (c → 0).
// At c ≤ 0 (grazing or behind the facet) we return the grazing limit 1: it keeps g + c > 0 for
// η = 1, where BBM's formula is 0/0.
template <class T>
T cook_fresnel(const T& eta, double c) {
  using std::sqrt;
  if (c <= 0.0) return T(1.0);
  const T g2 = eta * eta + (c * c - 1.0);
  const T g = g2 > T(0.0) ? T(sqrt(g2)) : T(0.0);
  const T a = (g - c) / (g + c);
  const T b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
  const T f = 0.5 * a * a * (1.0 + b * b);
  return f > T(0.0) ? f : T(0.0);
}

// V-groove masking-shadowing (Cook & Torrance 1982; Ngan 2005 and BBM's maskingshadowing::vgroove):
//   G = min(1, 2(n·h)(n·l)/(l·h), 2(n·h)(n·v)/(v·h)),  with v·h = l·h for the half vector.
inline double vgroove_masking(double nh, double nl, double nv, double lh) {
  return std::min({1.0, 2.0 * nh * nl / lh, 2.0 * nh * nv / lh});
}

}  // namespace brdffit::models
