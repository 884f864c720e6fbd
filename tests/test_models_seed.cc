// Hand-derived values for the ten seed models (Lambert and GGX are in test_models.cc), chosen
// to pin down the decisions each header documents: raw n·l in half-lambert, the n·l gate on
// phong/blinn-phong, the number of bands in banded, the glossiness² exponent and the smoothstep
// interiors of toon, the non-linear albedo of oren-nayar, and the guards that keep directions
// below or at the horizon finite. Directions use 3-4-5 triangles so the cosines are exact.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "brdffit/model.h"
#include "brdffit/registry.h"
#include "test_util.h"

namespace brdffit {
namespace {

using test::dir;

using test::shade1;

using test::kNormal;
const Vec3 kL68(0.6, 0, 0.8);    // n·l = 0.8
const Vec3 kL68m(-0.6, 0, 0.8);  // mirror of kL68 about n
const Vec3 kL86(0.8, 0, 0.6);    // n·l = 0.6
const Vec3 kL86m(-0.8, 0, 0.6);  // mirror of kL86

TEST(SeedHalfLambert, RawNdotL) {
  // n·l = 0.6, w = 0.75: 0.6·0.75 + 0.25 = 0.7 → 0.49.
  EXPECT_NEAR(shade1("half-lambert", {"albedo=1", "wrap=0.75"}, kL86, kNormal), 0.49, 1e-12);
  // Per channel, l = n: (1·w + 1 - w)² = 1 → the albedo itself.
  const Rgb<double> c = test::shade("half-lambert", {"albedo=0.2,0.4,0.6", "wrap=0.9"}, kNormal, kNormal);
  EXPECT_NEAR(c[0], 0.2, 1e-12);
  EXPECT_NEAR(c[1], 0.4, 1e-12);
  EXPECT_NEAR(c[2], 0.6, 1e-12);
  // Raw n·l = -1 (light straight behind), w = 0.5: (-0.5 + 0.5)² = 0.
  EXPECT_NEAR(shade1("half-lambert", {"albedo=1", "wrap=0.5"}, Vec3(0, 0, -1), kNormal), 0.0, 1e-12);
  // Same with w = 0.75: (-0.75 + 0.25)² = 0.25 — the back brightens again for w > 0.5
  // (the documented consequence of the raw n·l); the seed's clamped n·l would give 0.25² = 0.0625.
  EXPECT_NEAR(shade1("half-lambert", {"albedo=1", "wrap=0.75"}, Vec3(0, 0, -1), kNormal), 0.25, 1e-12);
}

TEST(SeedWrap, HandValues) {
  // n·l = 0.6, wrap 0.25, contrast 1: (0.6 + 0.25)/1.25 = 0.68.
  EXPECT_NEAR(shade1("wrap", {"albedo=1", "wrap=0.25", "contrast=1"}, kL86, kNormal), 0.68, 1e-12);
  // n·l = -0.2 (behind), wrap 0.5, contrast 1: 0.3/1.5 = 0.2; albedo 0.5 → 0.1.
  EXPECT_NEAR(shade1("wrap", {"albedo=0.5", "wrap=0.5", "contrast=1"}, Vec3(std::sqrt(0.96), 0, -0.2), kNormal), 0.1,
              1e-12);
  // n·l = 0.6, wrap 0, contrast 0.5: √0.6.
  EXPECT_NEAR(shade1("wrap", {"albedo=1", "wrap=0", "contrast=0.5"}, kL86, kNormal), std::sqrt(0.6), 1e-12);
  // n·l = 1: saturate(1) = 1 whatever the contrast.
  EXPECT_NEAR(shade1("wrap", {"albedo=0.3", "wrap=0.7", "contrast=7"}, kNormal, kNormal), 0.3, 1e-12);
}

TEST(SeedPhong, HandValuesAndGate) {
  // Mirror pair, n·l = 0.6: r·v = 1 → 0.5·0.6 + 0.25·1 = 0.55.
  EXPECT_NEAR(shade1("phong", {"albedo=0.5", "specular=0.25", "shininess=100"}, kL86, kL86m), 0.55, 1e-12);
  // l = n, v with n·v = 0.8: r = n, r·v = 0.8, shininess 2 → 0.64.
  EXPECT_NEAR(shade1("phong", {"albedo=0", "specular=1", "shininess=2"}, kNormal, kL68), 0.64, 1e-12);
  // l = v = (0.8,0,0.6): r = (-0.8,0,0.6), r·v = -0.64 + 0.36 < 0 → diffuse only, 0.6.
  EXPECT_NEAR(shade1("phong", {"albedo=1", "specular=1", "shininess=2"}, kL86, kL86), 0.6, 1e-12);
  // Light just below the horizon, v near its mirror direction: r·v > 0.9 but n·l < 0, so the
  // gate (seed 001) gives 0 where seed 000's ungated specular would give a highlight.
  const Vec3 l_below = dir(0.8, 0, -0.05), v_near_mirror = dir(-0.8, 0, 0.05);
  EXPECT_GT(reflect_about_normal(l_below).dot(v_near_mirror), 0.9);
  EXPECT_NEAR(shade1("phong", {"albedo=1", "specular=1", "shininess=2"}, l_below, v_near_mirror), 0.0, 1e-15);
}

TEST(SeedBlinnPhong, HandValues) {
  // Mirror pair, n·l = 0.8: h = n → 0.4·0.8 + 0.5·1 = 0.82.
  EXPECT_NEAR(shade1("blinn-phong", {"albedo=0.4", "specular=0.5", "gloss=300"}, kL68, kL68m), 0.82, 1e-12);
  // l = n, v = (0.6,0,0.8): h ∝ (0.6,0,1.8), n·h = 1.8/√3.6 = √0.9; gloss 2 → 0.9, gloss 4 → 0.81.
  EXPECT_NEAR(shade1("blinn-phong", {"albedo=0", "specular=1", "gloss=2"}, kNormal, kL68), 0.9, 1e-12);
  EXPECT_NEAR(shade1("blinn-phong", {"albedo=0", "specular=1", "gloss=4"}, kNormal, kL68), 0.81, 1e-12);
  // l = v = (0.6,0,0.8): h = l, n·h = 0.8, gloss 1 → 0.5·0.8 + 0.5·0.8 = 0.8.
  EXPECT_NEAR(shade1("blinn-phong", {"albedo=0.5", "specular=0.5", "gloss=1"}, kL68, kL68), 0.8, 1e-12);
  // Gate: light below the horizon, h near n → still 0.
  EXPECT_NEAR(shade1("blinn-phong", {"albedo=1", "specular=1", "gloss=1"}, dir(0.8, 0, -0.05), dir(-0.8, 0, 0.05)), 0.0,
              1e-15);
}

TEST(SeedBanded, HandValuesAndBandCount) {
  // steps 3, n·l = 0.5: ⌈1.5⌉/3 = 2/3.
  EXPECT_NEAR(shade1("banded", {"albedo=1", "steps=3"}, Vec3(std::sqrt(0.75), 0, 0.5), kNormal), 2.0 / 3, 1e-12);
  // steps 8, n·l = 0.6: ⌈4.8⌉/8 = 0.625; albedo 0.8 → 0.5.
  EXPECT_NEAR(shade1("banded", {"albedo=0.8", "steps=8"}, kL86, kNormal), 0.5, 1e-12);
  // Band edge: steps 2, n·l = 0.5 exactly belongs to the lower band: ⌈1⌉/2 = 0.5.
  EXPECT_NEAR(shade1("banded", {"albedo=1", "steps=2"}, Vec3(std::sqrt(0.75), 0, 0.5), kNormal), 0.5, 1e-12);
  // Unlit: 0.
  EXPECT_NEAR(shade1("banded", {"albedo=1", "steps=4"}, Vec3(0.8, 0, -0.6), kNormal), 0.0, 1e-15);
  // `steps` is the number of lit bands: n·l over (0, 1] gives exactly `steps` distinct levels.
  for (int steps : {1, 2, 4, 7, 32}) {
    std::set<double> levels;
    for (int i = 1; i <= 10000; ++i) {
      const double z = i / 10000.0;
      levels.insert(
          shade1("banded", {"albedo=1", "steps=" + std::to_string(steps)}, Vec3(std::sqrt(1 - z * z), 0, z), kNormal));
    }
    EXPECT_EQ(levels.size(), static_cast<size_t>(steps)) << steps;
  }
}

TEST(SeedMinnaert, HandValues) {
  // n·l = 0.6, n·v = 0.8, k = 0.5: 0.6·√0.48.
  EXPECT_NEAR(shade1("minnaert", {"albedo=1", "roughness=0.5"}, kL86, kL68), 0.6 * std::sqrt(0.48), 1e-12);
  // Same directions, k = 1: 0.6·0.48 = 0.288; albedo 0.5 → 0.144.
  EXPECT_NEAR(shade1("minnaert", {"albedo=0.5", "roughness=1"}, kL86, kL68), 0.144, 1e-12);
  // View below the horizon: n·v clamps to 0, 0^k = 0 for k > 0.
  EXPECT_NEAR(shade1("minnaert", {"albedo=1", "roughness=0.5"}, kL86, Vec3(0.6, 0, -0.8)), 0.0, 1e-15);
  // Light below the horizon: n·l = 0 → 0.
  EXPECT_NEAR(shade1("minnaert", {"albedo=1", "roughness=0.5"}, Vec3(0.6, 0, -0.8), kNormal), 0.0, 1e-15);
  // k = 0 is Lambert's n·l: 0.48⁰ = 1 → 0.6.
  EXPECT_NEAR(shade1("minnaert", {"albedo=1", "roughness=0"}, kL86, kL68), 0.6, 1e-12);
}

TEST(SeedOrenNayar, HandValues) {
  // σ = 0.5: σ² = 0.25; A = 1 - 0.5·0.25/0.58, B = 0.17·0.25/0.38, C = 0.45·0.25/0.34.
  const double a = 1 - 0.5 * 0.25 / 0.58, b = 0.17 * 0.25 / 0.38, c = 0.45 * 0.25 / 0.34;
  // Mirror pair, n·l = n·v = 0.8: l·v = -0.36 + 0.64 = 0.28, s = 0.28 - 0.64 = -0.36 (not divided).
  EXPECT_NEAR(shade1("oren-nayar", {"albedo=0.5", "roughness=0.5"}, kL68, kL68m), 0.5 * 0.8 * (a + 0.5 * b - 0.36 * c),
              1e-12);
  // l with n·l = 0.6, v with n·v = 0.8, same plane: l·v = 0.48 + 0.48 = 0.96, s = 0.96 - 0.48 = 0.48,
  // divided by max(0.6, 0.8) → 0.6.
  EXPECT_NEAR(shade1("oren-nayar", {"albedo=1", "roughness=0.5"}, kL86, kL68), 0.6 * (a + b + 0.6 * c), 1e-12);
  // v = n: l·v = n·l = 0.8 → s = 0: 0.8·albedo·(A + albedo·B).
  EXPECT_NEAR(shade1("oren-nayar", {"albedo=0.3", "roughness=0.5"}, kL68, kNormal), 0.3 * 0.8 * (a + 0.3 * b), 1e-12);
  // Albedo is not linear: doubling it more than doubles the shade (the albedo·B term).
  const double half = shade1("oren-nayar", {"albedo=0.4", "roughness=0.5"}, kL68, kNormal);
  const double full = shade1("oren-nayar", {"albedo=0.8", "roughness=0.5"}, kL68, kNormal);
  EXPECT_NEAR(full - 2 * half, 0.8 * (0.64 - 2 * 0.16) * b, 1e-12);
  // σ = 0: A = 1, B = C = 0 → albedo·n·l = 0.5·0.6, whatever the directions.
  EXPECT_NEAR(shade1("oren-nayar", {"albedo=0.5", "roughness=0"}, kL86, kL68), 0.3, 1e-12);
  // Both directions below the horizon: 0, not the seed's 0·∞.
  const double below = shade1("oren-nayar", {"albedo=1", "roughness=1"}, Vec3(0.6, 0, -0.8), Vec3(0.6, 0, -0.8));
  EXPECT_EQ(below, 0.0);
}

TEST(SeedGaussian, HandValues) {
  // l = v = (0.6,0,0.8): h = l, θh = acos 0.8 = 0.6435; m = 0.5 → lobe 1.2·exp(-(θh/0.5)²);
  // f = 0.4/π + 2·lobe, shade = f·0.8.
  {
    const double th = std::acos(0.8), lobe = 1.2 * std::exp(-(th / 0.5) * (th / 0.5));
    EXPECT_NEAR(shade1("gaussian", {"albedo=0.4", "specular=2", "m=0.5"}, kL68, kL68), (0.4 / kPi + 2 * lobe) * 0.8,
                1e-12);
  }
  // Mirror pair at n·l = 0.6: θh = 0 → lobe 1.2, whatever m.
  EXPECT_NEAR(shade1("gaussian", {"albedo=0", "specular=5", "m=0.01"}, kL86, kL86m), 6.0 * 0.6, 1e-12);
  // l = n, v = (0.6,0,0.8): n·h = √0.9, θh = acos √0.9; m = 0.1 → 1.2·exp(-(θh/0.1)²).
  {
    const double th = std::acos(std::sqrt(0.9));
    EXPECT_NEAR(shade1("gaussian", {"albedo=0", "specular=1", "m=0.1"}, kNormal, kL68), 1.2 * std::exp(-th * th / 0.01),
                1e-12);
  }
  // Reciprocal BRDF: shade(l,v)/n·l = shade(v,l)/n·v.
  EXPECT_NEAR(shade1("gaussian", {"albedo=0.3", "specular=1", "m=0.4"}, kL86, kL68) / 0.6,
              shade1("gaussian", {"albedo=0.3", "specular=1", "m=0.4"}, kL68, kL86) / 0.8, 1e-12);
}

TEST(SeedBeckmann, HandValues) {
  // l = v = (0.6,0,0.8): h = l, cos² = 0.64, tan² = 0.36/0.64 = 0.5625; m = 0.75 (m² = 0.5625):
  // D = e⁻¹/(π·0.5625·0.64²); shade = specular·D·0.8.
  EXPECT_NEAR(shade1("beckmann", {"albedo=0", "specular=2", "m=0.75"}, kL68, kL68),
              2 * std::exp(-1.0) / (kPi * 0.5625 * 0.4096) * 0.8, 1e-12);
  // l = v = n, m = 0.25: D = 1/(π/16) = 16/π; specular 0.5, albedo 0.2 → 0.2/π + 8/π.
  EXPECT_NEAR(shade1("beckmann", {"albedo=0.2", "specular=0.5", "m=0.25"}, kNormal, kNormal), 8.2 / kPi, 1e-12);
  // Mirror pair at n·l = 0.6: h = n → D = 1/(π m²); m = 0.5 → 4/π; shade = 0.1·4/π·0.6.
  EXPECT_NEAR(shade1("beckmann", {"albedo=0", "specular=0.1", "m=0.5"}, kL86, kL86m), 0.24 / kPi, 1e-12);
  // View below the horizon with h horizontal (n·h = 0): the lobe is 0, the Lambert base stays:
  // albedo/π·n·l = 0.5/π·0.8 (the seed's formula is 0/0 there).
  EXPECT_NEAR(shade1("beckmann", {"albedo=0.5", "specular=1", "m=0.3"}, kL68, Vec3(0.6, 0, -0.8)), 0.4 / kPi, 1e-12);
  // Grazing: l = (1,0,1e-100), v = (1,0,0): n·h = 5e-101 > 0, cos⁴θh underflows to 0 and
  // exp(-tan²/m²) to 0; the lobe is 0 (not 0/0): shade = 0.5/π·1e-100.
  EXPECT_NEAR(shade1("beckmann", {"albedo=0.5", "specular=1", "m=0.3"}, Vec3(1, 0, 1e-100), Vec3(1, 0, 0)) * 1e100,
              0.5 / kPi, 1e-12);
}

TEST(SeedToon, HandValues) {
  // l = n, v = (0.6,0,0.8): light = 1; n·h = √0.9; glossiness 2 → exponent 4: 0.81 > 0.01 → spec = specular;
  // rimDot = 0.2 < rim_amount - 0.01 → rim 0. shade = albedo·(1 + specular) = 0.5·1.5.
  EXPECT_NEAR(shade1("toon", {"albedo=0.5", "specular=0.5", "glossiness=2"}, kNormal, kL68), 0.75, 1e-12);
  // Same directions, glossiness 10 → exponent 100 (glossiness², not 10): 0.9^50 = 0.005154,
  // inside the smoothstep(0.005, 0.01) ramp: t = (0.9^50 - 0.005)/0.005, spec = t²(3-2t).
  {
    const double x = std::pow(0.9, 50), t = (x - 0.005) / 0.005, ss = t * t * (3 - 2 * t);
    EXPECT_NEAR(shade1("toon", {"albedo=1", "specular=1", "glossiness=10"}, kNormal, kL68), 1 + ss, 1e-9);
  }
  // Rim: l = n (n·l^thr = 1), v.z = 0.3 → rimDot = 0.7; rim_amount 0.7 → middle of the ramp, 0.5.
  // n·h = 1.3/√2.6 ≈ 0.806, ^(32²) ≈ 0 → no highlight. shade = albedo·(1 + 0.5).
  EXPECT_NEAR(shade1("toon", {"albedo=0.4", "rim_amount=0.7"}, kNormal, Vec3(std::sqrt(0.91), 0, 0.3)), 0.4 * 1.5,
              1e-9);
  // rim_threshold: n·l = 0.25, thr = 0.5 → 0.25^0.5 = 0.5; v.z = 0.1 → rimDot 0.9; 0.45 = rim_amount
  // → rim 0.5. v on the same side as l: n·h ≈ 0.18, ^(10²) ≈ 0 → no highlight. shade = 1 + 0.5.
  EXPECT_NEAR(shade1("toon", {"albedo=1", "glossiness=10", "rim_amount=0.45", "rim_threshold=0.5"},
                     Vec3(std::sqrt(1 - 0.0625), 0, 0.25), Vec3(std::sqrt(0.99), 0, 0.1)),
              1.5, 1e-9);
  // light ramp: n·l = 0.005 → smoothstep(0, 0.01, 0.005) = 0.5; v = n: rimDot 0; n·h = cos(≈44.9°)·...
  // ^1024 ≈ 0. shade = albedo·0.5.
  EXPECT_NEAR(shade1("toon", {"albedo=0.6"}, Vec3(std::sqrt(1 - 0.005 * 0.005), 0, 0.005), kNormal), 0.3, 1e-9);
}

TEST(SeedModels, FiniteValuesAndDerivativesAtTheHorizon) {
  // Directions at, just above and just below the horizon, where products of cosines and the
  // smoothstep of n·l become subnormal (n·l below 1e-154) and 0/0 or log 0 lurk; parameters
  // all at their lower bounds, all at their defaults, all at their upper bounds.
  const std::vector<Vec3> dirs = {kNormal,
                                  Vec3(1, 0, 0),
                                  Vec3(1, 0, 1e-155),
                                  Vec3(-1, 0, 1e-155),
                                  Vec3(1, 0, 5e-157),
                                  Vec3(0, 1, 1e-100),
                                  Vec3(1, 0, 1e-300),
                                  Vec3(1, 0, 1e-310),  // subnormal n·l
                                  Vec3(0.6, 0, -0.8),
                                  Vec3(1, 0, -1e-100),
                                  kL68};
  for (const char* name : {"half-lambert", "wrap", "phong", "blinn-phong", "banded", "minnaert", "oren-nayar",
                           "gaussian", "beckmann", "toon"}) {
    SCOPED_TRACE(name);
    const Model& m = *find_model(name);
    for (int which = 0; which < 3; ++which) {
      std::vector<double> values;
      for (const ParamSpec& p : m.parameters())
        values.insert(values.end(), p.channels, which == 0 ? p.lower : which == 1 ? p.default_value : p.upper);
      for (const Vec3& l : dirs)
        for (const Vec3& v : dirs) {
          std::vector<double> jac(3 * m.num_values());
          const Rgb<double> s = m.shade_with_jacobian(values.data(), l, v, jac.data());
          bool finite = s.allFinite();
          for (double j : jac) finite = finite && std::isfinite(j);
          EXPECT_TRUE(finite) << "set " << which << " l " << l.transpose() << " v " << v.transpose();
        }
    }
  }
}

}  // namespace
}  // namespace brdffit
