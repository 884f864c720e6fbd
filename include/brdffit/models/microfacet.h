// Microfacet pieces shared by the renderer materials (gltf, openpbr): the GGX normal
// distribution, Smith's height-correlated masking-shadowing and the exact dielectric Fresnel.
// Directions are in the local frame n = (0,0,1), the tangent along +x.
#pragma once

#include <cmath>

#include "brdffit/math.h"

namespace brdffit::models {

// Anisotropic GGX (Trowbridge-Reitz), normalised so that ∫ D (n·h) dωh = 1:
//   D(h) = 1 / (π αx αy ((hx/αx)² + (hy/αy)² + hz²)²)        (αx = αy = α: the isotropic form
//   α² / (π ((n·h)²(α²-1) + 1)²)).  Zero below the horizon.
template <class T>
T ggx_ndf(const Vec3& h, const T& alpha_x, const T& alpha_y) {
  if (h.z() <= 0.0) return T(0.0);
  const T sx = h.x() / alpha_x, sy = h.y() / alpha_y;
  const T q = sx * sx + sy * sy + h.z() * h.z();
  return 1.0 / (kPi * alpha_x * alpha_y * q * q);
}

// Smith's Λ for GGX in direction w (Heitz 2014, eq. 86): (-1 + √(1 + (αx²wx² + αy²wy²)/wz²)) / 2.
template <class T>
T ggx_smith_lambda(const Vec3& w, const T& alpha_x, const T& alpha_y) {
  using std::sqrt;
  const double z2 = w.z() * w.z();
  const T a2 = (alpha_x * alpha_x * (w.x() * w.x()) + alpha_y * alpha_y * (w.y() * w.y())) / z2;
  return (sqrt(1.0 + a2) - 1.0) * 0.5;
}

// Height-correlated Smith masking-shadowing G2 = 1 / (1 + Λ(l) + Λ(v)) (Heitz 2014, eq. 99),
// for l and v above the surface and on the front side of h.
template <class T>
T ggx_height_correlated_g2(const Vec3& l, const Vec3& v, const T& alpha_x, const T& alpha_y) {
  return 1.0 / (1.0 + ggx_smith_lambda(l, alpha_x, alpha_y) + ggx_smith_lambda(v, alpha_x, alpha_y));
}

// Fresnel reflectance of unpolarised light at a dielectric interface of relative index eta for
// the cosine c of the incident angle (Walter et al. 2007, eq. 22): with g = √(η² - 1 + c²),
//   F = ½ (g-c)²/(g+c)² · (1 + ((c(g+c) - 1) / (c(g-c) + 1))²);  1 for total internal reflection.
template <class T>
T dielectric_fresnel(double c, const T& eta) {
  using std::sqrt;
  const T g2 = eta * eta - 1.0 + c * c;
  if (!(g2 > T(0.0))) return T(1.0);
  const T g = sqrt(g2);
  const T a = (g - c) / (g + c), b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
  return 0.5 * a * a * (1.0 + b * b);
}

}  // namespace brdffit::models
