// Löw 2012 (low-smooth, low-microfacet, low-cook-torrance, low-ashikhmin-shirley) and Bagher
// 2012 (sgd): values at hand-computed points, published parameters, derivatives, reciprocity,
// and the published-fit reader and `score --published` on these files.
//
// Fresnel reference: the tests compute a dielectric's reflectance from Snell's law and the two
// polarised amplitudes, ½(r_s² + r_p²), not from Cook's algebraic form the models use.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <limits>
#include <random>

#include <ceres/jet.h>
#include <nlohmann/json.hpp>

#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/model.h"
#include "brdffit/models/sgd.h"
#include "brdffit/published_fits.h"
#include "brdffit/registry.h"
#include "test_util.h"

namespace brdffit {
namespace {

using test::dir;

// Unpolarised Fresnel reflectance from air into a dielectric of index eta at incidence cosine ci.
double snell_fresnel(double eta, double ci) {
  const double si2 = 1.0 - ci * ci;
  const double ct = std::sqrt(1.0 - si2 / (eta * eta));
  const double rs = (ci - eta * ct) / (ci + eta * ct);
  const double rp = (eta * ci - ct) / (eta * ci + ct);
  return 0.5 * (rs * rs + rp * rp);
}

std::vector<double> values_of(const std::string& model, const std::vector<std::string>& params) {
  return parameter_values(*find_model(model), params);
}

Rgb<double> brdf(const std::string& model, const std::vector<double>& values, const Vec3& l, const Vec3& v) {
  return *find_model(model)->brdf(values.data(), l, v);
}

using test::expect_rgb_near;

const char* const kModels[] = {"low-smooth", "low-microfacet", "low-cook-torrance", "low-ashikhmin-shirley", "sgd"};

// Mirror pair 36.87° from the normal (3-4-5: cosines exact) and an off-specular pair.
using test::kNormal;
const Vec3 kL(0.6, 0, 0.8), kMirrorV(-0.6, 0, 0.8);

TEST(LowModels, FresnelReferenceIsRight) {
  // Normal incidence: ((η−1)/(η+1))²; glass at 45°: 0.0500 (textbook value ≈ 5 %).
  EXPECT_NEAR(snell_fresnel(1.5, 1.0), 0.04, 1e-15);
  EXPECT_NEAR(snell_fresnel(1.5, std::sqrt(0.5)), 0.0502, 2e-4);
}

TEST(LowSmooth, HandValues) {
  const std::vector<double> p =
      values_of("low-smooth", {"albedo=0.1,0.2,0.3", "A=2,1,0.5", "B=50", "C=1.5", "eta=1.5"});
  // l = v = n: l_xy + v_xy = 0 (S = 1), cosθd = 1, F = 0.04.
  expect_rgb_near(brdf("low-smooth", p, kNormal, kNormal),
                  Rgb<double>(0.1 / kPi + 2 * 0.04, 0.2 / kPi + 1 * 0.04, 0.3 / kPi + 0.5 * 0.04));
  // Mirror pair: S = 1, |l_xy − v_xy|² = 1.44, cosθd = √(1 − 0.36) = 0.8.
  const double f_mirror = snell_fresnel(1.5, 0.8);
  expect_rgb_near(brdf("low-smooth", p, kL, kMirrorV),
                  Rgb<double>(0.1 / kPi + 2 * f_mirror, 0.2 / kPi + f_mirror, 0.3 / kPi + 0.5 * f_mirror));
  // l = (0.6,0,0.8), v = n: |l_xy + v_xy|² = 0.36, S = (1 + 18)^−1.5, cosθd = √(1 − 0.09).
  const double lobe = std::pow(19.0, -1.5) * snell_fresnel(1.5, std::sqrt(0.91));
  const Rgb<double> shaded = find_model("low-smooth")->shade(p.data(), kL, kNormal);
  expect_rgb_near(shaded, 0.8 * Rgb<double>(0.1 / kPi + 2 * lobe, 0.2 / kPi + lobe, 0.3 / kPi + 0.5 * lobe));
}

TEST(LowMicrofacet, HandValues) {
  const std::vector<double> p = values_of("low-microfacet", {"albedo=0.1", "A=3", "B=400", "C=0.8", "eta=2"});
  // l = v = n: S = 1, G = 1, F(2, 1) = 1/9: f = 0.1/π + 3·(1/9)/π.
  expect_rgb_near(brdf("low-microfacet", p, kNormal, kNormal), Rgb<double>::Constant(0.1 / kPi + 3.0 / 9.0 / kPi));
  // Mirror pair: h = n, S = 1, G = min(1, 2) = 1, l·h = 0.8: f = 0.1/π + 3·F/(π·0.64).
  expect_rgb_near(brdf("low-microfacet", p, kL, kMirrorV),
                  Rgb<double>::Constant(0.1 / kPi + 3 * snell_fresnel(2, 0.8) / (kPi * 0.64)));
  // l = (0.6,0,0.8), v = n: l + v = (0.6,0,1.8), n·h = l·h = 1.8/√3.6; G = min(1, 1.6, 2) = 1.
  const double nh = 1.8 / std::sqrt(3.6);
  const double lobe = 3 * std::pow(1 + 400 * (1 - nh), -0.8) * snell_fresnel(2, nh) / (kPi * 0.8);
  expect_rgb_near(brdf("low-microfacet", p, kL, kNormal), Rgb<double>::Constant(0.1 / kPi + lobe));
}

TEST(LowCookTorrance, HandValues) {
  const std::vector<double> p = values_of("low-cook-torrance", {"albedo=0.2", "specular=0.5", "m=0.3", "eta=1.5"});
  // l = v = n: D = 1/m² (no 1/π), G = 1, F = 0.04: f = 0.2/π + 0.5·0.04/(π·0.09).
  expect_rgb_near(brdf("low-cook-torrance", p, kNormal, kNormal),
                  Rgb<double>::Constant(0.2 / kPi + 0.5 * 0.04 / (kPi * 0.09)));
  // l = (0.6,0,0.8), v = n: tan²θh = (0.6/1.8)² = 1/9, cos²θh = 0.9, G = 1, l·h = √0.9.
  const double d = std::exp(-1.0 / 9.0 / 0.09) / (0.09 * 0.81);
  const double lobe = 0.5 * d * snell_fresnel(1.5, std::sqrt(0.9)) / (kPi * 0.8);
  expect_rgb_near(brdf("low-cook-torrance", p, kL, kNormal), Rgb<double>::Constant(0.2 / kPi + lobe));
}

TEST(LowAshikhminShirley, HandValues) {
  const std::vector<double> p =
      values_of("low-ashikhmin-shirley", {"albedo=0", "specular=0.4,0.2,0.1", "n=100", "eta=1.5"});
  // l = v = n: (n+1)/(8π)·1·F(1.5, 1)/(1·1).
  const double at_normal = 101 / (8 * kPi) * 0.04;
  expect_rgb_near(brdf("low-ashikhmin-shirley", p, kNormal, kNormal),
                  Rgb<double>(0.4 * at_normal, 0.2 * at_normal, 0.1 * at_normal));
  // l = (0.6,0,0.8), v = n: n·h = l·h = √0.9, max(n·l, n·v) = 1.
  const double c = std::sqrt(0.9);
  const double lobe = 101 / (8 * kPi) * std::pow(c, 100) * snell_fresnel(1.5, c) / c;
  expect_rgb_near(brdf("low-ashikhmin-shirley", p, kL, kNormal), Rgb<double>(0.4 * lobe, 0.2 * lobe, 0.1 * lobe));
}

TEST(Sgd, HandValues) {
  // One set of values per channel, so each channel checks a different branch.
  const std::vector<double> p =
      values_of("sgd", {"albedo=0.1", "specular=1", "alpha=0.1,0.2,0.05", "p=0.5,0,1", "f0=0.05,0.5,0.05",
                        "f1=0,0.2,-0.5", "K=10,5,20", "lambda=2,0,1", "c=0.5,1,1e4", "k=2,1,3", "theta0=0.2,0.5,-0.3"});
  // Mirror pair: h = n, tan²θh = 0, t = α; l·h = 0.8, θl = θv = acos 0.8.
  const double theta = std::acos(0.8), schlick = std::pow(0.2, 5);
  auto lobe = [&](double alpha, double p_, double f0, double f1, double K, double g1) {
    const double d = K * std::exp(-alpha) / std::pow(alpha, p_) / kPi;
    const double fresnel = f0 + (1 - f0) * schlick - f1 * 0.8;
    return d * g1 * g1 * fresnel / (kPi * 0.64);
  };
  // R: θ > θ0 = 0.2: G1 = 1 + 2(1 − exp(0.5 (θ − 0.2)²)).
  const double g1_r = 1 + 2 * (1 - std::exp(0.5 * std::pow(theta - 0.2, 2)));
  // G: Λ = 0, G1 = 1. B: θ0 < 0 and c = 1e4: c (θ+0.3)³ = 8390 is above the cap, G1 clamps to 0.
  expect_rgb_near(brdf("sgd", p, kL, kMirrorV), Rgb<double>(0.1 / kPi + lobe(0.1, 0.5, 0.05, 0, 10, g1_r),
                                                            0.1 / kPi + lobe(0.2, 0, 0.5, 0.2, 5, 1), 0.1 / kPi));
  // At normal incidence (θ = 0): R and G below θ0 (G1 = 1); B with θ0 = −0.3 still applies
  // the formula: c·0.3³ = 270, above the cap, clamped to 0. l·h = 1: F = f0 − f1.
  const double d_r = 10 * std::exp(-0.1) / std::pow(0.1, 0.5) / kPi, d_g = 5 * std::exp(-0.2) / kPi;
  expect_rgb_near(brdf("sgd", p, kNormal, kNormal),
                  Rgb<double>(0.1 / kPi + d_r * 0.05 / kPi, 0.1 / kPi + d_g * 0.3 / kPi, 0.1 / kPi));
  // Negative θ0 with a moderate c: G1(0) = 1 + Λ(1 − exp(c·0.3^k)) < 1.
  const std::vector<double> q = values_of("sgd", {"albedo=0", "specular=1", "alpha=0.1", "p=0.5", "f0=0.05", "f1=0",
                                                  "K=10", "lambda=1", "c=2", "k=2", "theta0=-0.3"});
  const double g1 = 1 + (1 - std::exp(2 * 0.09));
  EXPECT_NEAR(brdf("sgd", q, kNormal, kNormal)[0], d_r * 0.05 * g1 * g1 / kPi, 1e-12);
  // c = 0 (no shadowing; below the bounds, where a fit's bound handling may put it) and k at
  // its bound 1000 with θ0 = −π/2 ((θ−θ0)^k ≈ e^1145): finite values and derivatives.
  const Model& sgd = *find_model("sgd");
  for (auto [c_value, k_value] : {std::pair{0.0, 2.0}, std::pair{1e-10, 1000.0}}) {
    std::vector<double> r = q;
    std::fill_n(r.begin() + sgd.offset_of("c"), 3, c_value);
    std::fill_n(r.begin() + sgd.offset_of("k"), 3, k_value);
    std::fill_n(r.begin() + sgd.offset_of("theta0"), 3, -kPi / 2);
    std::vector<double> jacobian(3 * sgd.num_values());
    const Rgb<double> s = sgd.shade_with_jacobian(r.data(), kL, kMirrorV, jacobian.data());
    EXPECT_TRUE(s.allFinite());
    for (double x : jacobian) EXPECT_TRUE(std::isfinite(x)) << c_value << " " << k_value;
  }
}

TEST(LowModels, ContainLambertExactly) {
  std::mt19937_64 rng(5);
  const Model& lambert = *find_model("lambert");
  for (const char* name : kModels) {
    SCOPED_TRACE(name);
    const Model& model = *find_model(name);
    ASSERT_GE(model.nestings().size(), 1u);
    const Nesting& nesting = model.nestings()[0];
    EXPECT_EQ(nesting.inner, "lambert");
    EXPECT_TRUE(nesting.exact);
    const std::vector<double> inner = {0.3, 0.2, 0.1};
    const std::vector<double> outer = embed_values(model, nesting, lambert, inner);
    for (int i = 0; i < 20; ++i) {
      const Vec3 l = test::random_upper_direction(rng), v = test::random_upper_direction(rng);
      expect_rgb_near(model.shade(outer.data(), l, v), lambert.shade(inner.data(), l, v), 1e-15);
    }
  }
}

TEST(Sgd, ShadowingWhereItsExponentIsBelowAUnitInTheLastPlaceOfOne) {
  // G1 = 1 + Λ(1 − exp(x)), x = c(θ−θ0)^k. Where x < 2⁻⁶⁰ exp(x) rounds to 1 and the model skips
  // the exps; the value must still be the formula's to the bit, and the Jets' derivatives its
  // own: by c −Λe^x(θ−θ0)^k, tiny but not 0 (a fit's Jacobian needs them where all are tiny).
  using models::SgdLobe;
  const double theta = 1.0, theta0 = 0.2, lambda = 2.0, k = 24.5;
  const double power = std::pow(theta - theta0, k);
  for (double x : {0x1p-70, 0x1p-61, 0x1p-59, 0x1p-40, 1e-3}) {
    SCOPED_TRACE(x);
    const double c = x / power;
    EXPECT_EQ(SgdLobe::shadowing(lambda, c, k, theta0, theta), 1.0 + lambda * (1.0 - std::exp(c * power)));
    using Jet = ceres::Jet<double, 4>;
    const Jet g = SgdLobe::shadowing(Jet(lambda, 0), Jet(c, 1), Jet(k, 2), Jet(theta0, 3), theta);
    const double e = std::exp(c * power), log_base = std::log(theta - theta0);
    EXPECT_EQ(g.a, 1.0 + lambda * (1.0 - e));
    EXPECT_DOUBLE_EQ(g.v[0], 1.0 - e);
    EXPECT_DOUBLE_EQ(g.v[1], -lambda * e * power);
    EXPECT_DOUBLE_EQ(g.v[2], -lambda * e * c * power * log_base);
    EXPECT_DOUBLE_EQ(g.v[3], lambda * e * c * power * k / (theta - theta0));
  }
  // x = 2⁻⁴⁰ is well within a double's reach of 1: G1 is not 1 there.
  EXPECT_LT(SgdLobe::shadowing(lambda, 0x1p-40 / power, k, theta0, theta), 1.0);
}

TEST(Sgd, ContainsCookTorranceWhereItsShadowingIsOne) {
  // The approximate nesting: Beckmann's D and Schlick's F are reproduced exactly; only the
  // V-groove G is missing, so where G = 1 (l = (0.6,0,0.8), v = n: min(1, 1.6, 2)) the two agree.
  const Model& sgd = *find_model("sgd");
  const Model& ct = *find_model("cook-torrance");
  ASSERT_EQ(sgd.nestings().size(), 2u);
  const Nesting& nesting = sgd.nestings()[1];
  EXPECT_EQ(nesting.inner, "cook-torrance");
  EXPECT_FALSE(nesting.exact);
  const std::vector<double> inner =
      parameter_values(ct, {"albedo=0.1,0.2,0.3", "specular=0.5,0.4,0.3", "f0=0.2", "m=0.3"});
  const std::vector<double> outer = embed_values(sgd, nesting, ct, inner);
  EXPECT_NEAR(outer[sgd.offset_of("alpha")], 0.09, 1e-15);
  EXPECT_NEAR(outer[sgd.offset_of("K")], std::exp(0.09) / 0.09, 1e-12);
  expect_rgb_near(sgd.shade(outer.data(), kL, kNormal), ct.shade(inner.data(), kL, kNormal), 1e-12);
}

TEST(LowModels, AutodiffMatchesFiniteDifferencesAndIsReciprocal) {
  std::mt19937_64 rng(17);
  for (const char* name : kModels) {
    SCOPED_TRACE(name);
    const Model& m = *find_model(name);
    const int n = m.num_values();
    for (int trial = 0; trial < 30; ++trial) {
      const std::vector<double> values = test::random_values(m, rng);
      const Vec3 l = test::random_upper_direction(rng, 0.1), v = test::random_upper_direction(rng, 0.1);
      // Reciprocity: every one of these models is symmetric in l and v.
      const Rgb<double> a = *m.brdf(values.data(), l, v), b = *m.brdf(values.data(), v, l);
      expect_rgb_near(a, b, 1e-10);
      std::vector<double> jac(3 * n);
      const Rgb<double> shaded = m.shade_with_jacobian(values.data(), l, v, jac.data());
      for (int i = 0; i < n; ++i) {
        const double h = 1e-6 * std::max(1e-3, std::abs(values[i]));
        std::vector<double> up = values, down = values;
        up[i] += h;
        down[i] -= h;
        const Rgb<double> fd = (m.shade(up.data(), l, v) - m.shade(down.data(), l, v)) / (2 * h);
        for (int c = 0; c < 3; ++c) {
          // Plus the difference quotient's round-off, ~ε·|shade|/h (these lobes reach 1e5).
          const double round_off = 10 * std::numeric_limits<double>::epsilon() * std::abs(shaded[c]) / h;
          EXPECT_NEAR(jac[c * n + i], fd[c],
                      1e-5 * std::max({1e-6, std::abs(jac[c * n + i]), std::abs(fd[c])}) + round_off)
              << m.parameters()[0].name << " value " << i << " channel " << c;
        }
      }
    }
  }
}

// The published fits bundled with the project (data/published-fits: BBM's files, with its licence).
using test::kPublishedFits;

TEST(LowModels, PublishedParametersReproduceIndependentValues) {
  const std::string& fits = kPublishedFits;
  // low_cooktorrance_E2.fit, blue-acrylic: Lambertian [0.0162, 0.0399, 0.109],
  // LowCookTorrance(albedo = [0.06877, 0.06156, 0.05938], roughness = 0.01082, eta = 1.29353).
  // At l = v = n: f = albedo/π + albedo_s·F(η, 1)/(π m²).
  const auto ct =
      find_published_fit(fits + "/low_cooktorrance_E2.fit", "blue-acrylic", *find_model("low-cook-torrance"));
  ASSERT_TRUE(ct.has_value());
  const double f_ct = snell_fresnel(1.29353, 1.0) / (kPi * 0.01082 * 0.01082);
  expect_rgb_near(
      brdf("low-cook-torrance", ct->values, kNormal, kNormal),
      Rgb<double>(0.0162 / kPi + 0.06877 * f_ct, 0.0399 / kPi + 0.06156 * f_ct, 0.109 / kPi + 0.05938 * f_ct), 1e-12);
  // low_lowsmooth_E2.fit, red-fabric: Lambertian [0.187, 0.0208, 0.0043], LowSmooth(A = [0.90493,
  // 0.29388, 0.25333], B = 15.477787, C = 0.50072, eta = 1.42381), at l = (0.6,0,0.8), v = n.
  const auto smooth = find_published_fit(fits + "/low_lowsmooth_E2.fit", "red-fabric", *find_model("low-smooth"));
  ASSERT_TRUE(smooth.has_value());
  const double s = std::pow(1 + 15.477787 * 0.36, -0.50072) * snell_fresnel(1.42381, std::sqrt(0.91));
  expect_rgb_near(brdf("low-smooth", smooth->values, kL, kNormal),
                  Rgb<double>(0.187 / kPi + 0.90493 * s, 0.0208 / kPi + 0.29388 * s, 0.0043 / kPi + 0.25333 * s),
                  1e-12);
  // bagher_sgd.fit, gold-metallic-paint, red channel: Lambertian 0.0178625, albedo 0.17127,
  // alpha 0.127954, p 0.781093, f0 1.00776e-12, f1 -1, K 5.90039, Lambda 2.7548, c 9.46481e-08,
  // k 23.8811, theta0 -0.303345; mirror pair at acos 0.8 (h = n).
  const auto sgd = find_published_fit(fits + "/bagher_sgd.fit", "gold-metallic-paint", *find_model("sgd"));
  ASSERT_TRUE(sgd.has_value());
  const double theta = std::acos(0.8);
  const double g1 = 1 + 2.7548 * (1 - std::exp(9.46481e-08 * std::pow(theta + 0.303345, 23.8811)));
  const double d = 5.90039 * std::exp(-0.127954) / std::pow(0.127954, 0.781093) / kPi;
  const double fresnel = 1.00776e-12 + (1 - 1.00776e-12) * std::pow(0.2, 5) + 0.8;
  const double expected = 0.0178625 / kPi + 0.17127 * d * g1 * g1 * fresnel / (kPi * 0.64);
  EXPECT_NEAR(brdf("sgd", sgd->values, kL, kMirrorV)[0], expected, 1e-12 * expected);
}

TEST(LowModels, EveryPublishedLineOfTheirFilesMaps) {
  const std::string& fits = kPublishedFits;
  const std::vector<std::pair<const char*, const char*>> files = {
      {"low-smooth", "low_lowsmooth_E2.fit"},
      {"low-microfacet", "low_lowmicrofacet_E2.fit"},
      {"low-cook-torrance", "low_cooktorrance_E1.fit"},
      {"low-cook-torrance", "low_cooktorrance_E2.fit"},
      {"low-ashikhmin-shirley", "low_ashikhminshirley_E1.fit"},
      {"low-ashikhmin-shirley", "low_ashikhminshirley_E2.fit"},
      {"sgd", "bagher_sgd.fit"}};
  std::mt19937_64 rng(3);
  for (const auto& [name, file] : files) {
    const Model& model = *find_model(name);
    const auto all = read_published_fits(fits + "/" + file);
    EXPECT_GE(all.size(), 90u) << file;
    for (const auto& [material, terms] : all) {
      SCOPED_TRACE(std::string(file) + " " + material);
      const auto values = to_model_values(model, terms);
      ASSERT_TRUE(values.has_value());
      // Finite and non-negative, values and derivatives, at random and mirror pairs.
      std::vector<double> jacobian(3 * model.num_values());
      for (int i = 0; i < 20; ++i) {
        const Vec3 l = test::random_upper_direction(rng, 0.01);
        const Vec3 v = i % 2 ? test::random_upper_direction(rng, 0.01) : Vec3(-l.x(), -l.y(), l.z());
        const Rgb<double> s = model.shade_with_jacobian(values->data(), l, v, jacobian.data());
        ASSERT_TRUE(s.allFinite());
        EXPECT_GE(s.minCoeff(), 0.0);
        for (double x : jacobian) ASSERT_TRUE(std::isfinite(x));
      }
    }
  }
}

struct TempFile {
  std::string path;
  TempFile(const std::string& name, const std::string& text)
      : path(std::filesystem::temp_directory_path() / ("brdffit-low-" + std::to_string(::getpid()) + "-" + name)) {
    write_file_atomic(path, text);
  }
  ~TempFile() { std::filesystem::remove(path); }
};

std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an Error";
  return "";
}

TEST(LowModels, BadPublishedLinesGiveClearErrors) {
  const TempFile file(
      "bad.fit",
      "good = Aggregate(Lambertian(albedo = [0.1, 0.1, 0.1]), LowSmooth(A = [1, 2, 3], B = 10, C = 1, "
      "eta = 1.5))\n"
      "noc = Aggregate(Lambertian(albedo = [0.1, 0.1, 0.1]), LowSmooth(A = [1, 2, 3], B = 10, eta = 1.5))\n"
      "flat = Bagher(albedo = [1, 1, 1], alpha = [0.1, 0.1, 0.1], p = [0.5, 0.5, 0.5], eta = [0.1, 0.2], "
      "K = [1, 1, 1], Lambda = [1, 1, 1], c = [1, 1, 1], k = [1, 1, 1], theta0 = [0, 0, 0])\n"
      "wardduer = NganWardDuer(albedo = [0.1, 0.1, 0.1], roughness = 0.1)\n");
  // The good line maps onto low-smooth only, with every value where BBM has it.
  const std::vector<PublishedFit> good = find_published_fits(file.path, "good");
  ASSERT_EQ(good.size(), 1u);
  EXPECT_EQ(good[0].model, "low-smooth");
  EXPECT_EQ(good[0].term, "LowSmooth");
  EXPECT_EQ(good[0].values, (std::vector<double>{0.1, 0.1, 0.1, 1, 2, 3, 10, 1, 1.5}));
  // A missing parameter, Bagher's eta not two rows of three, an unsupported lobe, no such material.
  for (const auto& [material, fragment] : std::vector<std::pair<std::string, std::string>>{
           {"noc", "'noc' (Lambertian + LowSmooth) maps onto none"},
           {"flat", "'flat' (Bagher) maps onto none"},
           {"wardduer", "'wardduer' (NganWardDuer) maps onto none"},
           {"nope", "no material 'nope' (4 materials: flat, good, noc, wardduer)"}}) {
    const std::string message = error_of([&] { find_published_fits(file.path, material); });
    EXPECT_NE(message.find(file.path), std::string::npos) << message;
    EXPECT_NE(message.find(fragment), std::string::npos) << message;
  }
}

TEST(LowModels, ScorePublishedOnTheCommandLine) {
  // A tiny table: two samples of f·cosθi in directions (CSV), and a fit file naming it.
  const TempFile table("tiny.csv",
                       "lx,ly,lz,vx,vy,vz,r,g,b\n0,0,1,0,0,1,0.5,0.5,0.5\n0.6,0,0.8,-0.6,0,0.8,0.3,0.3,0.3\n");
  const std::string material = std::filesystem::path(table.path).stem().string();
  const TempFile fits("tiny.fit", material +
                                      " = Aggregate(Lambertian(albedo = [0.5, 0.5, 0.5]), LowCookTorrance(albedo "
                                      "= [0.1, 0.1, 0.1], roughness = 0.2, eta = 1.5))\n");
  const test::CommandResult ok = test::run_cli("score " + table.path + " --published " + fits.path + " --json");
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  const auto json = nlohmann::json::parse(ok.output);
  ASSERT_EQ(json.size(), 1u);
  EXPECT_EQ(json[0]["model"], "low-cook-torrance");
  EXPECT_EQ(json[0]["material"], material);
  // Its cosine error, computed here: the CSV holds f, compared as f·cosθi, equal weights.
  // l = v = n: D = 1/m², F = 0.04; mirror pair: h = n, l·h = 0.8, G = 1.
  const double f_normal = 0.5 / kPi + 0.1 * 0.04 / (kPi * 0.04);
  const double f_mirror = 0.5 / kPi + 0.1 * snell_fresnel(1.5, 0.8) / (kPi * 0.04 * 0.64);
  const double cosine = std::sqrt((std::pow(f_normal - 0.5, 2) + std::pow((f_mirror - 0.3) * 0.8, 2)) / 2);
  EXPECT_NEAR(json[0]["metrics"]["cosine"].get<double>(), cosine, 1e-9);

  for (const auto& [args, fragment] : std::vector<std::pair<std::string, std::string>>{
           {"score " + table.path + " --published " + fits.path + " --material other", "no material 'other'"},
           {"score " + table.path + " --published " + fits.path + " -m ward", "give -m or --published, not both"},
           {"score " + table.path, "or --published FILE.fit"},
           {"score " + table.path + " --published " + fits.path + " --material a --name b",
            "give the line's name once"}}) {
    SCOPED_TRACE(args);
    const test::CommandResult r = test::run_cli(args);
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.output.find(fragment), std::string::npos) << r.output;
  }
}

}  // namespace
}  // namespace brdffit
