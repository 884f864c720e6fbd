// Values derived by hand from each literature model's formula (the derivation is in the comment
// above each expectation). Lambert and GGX are in test_models.cc, the other seed models in
// test_models_seed.cc.
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
