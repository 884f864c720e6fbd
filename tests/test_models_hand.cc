// Values derived by hand from each model's formula (the derivation is in the comment above
// each expectation), for the seed and literature models. Lambert and GGX are in test_models.cc.
#include <gtest/gtest.h>

#include "brdffit/model.h"
#include "test_util.h"

namespace brdffit {
namespace {

using test::dir;

// The model's shaded value for one channel when all colour channels are equal.
double shade1(const std::string& name, const std::vector<std::string>& params, const Vec3& l, const Vec3& v) {
  const Model* model = find_model(name);
  EXPECT_NE(model, nullptr) << name;
  const std::vector<double> values = parameter_values(*model, params);
  const Rgb<double> s = model->shade(values.data(), l, v);
  EXPECT_NEAR(s[0], s[1], 1e-15);
  EXPECT_NEAR(s[1], s[2], 1e-15);
  return s[0];
}

const double kSqrtHalf = std::sqrt(0.5);
const Vec3 kNormal(0, 0, 1);
const Vec3 k45X = dir(1, 0, 1);   // 45° towards +x
const Vec3 k45mX = dir(-1, 0, 1);  // 45° towards -x: the mirror of k45X

TEST(HalfLambert, HandValues) {
  // n·l = 1, w = 0.5: (0.5 + 0.5)² = 1.
  EXPECT_NEAR(shade1("half-lambert", {"albedo=0.8"}, kNormal, kNormal), 0.8, 1e-12);
  // n·l = cos45, w = 0.5: (0.5·0.7071 + 0.5)² = 0.72855.
  EXPECT_NEAR(shade1("half-lambert", {"albedo=1"}, k45X, kNormal), std::pow(0.5 * kSqrtHalf + 0.5, 2), 1e-12);
  // Raw n·l = -0.6 (light behind), w = 0.5: (−0.3 + 0.5)² = 0.04 — the back keeps shading.
  EXPECT_NEAR(shade1("half-lambert", {"albedo=1"}, Vec3(0.8, 0, -0.6), kNormal), 0.04, 1e-12);
  // w = 1 is (n·l)²: 0.5.
  EXPECT_NEAR(shade1("half-lambert", {"albedo=1", "wrap=1"}, k45X, kNormal), 0.5, 1e-12);
}

TEST(Wrap, HandValues) {
  // wrap 0, contrast 1 is n·l.
  EXPECT_NEAR(shade1("wrap", {"albedo=1", "wrap=0", "contrast=1"}, k45X, kNormal), kSqrtHalf, 1e-12);
  // n·l = 0, wrap 0.5, contrast 2: (0.5/1.5)² = 1/9.
  EXPECT_NEAR(shade1("wrap", {"albedo=1", "wrap=0.5", "contrast=2"}, Vec3(1, 0, 0), kNormal), 1.0 / 9, 1e-12);
  // n·l = -0.6, wrap 0.5: saturate(-0.1/1.5) = 0.
  EXPECT_NEAR(shade1("wrap", {"albedo=1", "wrap=0.5"}, Vec3(0.8, 0, -0.6), kNormal), 0.0, 1e-12);
}

TEST(Phong, HandValues) {
  // l at 45° towards +x, v at its mirror: r·v = 1 → 0.5·cos45 + 0.3·1.
  EXPECT_NEAR(shade1("phong", {"albedo=0.5", "specular=0.3", "shininess=10"}, k45X, k45mX), 0.5 * kSqrtHalf + 0.3,
              1e-12);
  // v = n: r·v = cos45 → 0.3·cos45^10 = 0.3/32.
  EXPECT_NEAR(shade1("phong", {"albedo=0", "specular=0.3", "shininess=10"}, k45X, kNormal), 0.3 / 32, 1e-12);
  // l = n, v 45° away: r = n, r·v = cos45, exponent 2 → 0.2 + 0.4·0.5.
  EXPECT_NEAR(shade1("phong", {"albedo=0.2", "specular=0.4", "shininess=2"}, kNormal, k45X), 0.2 + 0.2, 1e-12);
}

TEST(BlinnPhong, HandValues) {
  // Mirror pair: h = n, n·h = 1 → 0.5·cos45 + 0.3.
  EXPECT_NEAR(shade1("blinn-phong", {"albedo=0.5", "specular=0.3", "gloss=50"}, k45X, k45mX), 0.5 * kSqrtHalf + 0.3,
              1e-12);
  // l = n, v 60° away: h at 30°, n·h = cos30; gloss 2 → 0.75.
  EXPECT_NEAR(shade1("blinn-phong", {"albedo=0", "specular=1", "gloss=2"}, kNormal, dir(std::sqrt(3), 0, 1)), 0.75,
              1e-12);
  // Light below the horizon: nothing.
  EXPECT_NEAR(shade1("blinn-phong", {}, Vec3(0.8, 0, -0.6), kNormal), 0.0, 1e-12);
}

TEST(Banded, HandValues) {
  // 4 bands: n·l = 0.7071 lies in (0.5, 0.75] → 0.75.
  EXPECT_NEAR(shade1("banded", {"albedo=1", "steps=4"}, k45X, kNormal), 0.75, 1e-12);
  // n·l = 1 → top band 1.
  EXPECT_NEAR(shade1("banded", {"albedo=0.6", "steps=4"}, kNormal, kNormal), 0.6, 1e-12);
  // 2 bands: n·l = 0.3 → 0.5; 1 band: any lit point → 1.
  EXPECT_NEAR(shade1("banded", {"albedo=1", "steps=2"}, Vec3(std::sqrt(1 - 0.09), 0, 0.3), kNormal), 0.5, 1e-12);
  EXPECT_NEAR(shade1("banded", {"albedo=1", "steps=1"}, Vec3(std::sqrt(1 - 0.09), 0, 0.3), kNormal), 1.0, 1e-12);
}

TEST(Minnaert, HandValues) {
  // roughness 0 is n·l.
  EXPECT_NEAR(shade1("minnaert", {"albedo=1", "roughness=0"}, k45X, kNormal), kSqrtHalf, 1e-12);
  // n·l = n·v = cos45, k = 1: cos45·(0.5)¹ = 0.35355.
  EXPECT_NEAR(shade1("minnaert", {"albedo=1", "roughness=1"}, k45X, k45mX), kSqrtHalf * 0.5, 1e-12);
  // n·l = 1, n·v = 0.5, k = 2: 1·0.25.
  EXPECT_NEAR(shade1("minnaert", {"albedo=0.8", "roughness=2"}, kNormal, dir(std::sqrt(3), 0, 1)), 0.8 * 0.25, 1e-12);
}

TEST(OrenNayar, HandValues) {
  // σ = 0: A = 1, B = C = 0 → albedo·n·l.
  EXPECT_NEAR(shade1("oren-nayar", {"albedo=0.5", "roughness=0"}, k45X, kNormal), 0.5 * kSqrtHalf, 1e-12);
  // σ = 1, l = v = n: s = 1 - 1 = 0; A = 1 - 0.5/1.33, B = 0.17/1.13 → n·l·albedo·(A + albedo·B).
  {
    const double a = 1 - 0.5 / 1.33, b = 0.17 / 1.13;
    EXPECT_NEAR(shade1("oren-nayar", {"albedo=0.5", "roughness=1"}, kNormal, kNormal), 0.5 * (a + 0.5 * b), 1e-12);
  }
  // σ = 1, l = v both 45° towards +x: l·v = 1, s = 1 - 0.5 = 0.5, divided by
  // max(n·l, n·v) = cos45 → s = 0.7071; shade = n·l·(A + B + C·s) with albedo 1.
  {
    const double a = 1 - 0.5 / 1.33, b = 0.17 / 1.13, c = 0.45 / 1.09, s = 0.5 / kSqrtHalf;
    EXPECT_NEAR(shade1("oren-nayar", {"albedo=1", "roughness=1"}, k45X, k45X), kSqrtHalf * (a + b + c * s), 1e-12);
  }
}

TEST(Gaussian, HandValues) {
  // Mirror pair: θh = 0 → lobe 1.2: f = albedo/π + 1.2·specular; shade = f·cos45.
  EXPECT_NEAR(shade1("gaussian", {"albedo=0.3", "specular=0.5", "m=0.2"}, k45X, k45mX),
              (0.3 / kPi + 0.6) * kSqrtHalf, 1e-12);
  // l = n, v 60° away: θh = 30° = π/6; m = π/6 → lobe 1.2·e⁻¹.
  EXPECT_NEAR(shade1("gaussian", {"albedo=0", "specular=1", "m=0.5235987755982988"}, kNormal, dir(std::sqrt(3), 0, 1)),
              1.2 * std::exp(-1.0), 1e-12);
  // Light below the horizon: 0.
  EXPECT_NEAR(shade1("gaussian", {}, Vec3(0.8, 0, -0.6), kNormal), 0.0, 1e-12);
}

TEST(Beckmann, HandValues) {
  // h = n: D = 1/(π m²); m = 0.5 → 4/π; f = 0.2/π + 0.1·4/π at l = v = n.
  EXPECT_NEAR(shade1("beckmann", {"albedo=0.2", "specular=0.1", "m=0.5"}, kNormal, kNormal), 0.2 / kPi + 0.4 / kPi,
              1e-12);
  // l = n, v 60° away: θh = 30°, tan² = 1/3, cos⁴ = 9/16; m = 1: D = e^(-1/3)/(π·9/16).
  EXPECT_NEAR(shade1("beckmann", {"albedo=0", "specular=1", "m=1"}, kNormal, dir(std::sqrt(3), 0, 1)),
              std::exp(-1.0 / 3) / (kPi * 9.0 / 16), 1e-12);
  // Diffuse only: albedo/π·cos45.
  EXPECT_NEAR(shade1("beckmann", {"albedo=1", "specular=0"}, k45X, kNormal), kSqrtHalf / kPi, 1e-12);
}

TEST(Toon, HandValues) {
  // l = v = n: light 1; n·h = 1 → highlight 1 → spec 1·specular; rimDot = 0 → rim 0.
  EXPECT_NEAR(shade1("toon", {"albedo=0.5", "specular=0.4"}, kNormal, kNormal), 0.5 * (1 + 0.4), 1e-12);
  // l = n, v 60° away: n·h = cos30 = 0.866, ^(32²) ≈ 0 → no highlight; rimDot = 0.5,
  // (n·l)^0.1 = 1 → 0.5 < rim_amount 0.716 → no rim: albedo·1.
  EXPECT_NEAR(shade1("toon", {"albedo=0.5"}, kNormal, dir(std::sqrt(3), 0, 1)), 0.5, 1e-12);
  // Grazing view v = (0.995,0,0.0999): rimDot ≈ 0.9, light at n → rim 1; n·h small → no highlight.
  EXPECT_NEAR(shade1("toon", {"albedo=0.5"}, kNormal, dir(1, 0, 0.1)), 0.5 * 2, 1e-12);
  // Light just below the horizon: light 0, no rim, no highlight.
  EXPECT_NEAR(shade1("toon", {"albedo=0.5"}, Vec3(0.8, 0, -0.6), kNormal), 0.0, 1e-12);
}

TEST(CookTorrance, HandValues) {
  // l = v = n: h = n, D = 1/(π m²), G = min(1, 2, 2) = 1, F = f0 at l·h = 1:
  // f = albedo/π + specular·f0/(π m²)/π.
  EXPECT_NEAR(shade1("cook-torrance", {"albedo=0.1", "specular=0.5", "f0=0.04", "m=0.2"}, kNormal, kNormal),
              0.1 / kPi + 0.5 * 0.04 / (kPi * 0.04) / kPi, 1e-12);
  // Mirror pair at 45°: h = n, D = 1/(π m²), l·h = cos45, G = min(1, 2·1·cos45/cos45) = 1,
  // F = f0 + (1-f0)(1-cos45)^5; f_spec = D·F/(π·0.5); shade = f·cos45.
  {
    const double m = 0.3, f0 = 0.1, d = 1 / (kPi * m * m), f = f0 + (1 - f0) * std::pow(1 - kSqrtHalf, 5);
    EXPECT_NEAR(shade1("cook-torrance", {"albedo=0", "specular=1", "f0=0.1", "m=0.3"}, k45X, k45mX),
                d * f / (kPi * 0.5) * kSqrtHalf, 1e-12);
  }
  // l = n, v 60° away: h at 30°, n·h = cos30, l·h = cos30; G = min(1, 2cos30·1/cos30, 2cos30·0.5/cos30) = 1;
  // m = 1: D = e^(-1/3)/(π·9/16); F = 1 when f0 = 1: f_spec = D/(π·1·0.5).
  EXPECT_NEAR(shade1("cook-torrance", {"albedo=0", "specular=1", "f0=1", "m=1"}, kNormal, dir(std::sqrt(3), 0, 1)),
              std::exp(-1.0 / 3) / (kPi * 9.0 / 16) / (kPi * 0.5), 1e-12);
}

TEST(Ward, HandValues) {
  // l = v = n: tanθh = 0, f = albedo/π + specular/(4π α²).
  EXPECT_NEAR(shade1("ward", {"albedo=0.2", "specular=0.1", "alpha=0.5"}, kNormal, kNormal),
              0.2 / kPi + 0.1 / (4 * kPi * 0.25), 1e-12);
  // Mirror pair at 45°: θh = 0, √(n·l n·v) = 0.5·... = cos45: f_spec = s/(4πα²·cos45); shade·cos45.
  EXPECT_NEAR(shade1("ward", {"albedo=0", "specular=1", "alpha=0.2"}, k45X, k45mX), 1 / (4 * kPi * 0.04), 1e-12);
  // l = n, v 60° away: tan²θh = 1/3; α = 1: e^(-1/3)/(4π·√0.5).
  EXPECT_NEAR(shade1("ward", {"albedo=0", "specular=1", "alpha=1"}, kNormal, dir(std::sqrt(3), 0, 1)),
              std::exp(-1.0 / 3) / (4 * kPi * std::sqrt(0.5)), 1e-12);
}

TEST(AshikhminShirley, HandValues) {
  // l = v = n: n·h = 1, l·h = 1, F = f0, max(n·l,n·v) = 1: f_spec = (n+1)/(8π)·f0.
  EXPECT_NEAR(shade1("ashikhmin-shirley", {"albedo=0.3", "specular=1", "f0=0.05", "n=100"}, kNormal, kNormal),
              0.3 / kPi + 101 / (8 * kPi) * 0.05, 1e-12);
  // Mirror pair at 45°: n·h = 1, l·h = cos45, max = cos45: f_spec = (n+1)/(8π)·F/(0.5); shade·cos45.
  {
    const double f = 0.2 + 0.8 * std::pow(1 - kSqrtHalf, 5);
    EXPECT_NEAR(shade1("ashikhmin-shirley", {"albedo=0", "specular=1", "f0=0.2", "n=10"}, k45X, k45mX),
                11 / (8 * kPi) * f / 0.5 * kSqrtHalf, 1e-12);
  }
  // l = n, v 60° away: n·h = l·h = cos30, max(1, 0.5) = 1, f0 = 1: (n+1)/(8π)·cos30^n/cos30.
  {
    const double c = std::cos(kPi / 6);
    EXPECT_NEAR(shade1("ashikhmin-shirley", {"albedo=0", "specular=1", "f0=1", "n=4"}, kNormal, dir(std::sqrt(3), 0, 1)),
                5 / (8 * kPi) * std::pow(c, 4) / c, 1e-12);
  }
}

TEST(Lafortune, HandValues) {
  // Mirror pair at 45°, cxy = -cz = -0.5: dot = -0.5·(-0.5) + 0.5·0.5 = 0.5, c = 0.5 → (1)^n:
  // f_spec = (n+2)/(2π); shade = f·cos45.
  EXPECT_NEAR(shade1("lafortune", {"albedo=0", "specular=1", "cxy=-0.5", "cz=0.5", "n=20"}, k45X, k45mX),
              22 / (2 * kPi) * kSqrtHalf, 1e-12);
  // l = v = n: dot = cz, c = max(0.3, 0.6) = 0.6 → 1^n; plus albedo/π.
  EXPECT_NEAR(shade1("lafortune", {"albedo=0.3", "specular=0.5", "cxy=-0.3", "cz=0.6", "n=3"}, kNormal, kNormal),
              0.3 / kPi + 0.5 * 5 / (2 * kPi), 1e-12);
  // l = n, v 60° away: lx vx + ly vy = 0, lz vz = 0.5; cz = 1: (0.5)^2 with n = 2 → 4/(2π)·0.25.
  EXPECT_NEAR(shade1("lafortune", {"albedo=0", "specular=1", "cxy=-1", "cz=1", "n=2"}, kNormal, dir(std::sqrt(3), 0, 1)),
              4 / (2 * kPi) * 0.25, 1e-12);
}

}  // namespace
}  // namespace brdffit
