// Rusinkiewicz's half/difference parameterisation of a pair of directions (1998), as used by
// the MERL BRDF database: h = normalize(l + v) gives (θh, φh); the difference vector d is l
// expressed in a frame where h is the pole: d = Ry(-θh)·Rz(-φh)·l, giving (θd, φd).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "brdffit/math.h"

namespace brdffit {

struct HalfDiff {
  double theta_h = 0, phi_h = 0, theta_d = 0, phi_d = 0;
};

inline Vec3 rotate_z(const Vec3& d, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * d.x() - s * d.y(), s * d.x() + c * d.y(), d.z()};
}

inline Vec3 rotate_y(const Vec3& d, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * d.x() + s * d.z(), d.y(), -s * d.x() + c * d.z()};
}

// (l, v) unit directions in the local frame → half/difference angles.
inline HalfDiff to_half_diff(const Vec3& l, const Vec3& v) {
  const Vec3 h = half_vector(l, v);
  HalfDiff a;
  a.theta_h = std::acos(std::clamp(h.z(), -1.0, 1.0));
  a.phi_h = std::atan2(h.y(), h.x());
  const Vec3 d = rotate_y(rotate_z(l, -a.phi_h), -a.theta_h);
  a.theta_d = std::acos(std::clamp(d.z(), -1.0, 1.0));
  a.phi_d = std::atan2(d.y(), d.x());
  return a;
}

// Half/difference angles → (l, v): the inverse of to_half_diff.
inline void from_half_diff(const HalfDiff& a, Vec3& l, Vec3& v) {
  const Vec3 d(std::sin(a.theta_d) * std::cos(a.phi_d), std::sin(a.theta_d) * std::sin(a.phi_d), std::cos(a.theta_d));
  l = rotate_z(rotate_y(d, a.theta_h), a.phi_h);
  const Vec3 h(std::sin(a.theta_h) * std::cos(a.phi_h), std::sin(a.theta_h) * std::sin(a.phi_h), std::cos(a.theta_h));
  v = 2.0 * l.dot(h) * h - l;
}

// A regular grid over (θh, θd, φd) as MERL tables use it: θh bins uniform in √(θh/(π/2)),
// concentrating bins near the specular peak; θd uniform over [0, π/2); φd uniform over
// [0, period) (period π when reciprocity folds φd+π onto φd, 2π otherwise).
struct HalfDiffGrid {
  int theta_h_bins = 90, theta_d_bins = 90, phi_d_bins = 180;
  double phi_d_period = kPi;

  HalfDiff centre(int i_theta_h, int i_theta_d, int i_phi_d) const {
    HalfDiff a;
    const double u = (i_theta_h + 0.5) / theta_h_bins;
    a.theta_h = u * u * (kPi / 2);
    a.theta_d = (i_theta_d + 0.5) / theta_d_bins * (kPi / 2);
    a.phi_d = (i_phi_d + 0.5) / phi_d_bins * phi_d_period;
    return a;
  }

  // The measure of direction pairs a bin covers, dωi·dωo = 4 cosθd sinθd sinθh dθh dθd dφd dφh,
  // integrated exactly over the bin's extent in θh (√-spaced), θd and φd, and over φh ∈ [0, 2π)
  // (isotropy): 4 · (cosθh0 - cosθh1) · (sin²θd1 - sin²θd0)/2 · Δφd · 2π. Bins that straddle
  // the horizon keep their whole measure.
  double weight(int i_theta_h, int i_theta_d, int /*i_phi_d*/) const {
    const double u0 = double(i_theta_h) / theta_h_bins, u1 = double(i_theta_h + 1) / theta_h_bins;
    const double theta_h0 = u0 * u0 * (kPi / 2), theta_h1 = u1 * u1 * (kPi / 2);
    const double sin_theta_d0 = std::sin(double(i_theta_d) / theta_d_bins * (kPi / 2));
    const double sin_theta_d1 = std::sin(double(i_theta_d + 1) / theta_d_bins * (kPi / 2));
    const double d_phi_d = phi_d_period / phi_d_bins;
    return 4 * (std::cos(theta_h0) - std::cos(theta_h1)) * 0.5 *
           (sin_theta_d1 * sin_theta_d1 - sin_theta_d0 * sin_theta_d0) * d_phi_d * 2 * kPi;
  }

  // Calls visit(iθh, iθd, iφd, l, v, weight) for every bin whose centre pair lies above the
  // horizon: from_half_diff(centre(...)) and weight(...), with the sines and cosines of each axis
  // computed once (a full MERL table has 1.46 million bins).
  template <class Visit>
  void for_each_bin_above_horizon(Visit&& visit) const {
    std::vector<double> sin_phi_d(phi_d_bins), cos_phi_d(phi_d_bins);
    for (int ip = 0; ip < phi_d_bins; ++ip) {
      const double phi_d = centre(0, 0, ip).phi_d;
      sin_phi_d[ip] = std::sin(phi_d);
      cos_phi_d[ip] = std::cos(phi_d);
    }
    for (int ih = 0; ih < theta_h_bins; ++ih) {
      const double theta_h = centre(ih, 0, 0).theta_h, sin_h = std::sin(theta_h), cos_h = std::cos(theta_h);
      for (int id = 0; id < theta_d_bins; ++id) {
        const double theta_d = centre(ih, id, 0).theta_d, sin_d = std::sin(theta_d), cos_d = std::cos(theta_d);
        const double bin_weight = weight(ih, id, 0);
        for (int ip = 0; ip < phi_d_bins; ++ip) {
          // from_half_diff with φh = 0: l is d turned by θh about y, v its mirror about h.
          const double dx = sin_d * cos_phi_d[ip], dy = sin_d * sin_phi_d[ip];
          const Vec3 l(cos_h * dx + sin_h * cos_d, dy, -sin_h * dx + cos_h * cos_d);
          const Vec3 h(sin_h, 0.0, cos_h);
          const Vec3 v = 2.0 * l.dot(h) * h - l;
          if (l.z() > 0.0 && v.z() > 0.0) visit(ih, id, ip, l, v, bin_weight);
        }
      }
    }
  }
};

// Turns successive direction pairs about the normal by φh = 2π·frac(k·(√5-1)/2) for the k-th
// pair (a Kronecker sequence: deterministic and evenly spread). A table's bins put every half
// vector at φh = 0; an isotropic table's value is the same at any φh, so its samples spread this
// way are still its measurements, and they constrain a model over every azimuth. Without the
// spread an anisotropic model sees one slice and invents an orientation.
class AzimuthSpread {
 public:
  void turn(Vec3& l, Vec3& v) {
    const double phi_h = 2 * kPi * std::fmod(double(++count_) * kGoldenFraction, 1.0);
    l = rotate_z(l, phi_h);
    v = rotate_z(v, phi_h);
  }

 private:
  static constexpr double kGoldenFraction = 0.6180339887498949;  // (√5-1)/2
  uint64_t count_ = 0;
};

}  // namespace brdffit
