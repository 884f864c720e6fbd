// Properties every model must have (gradients, non-negativity, reciprocity, energy, linearity
// claims), hand-derived values for the base models, and the models/eval commands.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <random>
#include <thread>
#include <tuple>

#include <nlohmann/json.hpp>

#include "aniso_tables.h"
#include "brdffit/error.h"
#include "brdffit/fit_residual.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"
#include "test_util.h"

namespace brdffit {
namespace {

using test::dir;

using test::shade;

void expect_channels_near(const Rgb<double>& actual, double r, double g, double b, double tol = 1e-9) {
  EXPECT_NEAR(actual[0], r, tol);
  EXPECT_NEAR(actual[1], g, tol);
  EXPECT_NEAR(actual[2], b, tol);
}

TEST(Registry, HasEveryModelTheIssueNames) {
  for (const char* name :
       {"lambert", "half-lambert", "wrap", "phong", "blinn-phong", "banded", "minnaert", "oren-nayar", "gaussian",
        "beckmann", "ggx", "toon", "cook-torrance", "ward", "ashikhmin-shirley", "lafortune"})
    EXPECT_NE(find_model(name), nullptr) << name;
}

TEST(Registry, ParameterTablesAreConsistent) {
  for (const auto& m : all_models()) {
    SCOPED_TRACE(m->name());
    EXPECT_FALSE(m->summary().empty());
    for (const ParamSpec& p : m->parameters()) {
      SCOPED_TRACE(p.name);
      EXPECT_LT(p.lower, p.upper);
      EXPECT_GE(p.default_value, p.lower);
      EXPECT_LE(p.default_value, p.upper);
      EXPECT_FALSE(p.meaning.empty());
      EXPECT_TRUE(p.channels == 1 || p.channels == 3);
      if (p.linear) EXPECT_EQ(p.channels, 3) << "linear parameters are per-channel colours";
      if (p.spacing == Spacing::Log) EXPECT_GT(p.lower, 0.0);
    }
  }
}

// A stylised shader's albedo multiplies n·l as it is; a physically based model's is a reflectance,
// divided by π. The meaning users read says which: at normal light and view, with every other
// colour zero, albedo 1 adds about 1/π to the shaded value of a physically based model; a stylised
// one adds at least 0.45 (1 for half-Lambert, wrap, Phong, ...; 1.5 for toon with its ambient
// term; Oren-Nayar's A = 0.5 at the default roughness).
TEST(Registry, AlbedoMeaningSaysWhetherItIsDividedByPi) {
  for (const auto& m : all_models()) {
    const ParamSpec* albedo = m->find_parameter("albedo");
    if (!albedo) continue;
    SCOPED_TRACE(m->name());
    std::vector<double> values = m->default_values();
    for (const ParamSpec& p : m->parameters())
      if (p.linear) std::fill_n(values.begin() + m->offset_of(p.name), 3, 0.0);
    const double dark = m->shade(values.data(), Vec3(0, 0, 1), Vec3(0, 0, 1))[0];
    std::fill_n(values.begin() + m->offset_of("albedo"), 3, 1.0);
    const double added = m->shade(values.data(), Vec3(0, 0, 1), Vec3(0, 0, 1))[0] - dark;
    const bool stylised = albedo->meaning.find("no 1/π") != std::string::npos;
    if (stylised) {
      EXPECT_GE(added, 0.45) << albedo->meaning;
      EXPECT_LE(added, 2.0) << albedo->meaning;
    } else {
      EXPECT_NEAR(added, 1.0 / kPi, 0.3 / kPi) << albedo->meaning;
    }
  }
}

// What two-lobe composites rely on (two_lobes.h), declared by Model::is_lobe_over_lambert: the
// albedo, a colour, comes first and enters f as albedo/π alone, the rest is a lobe that does not
// depend on it. Checked at random values and directions for the models that declare it; and the
// converse, so that a lobe over Lambert written out by hand rather than as models::OverLambert
// is caught: a model that has parameters besides such an albedo declares it.
TEST(Registry, LobesOverLambertAreDeclaredAsSuch) {
  std::mt19937_64 rng(23);
  for (const auto& m : all_models()) {
    SCOPED_TRACE(m->name());
    const ParamSpec& first = m->parameters().front();
    bool albedo_over_pi = m->has_brdf() && first.name == "albedo" && first.channels == 3 &&
                          first.role == Role::DiffuseColour && m->parameters().size() > 1;
    for (int trial = 0; trial < 200 && albedo_over_pi; ++trial) {
      std::vector<double> values = test::random_values(*m, rng);
      const Vec3 l = test::random_direction_up_to(rng, 89.9), v = test::random_direction_up_to(rng, 89.9);
      const Rgb<double> albedo(values[0], values[1], values[2]), with = *m->brdf(values.data(), l, v);
      std::fill_n(values.begin(), 3, 0.0);
      const Rgb<double> without = *m->brdf(values.data(), l, v);
      albedo_over_pi = ((with - without - albedo * kInvPi).array().abs() <= 1e-12 * with.array().max(1.0)).all();
    }
    EXPECT_EQ(m->is_lobe_over_lambert(), albedo_over_pi);
  }
}

// --- hand-derived values -------------------------------------------------------------------

TEST(Lambert, HandValues) {
  // f = albedo/π; shade = f·cosθi.
  expect_channels_near(shade("lambert", {"albedo=1"}, dir(0, 0, 1), dir(1, 0, 1)), 1 / kPi, 1 / kPi, 1 / kPi);
  expect_channels_near(shade("lambert", {"albedo=0.2,0.4,0.6"}, dir(1, 0, 1), dir(0, 0, 1)), 0.2 / kPi * std::sqrt(0.5),
                       0.4 / kPi * std::sqrt(0.5), 0.6 / kPi * std::sqrt(0.5));
  expect_channels_near(shade("lambert", {"albedo=1"}, dir(1, 0, -0.2), dir(0, 0, 1)), 0, 0, 0);
}

TEST(Ggx, HandValues) {
  // Normal incidence and view: h = n, D = α²/π/α⁴ = 1/(πα²), F = f0, G = 1.
  // roughness 0.5: α = 0.25, D = 16/π; f = albedo/π + D·f0/4.
  const double d = 16.0 / kPi;
  expect_channels_near(shade("ggx", {"albedo=0.5", "roughness=0.5", "f0=0.04"}, dir(0, 0, 1), dir(0, 0, 1)),
                       0.5 / kPi + d * 0.04 / 4, 0.5 / kPi + d * 0.04 / 4, 0.5 / kPi + d * 0.04 / 4);
  // roughness 1 (α = 1): D = 1/π everywhere, k = 0.5, G1(x) = 2x/(x+1).
  // l = (sin60,0,cos60), v = n: h at 30°, l·h = cos30.
  {
    const double nl = 0.5, nv = 1.0, lh = std::cos(kPi / 6);
    const double g = (2 * nl / (nl + 1)) * (2 * nv / (nv + 1));
    const double f = 0.3 + std::pow(1 - lh, 5) * 0.7;
    const double spec = (1 / kPi) * f * g / (4 * nl * nv);
    const Rgb<double> s = shade("ggx", {"albedo=0", "roughness=1", "f0=0.3"}, dir(std::sqrt(3), 0, 1), dir(0, 0, 1));
    expect_channels_near(s, spec * nl, spec * nl, spec * nl);
  }
  // Coloured f0 only changes the specular term per channel; light below the horizon gives 0.
  expect_channels_near(shade("ggx", {"albedo=0", "roughness=0.5", "f0=1,0.5,0"}, dir(0, 0, 1), dir(0, 0, 1)), d / 4,
                       d / 8, 0.0);
  expect_channels_near(shade("ggx", {}, dir(0, 1, -0.1), dir(0, 0, 1)), 0, 0, 0);
}

// What sgd's evaluations give at one point, for comparisons to the bit: channel c's shade at [c],
// its derivative by value i at [3 + c·n + i] (n values), the linear parts (albedo's, specular's)
// at [3 + 3n + 3j + c], and the shade on doubles (all channels) at [9 + 3n + c].
std::vector<double> sgd_outputs(const std::vector<double>& values, const Vec3& l, const Vec3& v) {
  const Model& sgd = *find_model("sgd");
  const int n = sgd.num_values();
  std::vector<double> out(12 + 3 * n);
  const Rgb<double> shaded = sgd.shade_with_jacobian(values.data(), l, v, out.data() + 3);
  Rgb<double> basis[2];
  EXPECT_EQ(sgd.shade_linear_parts(values.data(), l, v, basis), Rgb<double>::Zero());  // all linear
  const Rgb<double> on_doubles = sgd.shade(values.data(), l, v);
  for (int c = 0; c < 3; ++c) {
    out[c] = shaded[c];
    out[3 + 3 * n + c] = basis[0][c];
    out[6 + 3 * n + c] = basis[1][c];
    out[9 + 3 * n + c] = on_doubles[c];
  }
  return out;
}

// sgd computes a channel's lobe once when its shape values are those of the channel before (the
// grid and the coordinate search set them alike in the three channels). From such a point, each
// shape value of channel 0 is changed in turn: channels 1 and 2 keep their values, derivatives and
// linear parts to the bit, so a reuse that overlooked any one shape value would show.
TEST(Sgd, AChannelShapedLikeTheOneBeforeIsShadedAsOnItsOwn) {
  const Model& sgd = *find_model("sgd");
  const int n = sgd.num_values();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.1, 0.9);
  std::vector<const ParamSpec*> shape;
  for (const ParamSpec& p : sgd.parameters())
    if (!p.linear) shape.push_back(&p);
  for (int trial = 0; trial < 10; ++trial) {
    // Bagher's median material (the defaults) with a wider lobe and a shadowing that acts from
    // θ0 = 0.4 rad on, seen from beyond it: there every shape value matters.
    std::vector<double> alike = sgd.default_values();
    const std::pair<const char*, double> shaped[] = {
        {"alpha", 0.3}, {"lambda", 1.5}, {"c", 0.3}, {"k", 3.0}, {"theta0", 0.4}};
    for (int c = 0; c < 3; ++c) {
      alike[sgd.offset_of("albedo") + c] = unit(rng);
      alike[sgd.offset_of("specular") + c] = unit(rng);
      for (const auto& [name, value] : shaped) alike[sgd.offset_of(name) + c] = value;
    }
    auto direction = [&] {
      const double theta = 0.5 + 0.7 * unit(rng), phi = 2.0 * kPi * unit(rng);
      return Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    };
    const Vec3 l = direction(), v = direction();
    const std::vector<double> alike_out = sgd_outputs(alike, l, v);
    for (const ParamSpec* p : shape) {
      SCOPED_TRACE(p->name);
      std::vector<double> apart = alike;
      double& changed = apart[sgd.offset_of(p->name)];
      changed = p->spacing == Spacing::Log ? changed * 1.5 : changed + 0.05 * (p->upper - p->lower);
      const std::vector<double> apart_out = sgd_outputs(apart, l, v);
      EXPECT_NE(apart_out[0], alike_out[0]);  // the change matters
      for (int c = 1; c < 3; ++c) {
        EXPECT_EQ(apart_out[c], alike_out[c]) << "channel " << c;
        for (int i = 0; i < n; ++i) EXPECT_EQ(apart_out[3 + c * n + i], alike_out[3 + c * n + i]) << "channel " << c;
        for (int k = 3 + 3 * n + c; k < 12 + 3 * n; k += 3) EXPECT_EQ(apart_out[k], alike_out[k]) << "channel " << c;
      }
    }
  }
}

// sgd computes its D once per run of samples with one n·h (math.h's once_per_parameters, keyed on
// n·h and on the three channels' α, p and K). At samples sharing a half vector, shaded in turn
// with each of those nine values changed, every shade, Jacobian and linear part must be what a
// thread that has computed nothing before gets (its memo is empty), to the bit: a key that
// overlooked one of them would hand back a stale D.
TEST(Sgd, ADistributionReusedAlongARunOfOneHalfAngleIsTheOneComputedAfresh) {
  const Model& sgd = *find_model("sgd");
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto afresh = [&](const std::vector<double>& values, const Vec3& l, const Vec3& v) {
    std::vector<double> out;
    std::thread([&] { out = sgd_outputs(values, l, v); }).join();
    return out;
  };
  std::vector<double> base = sgd.default_values();
  for (int c = 0; c < 3; ++c)  // channels apart, the shadowing acting from θ0 = 0.3 rad on
    for (const auto& [name, value] : {std::pair{"alpha", 0.05 + 0.1 * c},
                                      {"p", 0.3 + 0.2 * c},
                                      {"K", 5.0 + 2.0 * c},
                                      {"lambda", 1.5},
                                      {"c", 0.3},
                                      {"k", 3.0},
                                      {"theta0", 0.3}})
      base[sgd.offset_of(name) + c] = value;
  std::vector<std::vector<double>> variants = {base};  // then each of D's nine values 10 % larger, then base
  for (const char* name : {"alpha", "p", "K"})
    for (int c = 0; c < 3; ++c) {
      variants.push_back(base);
      variants.back()[sgd.offset_of(name) + c] *= 1.1;
    }
  variants.push_back(base);  // so that the next half vector's first sample has the same values
  int compared = 0;
  for (int run = 0; run < 6; ++run) {
    // A half vector 10-50° from the normal, and samples mirrored about it at 5-60°.
    const double theta_h = 0.17 + 0.7 * unit(rng), phi_h = 2.0 * kPi * unit(rng);
    const Vec3 h(std::sin(theta_h) * std::cos(phi_h), std::sin(theta_h) * std::sin(phi_h), std::cos(theta_h));
    for (int sample = 0; sample < 4; ++sample) {
      const double phi = 2.0 * kPi * unit(rng), theta_d = 0.09 + 0.95 * unit(rng);
      const Vec3 tangent = h.cross(Vec3(std::cos(phi), std::sin(phi), 0.3)).normalized();
      const Vec3 l = std::cos(theta_d) * h + std::sin(theta_d) * tangent, v = 2.0 * l.dot(h) * h - l;
      if (l.z() <= 0.05 || v.z() <= 0.05) continue;
      for (size_t k = 0; k < variants.size(); ++k) {
        SCOPED_TRACE(testing::Message() << "run " << run << ", sample " << sample << ", variant " << k);
        const std::vector<double> in_run = sgd_outputs(variants[k], l, v), fresh = afresh(variants[k], l, v);
        ASSERT_GT(fresh[0], 0.0);
        for (size_t i = 0; i < fresh.size(); ++i) EXPECT_EQ(in_run[i], fresh[i]) << "entry " << i;
        ++compared;
      }
    }
  }
  EXPECT_GE(compared, 100);  // of 264 evaluations, those of samples above the surface
}

// --- properties of every model ------------------------------------------------------------

TEST(AllModels, AutodiffGradientsMatchCentralDifferences) {
  std::mt19937_64 rng(7);
  for (const auto& m : all_models()) {
    SCOPED_TRACE(m->name());
    const int n = m->num_values();
    std::vector<bool> integer;  // per flattened value: integers have no derivative to check
    for (const ParamSpec& p : m->parameters()) integer.insert(integer.end(), p.channels, p.integer);
    for (int trial = 0; trial < 25; ++trial) {
      std::vector<double> values = test::random_values(*m, rng);
      const Vec3 l = test::random_upper_direction(rng), v = test::random_upper_direction(rng);
      std::vector<double> jac(3 * n);
      const Rgb<double> shaded = m->shade_with_jacobian(values.data(), l, v, jac.data());
      for (int i = 0; i < n; ++i) {
        if (integer[i]) continue;
        const double h = 1e-6 * std::max(1.0, std::abs(values[i]));
        std::vector<double> up = values, down = values;
        up[i] += h;
        down[i] -= h;
        const Rgb<double> fd = (m->shade(up.data(), l, v) - m->shade(down.data(), l, v)) / (2 * h);
        for (int c = 0; c < 3; ++c) {
          const double ad = jac[c * n + i];
          // The difference quotient's own round-off, ~ε·|shade|/h, matters where the shaded
          // value is large (unnormalised lobes such as sgd's reach 1e5 inside their bounds).
          const double round_off = 10 * std::numeric_limits<double>::epsilon() * std::abs(shaded[c]) / h;
          EXPECT_NEAR(ad, fd[c], 1e-6 * std::max({1.0, std::abs(ad), std::abs(fd[c])}) + round_off)
              << "value " << i << " channel " << c;
        }
      }
    }
  }
}

// Every model's own batch cost (BatchCost<M>, with one derivative per parameter where its
// channels are separate) gives the cost, gradient and Gauss-Newton matrix (RᵀR = JᵀJ, Rᵀy = Jᵀr)
// that its shade_with_jacobian gives through JacobianBatchCost (whose derivatives the test above
// checks against central differences): for each metric, with and without a loss, with a colour
// component and a scalar fixed and the blue channel not fitted.
TEST(AllModels, TheirBatchCostMatchesTheirJacobian) {
  std::mt19937_64 rng(3);
  const ceres::CauchyLoss cauchy(0.05);
  for (const auto& m : all_models()) {
    SCOPED_TRACE(m->name());
    const std::vector<double> truth = test::random_values(*m, rng);
    const SampleSet data = test::anisotropic_samples(*m, truth, 200, 0.1, 4);
    const std::vector<double> at = test::random_values(*m, rng);
    std::vector<int> free;  // all but integers, the second value and the last scalar
    int last_scalar = -1, offset = 0;
    for (const ParamSpec& p : m->parameters()) {
      if (p.channels == 1 && !p.integer) last_scalar = offset;
      offset += p.channels;
    }
    offset = 0;
    for (const ParamSpec& p : m->parameters())
      for (int c = 0; c < p.channels; ++c, ++offset)
        if (!p.integer && offset != 1 && offset != last_scalar) free.push_back(offset);
    for (Metric metric : {Metric::Cosine, Metric::Log})
      for (const ceres::LossFunction* loss :
           {static_cast<const ceres::LossFunction*>(nullptr), static_cast<const ceres::LossFunction*>(&cauchy)}) {
        const ResidualBatch batch{data.samples.data(), data.size(), metric, {true, true, false}, loss, &free, &at};
        std::vector<double> x;
        for (int i : free) x.push_back(at[i] * 1.01);
        const double* parameters[] = {x.data()};
        const int rows = int(free.size()) + 1, cols = int(free.size());
        auto normal_equations = [&](const ceres::CostFunction& cost) {
          std::vector<double> r(rows), j(rows * cols);
          double* jacobians[] = {j.data()};
          EXPECT_TRUE(cost.Evaluate(parameters, r.data(), jacobians));
          const Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> jm(j.data(), rows,
                                                                                                      cols);
          const Eigen::Map<Eigen::VectorXd> rv(r.data(), rows);
          return std::tuple{rv.squaredNorm(), Eigen::VectorXd(jm.transpose() * rv),
                            Eigen::MatrixXd(jm.transpose() * jm)};
        };
        const std::unique_ptr<ceres::CostFunction> own(new_batch_cost(*m, batch));
        const JacobianBatchCost from_jacobian(*m, batch);
        const auto [rr1, g1, h1] = normal_equations(*own);
        const auto [rr2, g2, h2] = normal_equations(from_jacobian);
        EXPECT_NEAR(rr2, rr1, 1e-10 * rr1);
        EXPECT_LT((g2 - g1).norm(), 1e-8 * (1 + g1.norm()));
        EXPECT_LT((h2 - h1).norm(), 1e-8 * (1 + h1.norm()));
      }
  }
}

TEST(AllModels, NonNegativeAndFinite) {
  // Over every parameter's whole range, bounds included, and directions up to 89.99° (grazing).
  std::mt19937_64 rng(11);
  for (const auto& m : all_models()) {
    SCOPED_TRACE(m->name());
    for (int trial = 0; trial < 4000; ++trial) {
      const std::vector<double> values = test::random_values_with_bounds(*m, rng);
      const Vec3 l = test::random_direction_up_to(rng, 89.99), v = test::random_direction_up_to(rng, 89.99);
      const Rgb<double> s = m->shade(values.data(), l, v);
      for (int c = 0; c < 3; ++c)
        ASSERT_TRUE(std::isfinite(s[c]) && s[c] >= 0.0) << s[c] << " at l " << l.transpose() << " v " << v.transpose()
                                                        << " values " << ::testing::PrintToString(values);
    }
  }
}

TEST(AllModels, AParameterThatOnlyScalesALinearOneTradesWithItExactly) {
  // ParamSpec::only_scales: the shaded value depends on the product alone, so the coordinate
  // search skips the parameter (every value costs the same once the linear one is solved).
  // Multiplying it by s and its linear partner by 1/s must change nothing, at random values.
  std::mt19937_64 rng(23);
  int declared = 0;
  for (const auto& m : all_models())
    for (const ParamSpec& p : m->parameters()) {
      if (!p.only_scales) continue;
      SCOPED_TRACE(m->name() + ": " + p.name);
      ++declared;
      const ParamSpec* partner = m->find_parameter(p.only_scales);
      ASSERT_NE(partner, nullptr);
      EXPECT_TRUE(partner->linear);
      ASSERT_EQ(partner->channels, p.channels);
      for (int trial = 0; trial < 100; ++trial) {
        const std::vector<double> x = test::random_values(*m, rng);
        const Vec3 l = test::random_upper_direction(rng), v = test::random_upper_direction(rng);
        const Rgb<double> expected = m->shade(x.data(), l, v);
        for (double s : {0.37, 5.0}) {
          std::vector<double> y = x;
          for (int c = 0; c < p.channels; ++c) {
            y[m->offset_of(p.name) + c] *= s;
            y[m->offset_of(partner->name) + c] /= s;
          }
          const Rgb<double> actual = m->shade(y.data(), l, v);
          for (int c = 0; c < 3; ++c) ASSERT_NEAR(actual[c], expected[c], 1e-12 * std::max(1.0, std::abs(expected[c])));
        }
      }
    }
  EXPECT_GE(declared, 1);  // sgd's K
}

TEST(AllModels, LinearParametersEnterAffinely) {
  // What the fitter's variable projection relies on: shade(a·x + (1-a)·y) = a·shade(x) + (1-a)·shade(y)
  // when x and y differ only in linear parameters.
  std::mt19937_64 rng(17);
  for (const auto& m : all_models()) {
    SCOPED_TRACE(m->name());
    for (int trial = 0; trial < 200; ++trial) {
      std::vector<double> x = test::random_values(*m, rng), y = x, mid = x;
      const std::vector<double> other = test::random_values(*m, rng);
      int offset = 0;
      for (const ParamSpec& p : m->parameters()) {
        if (p.linear)
          for (int c = 0; c < p.channels; ++c) {
            y[offset + c] = other[offset + c];
            mid[offset + c] = 0.3 * x[offset + c] + 0.7 * y[offset + c];
          }
        offset += p.channels;
      }
      const Vec3 l = test::random_upper_direction(rng), v = test::random_upper_direction(rng);
      const Rgb<double> expected = 0.3 * m->shade(x.data(), l, v) + 0.7 * m->shade(y.data(), l, v);
      const Rgb<double> actual = m->shade(mid.data(), l, v);
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(actual[c], expected[c], 1e-9 * std::max(1.0, std::abs(expected[c])));
    }
  }
}

// Variable projection's split of the shaded value (Model::shade_linear_parts, one evaluation with
// Jets for registered models) against the definition by evaluations: the base is the value with
// the linear parameters at 0, basis j the change from there when the j-th is 1, and base + Σ x_j·basis_j
// the value itself. Where the linear parameters are 0 a model that skipped a lobe whose scale is 0
// would have no derivative there: the split is taken at 0 by construction, so this checks it too.
TEST(AllModels, TheirLinearPartsAreTheirValuesSplitAlongTheLinearParameters) {
  std::mt19937_64 rng(19);
  std::vector<const Model*> models;
  for (const auto& m : all_models()) models.push_back(m.get());
  for (const char* composite : {"ggx+ggx", "cook-torrance+ward"}) models.push_back(find_model(composite));
  for (const Model* m : models) {
    ASSERT_NE(m, nullptr);
    SCOPED_TRACE(m->name());
    std::vector<std::pair<int, int>> linear;  // offset and channels
    int offset = 0;
    for (const ParamSpec& p : m->parameters()) {
      if (p.linear) linear.emplace_back(offset, p.channels);
      offset += p.channels;
    }
    for (int trial = 0; trial < 50; ++trial) {
      const std::vector<double> values = test::random_values(*m, rng);
      const Vec3 l = test::random_upper_direction(rng), v = test::random_upper_direction(rng);
      std::vector<Rgb<double>> basis(linear.size());
      const Rgb<double> base = m->shade_linear_parts(values.data(), l, v, basis.data());
      std::vector<double> zero = values;
      for (const auto& [at, channels] : linear) std::fill_n(zero.begin() + at, channels, 0.0);
      const Rgb<double> expected_base = m->shade(zero.data(), l, v);
      Rgb<double> rebuilt = base;
      const double scale = std::max(1.0, m->shade(values.data(), l, v).cwiseAbs().maxCoeff());
      for (size_t j = 0; j < linear.size(); ++j) {
        std::vector<double> unit = zero;
        std::fill_n(unit.begin() + linear[j].first, linear[j].second, 1.0);
        const Rgb<double> expected = m->shade(unit.data(), l, v) - expected_base;
        for (int c = 0; c < 3; ++c) {
          ASSERT_NEAR(basis[j][c], expected[c], 1e-12 * std::max(1.0, std::abs(expected[c]))) << "basis " << j;
          rebuilt[c] += values[linear[j].first + c % linear[j].second] * basis[j][c];
        }
      }
      for (int c = 0; c < 3; ++c) {
        ASSERT_NEAR(base[c], expected_base[c], 1e-12 * std::max(1.0, std::abs(expected_base[c])));
        ASSERT_NEAR(rebuilt[c], m->shade(values.data(), l, v)[c], 1e-10 * scale);
      }
    }
  }
}

// --- parameters and the CLI ------------------------------------------------------------------

TEST(Parameters, RejectsUnknownMalformedAndOutOfBounds) {
  const Model& ggx = *find_model("ggx");
  EXPECT_THROW(parameter_values(ggx, {"shininess=3"}), Error);
  EXPECT_THROW(parameter_values(ggx, {"roughness=abc"}), Error);
  EXPECT_THROW(parameter_values(ggx, {"roughness=2"}), Error);
  EXPECT_THROW(parameter_values(ggx, {"albedo=0.1,0.2"}), Error);
  EXPECT_THROW(parameter_values(ggx, {"roughness=nan"}), Error);
  EXPECT_THROW(parameter_values(ggx, {"roughness"}), Error);
  const std::vector<double> v = parameter_values(ggx, {"albedo=0.1,0.2,0.3", "roughness=0.7"});
  EXPECT_EQ(v[0], 0.1);
  EXPECT_EQ(v[2], 0.3);
  EXPECT_EQ(v[ggx.offset_of("roughness")], 0.7);
  EXPECT_EQ(v[ggx.offset_of("f0")], 0.04);  // default
}

TEST(Cli, ModelsListsEveryModel) {
  const auto text = test::run_cli("models");
  ASSERT_EQ(text.exit_code, 0) << text.output;
  const auto json = test::run_cli("models --json");
  ASSERT_EQ(json.exit_code, 0) << json.output;
  const nlohmann::json list = nlohmann::json::parse(json.output);
  ASSERT_EQ(list.size(), all_models().size());
  for (const auto& m : all_models()) {
    EXPECT_NE(text.output.find(m->name()), std::string::npos) << m->name();
    bool found = false;
    for (const auto& entry : list) found |= entry["model"] == m->name();
    EXPECT_TRUE(found) << m->name();
  }
}

TEST(Cli, EvalMatchesTheLibrary) {
  std::mt19937_64 rng(19);
  for (const auto& m : all_models()) {
    SCOPED_TRACE(m->name());
    const std::vector<double> values = test::random_values(*m, rng);
    std::string args = "eval -m " + m->name() + " --light 0.3,-0.2,1 --view -0.4,0.1,0.8 --json";
    int offset = 0;
    for (const ParamSpec& p : m->parameters()) {
      args += " --param " + p.name + "=";
      for (int c = 0; c < p.channels; ++c) args += (c ? "," : "") + fmt::format("{:.17g}", values[offset + c]);
      offset += p.channels;
    }
    const auto result = test::run_cli(args);
    ASSERT_EQ(result.exit_code, 0) << result.output;
    const nlohmann::json out = nlohmann::json::parse(result.output);
    const Rgb<double> expected = m->shade(values.data(), dir(0.3, -0.2, 1), dir(-0.4, 0.1, 0.8));
    EXPECT_EQ(out["model"], m->name());
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(out["shade"][c].get<double>(), expected[c], 1e-12 * (1 + std::abs(expected[c])));
    EXPECT_EQ(out["brdf"].is_null(), !m->has_brdf());
  }
}

TEST(Cli, BadArgumentsExitNonZeroWithAMessage) {
  // Every one a usage error: exit 2 with "brdffit: error: <what>", values and a malformed command
  // line (CLI11's parse errors) alike. A crash or an internal error (exit 70) fails either way.
  struct Case {
    const char* args;
    int exit_code;
    const char* message;
  };
  for (const Case& c :
       {Case{"eval nosuchmodel --light 0,0,1 --view 0,0,1", 2, "brdffit: error: --models: unknown model 'nosuchmodel'"},
        Case{"eval -m ggx --param roughness=5 --light 0,0,1 --view 0,0,1", 2, "roughness must lie in [0.01, 1], got 5"},
        Case{"eval -m ggx --param gloss=5 --light 0,0,1 --view 0,0,1", 2, "model ggx has no parameter 'gloss'"},
        Case{"eval -m ggx --light 0,0 --view 0,0,1", 2, "--light: expected X,Y,Z, got '0,0'"},
        Case{"eval -m ggx --light 0,0,0 --view 0,0,1", 2, "--light and --view must be non-zero directions"},
        Case{"eval -m ggx --view 0,0,1", 2, "--light is required"},
        Case{"nosuchcommand", 2, "no command 'nosuchcommand'"}}) {
    SCOPED_TRACE(c.args);
    const auto result = test::run_cli(c.args);
    EXPECT_EQ(result.exit_code, c.exit_code) << result.output;
    EXPECT_NE(result.output.find(c.message), std::string::npos) << result.output;
  }
}

}  // namespace
}  // namespace brdffit
