// The anisotropic models: values derived by hand from the papers' formulas, reduction to the
// isotropic models, derivatives, reciprocity, and recovery of the tangent frame (α_x, α_y, φ₀)
// from noisy synthetic tables given as samples, CSV and an RGL-format file.
#include <gtest/gtest.h>

#include "aniso_tables.h"
#include "brdffit/csv_samples.h"
#include "brdffit/fit.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"
#include "brdffit/rgl.h"
#include "test_util.h"

namespace brdffit {
namespace {

using test::dir;

const std::vector<std::string> kAnisotropic = {"ggx-aniso", "ward-aniso", "ashikhmin-shirley-aniso"};

using test::kCos30;
using test::kNormal;
using test::shade1;

// v 60° from the normal at azimuth φ; with l = n the half vector is 30° from the normal at φ.
Vec3 at_60(double phi_deg) {
  const double phi = phi_deg * kPi / 180;
  return Vec3(std::sin(kPi / 3) * std::cos(phi), std::sin(kPi / 3) * std::sin(phi), 0.5);
}

TEST(GgxAniso, HandValues) {
  // l = v = n: h = n, D = 1/(π α_x α_y), G = 1, F = f0: f = albedo/π + f0/(4π α_x α_y).
  EXPECT_NEAR(shade1("ggx-aniso", {"albedo=0.2", "f0=0.5", "alpha_x=0.1", "alpha_y=0.4"}, kNormal, kNormal),
              0.2 / kPi + 0.5 / (4 * kPi * 0.04), 1e-12);
  // l = n, v at 60° along the tangent axis (φ₀ = 30°, v at azimuth 30°): h = (sin30 along x, cos30);
  // D = 1/(π α_x α_y ((0.5/α_x)² + 0.75)²); G1(l) = 1; G1(v) = 0.5/(0.5(1-k)+k), k = α_x/2 (v lies
  // along x); F = f0 + (1-f0)(1-cos30)^5; f = D G F/(4·1·0.5); shade = f·1.
  const double ax = 0.2, ay = 0.5, f0 = 0.3;
  auto expected = [&](double along, double across) {
    const double d = 1 / (kPi * along * across * std::pow(std::pow(0.5 / along, 2) + 0.75, 2));
    const double k = along / 2, g = 0.5 / (0.5 * (1 - k) + k), f = f0 + (1 - f0) * std::pow(1 - kCos30, 5);
    return d * g * f / 2;
  };
  const std::vector<std::string> params = {"albedo=0", "f0=0.3", "alpha_x=0.2", "alpha_y=0.5", "phi0=30"};
  EXPECT_NEAR(shade1("ggx-aniso", params, kNormal, at_60(30)), expected(ax, ay), 1e-12);
  // Along the bitangent (azimuth 120°), and along the tangent's opposite (azimuth 210°).
  EXPECT_NEAR(shade1("ggx-aniso", params, kNormal, at_60(120)), expected(ay, ax), 1e-12);
  EXPECT_NEAR(shade1("ggx-aniso", params, kNormal, at_60(210)), expected(ax, ay), 1e-12);
  // φ₀ = 90° with the widths exchanged: v along the table's x axis is along the lobe's y axis.
  EXPECT_NEAR(shade1("ggx-aniso", {"albedo=0", "f0=0.3", "alpha_x=0.5", "alpha_y=0.2", "phi0=90"}, kNormal, at_60(0)),
              expected(ax, ay), 1e-12);
}

TEST(WardAniso, HandValues) {
  // l = v = n: f = albedo/π + specular/(4π α_x α_y).
  EXPECT_NEAR(shade1("ward-aniso", {"albedo=0.1", "specular=0.3", "alpha_x=0.1", "alpha_y=0.3"}, kNormal, kNormal),
              0.1 / kPi + 0.3 / (4 * kPi * 0.03), 1e-12);
  // l = n, v at 60° along the bitangent with φ₀ = 0 (azimuth 90°): tan²θh = 1/3, φh = 90°:
  // f = s·exp(-(1/3)/α_y²)/(4π α_x α_y √(1·0.5)).
  EXPECT_NEAR(
      shade1("ward-aniso", {"albedo=0", "specular=1", "alpha_x=0.1", "alpha_y=0.3", "phi0=0"}, kNormal, at_60(90)),
      std::exp(-1.0 / 3 / 0.09) / (4 * kPi * 0.03 * std::sqrt(0.5)), 1e-12);
  // φh = 45° from the tangent (φ₀ = 10°, azimuth 55°): exponent tan²θh (½/α_x² + ½/α_y²).
  EXPECT_NEAR(
      shade1("ward-aniso", {"albedo=0", "specular=1", "alpha_x=0.4", "alpha_y=0.3", "phi0=10"}, kNormal, at_60(55)),
      std::exp(-1.0 / 3 * (0.5 / 0.16 + 0.5 / 0.09)) / (4 * kPi * 0.12 * std::sqrt(0.5)), 1e-12);
}

TEST(AshikhminShirleyAniso, HandValues) {
  // l = n, v at 60° along the tangent (φ₀ = 0, azimuth 0): e = n_u, n·h = l·h = cos30,
  // max(n·l, n·v) = 1: f = s·√((n_u+1)(n_v+1))/(8π)·cos30^n_u·F/cos30.
  const double nu = 10, nv = 200, f0 = 0.2, f = f0 + (1 - f0) * std::pow(1 - kCos30, 5);
  const double scale = std::sqrt((nu + 1) * (nv + 1)) / (8 * kPi);
  const std::vector<std::string> params = {"albedo=0", "specular=1", "f0=0.2", "n_u=10", "n_v=200", "phi0=0"};
  EXPECT_NEAR(shade1("ashikhmin-shirley-aniso", params, kNormal, at_60(0)), scale * std::pow(kCos30, nu) * f / kCos30,
              1e-12);
  // Along the bitangent: exponent n_v.
  EXPECT_NEAR(shade1("ashikhmin-shirley-aniso", params, kNormal, at_60(90)), scale * std::pow(kCos30, nv) * f / kCos30,
              1e-14);
  // φh = 60°: e = n_u cos²60 + n_v sin²60 = 2.5 + 150.
  EXPECT_NEAR(shade1("ashikhmin-shirley-aniso", params, kNormal, at_60(60)),
              scale * std::pow(kCos30, 0.25 * nu + 0.75 * nv) * f / kCos30, 1e-14);
  // l = v = n: (n·h)^e = 1, F = f0: f = albedo/π + s·scale·f0.
  EXPECT_NEAR(shade1("ashikhmin-shirley-aniso", {"albedo=0.3", "specular=0.5", "f0=0.2", "n_u=10", "n_v=200"}, kNormal,
                     kNormal),
              0.3 / kPi + 0.5 * scale * f0, 1e-12);
}

// Every exact nesting of every model (anisotropic ones against their isotropic versions, two
// lobes against their first lobe, ...) reproduces the inner model's values at random points.
// Anisotropic models equal their isotropic versions for α_x = α_y at any φ₀.
TEST(Nestings, ExactNestingsReproduceTheInnerModel) {
  std::mt19937_64 rng(5);
  std::vector<const Model*> models;
  for (const auto& m : all_models()) models.push_back(m.get());
  for (const char* pair : {"ggx+ggx", "cook-torrance+cook-torrance", "ggx+beckmann", "ward+ggx-aniso"})
    models.push_back(find_model(pair));
  int checked = 0;
  for (const Model* outer : models) {
    for (const Nesting& nesting : outer->nestings()) {
      if (!nesting.exact) continue;
      const Model* inner = find_model(nesting.inner);
      ASSERT_NE(inner, nullptr) << outer->name() << " contains " << nesting.inner;
      for (int trial = 0; trial < 20; ++trial) {
        const std::vector<double> inner_values = test::random_values(*inner, rng);
        std::vector<double> values = embed_values(*outer, nesting, *inner, inner_values);
        for (const ParamSpec& p : outer->parameters())  // an isotropic lobe is the same turned any way
          if (p.role == Role::Orientation)
            values[outer->offset_of(p.name)] = std::uniform_real_distribution<double>(p.lower, p.upper)(rng);
        const Vec3 l = test::random_upper_direction(rng), v = test::random_upper_direction(rng);
        const Rgb<double> expected = inner->shade(inner_values.data(), l, v);
        // A layer of weight 0 is not computed on doubles, nor on the Jets of the linear parts, which
        // differentiate by the colours only (math.h's constant_zero); it is on the Jets that
        // differentiate by the weight. All three must give the inner model's value.
        std::vector<double> jacobian(3 * outer->num_values());
        std::vector<Rgb<double>> basis;
        for (const ParamSpec& p : outer->parameters())
          if (p.linear) basis.emplace_back();
        Rgb<double> rebuilt = outer->shade_linear_parts(values.data(), l, v, basis.data());
        size_t j = 0;
        for (const ParamSpec& p : outer->parameters())
          if (p.linear) {
            for (int c = 0; c < 3; ++c) rebuilt[c] += values[outer->offset_of(p.name) + c % p.channels] * basis[j][c];
            ++j;
          }
        for (const Rgb<double>& got : {outer->shade(values.data(), l, v),
                                       outer->shade_with_jacobian(values.data(), l, v, jacobian.data()), rebuilt})
          for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(got[c], expected[c], 1e-12 * (1 + std::fabs(expected[c])))
                << outer->name() << " ⊃ " << inner->name();
        ++checked;
      }
    }
  }
  EXPECT_GE(checked, 20 * 10);
}

// At weight 0 a layer adds nothing, but its weight's derivative there is the layer's own: the
// Jets that differentiate by the weight compute the layer (math.h's constant_zero), so a fit at
// the contained model's optimum sees which way the layer would take it. Checked against a forward
// difference into the bounds at random values and directions.
TEST(Layers, TheDerivativeByAWeightAtZeroIsTheLayersOwn) {
  std::mt19937_64 rng(23);
  const std::vector<std::pair<const char*, const char*>> weights = {
      {"openpbr+coat", "coat_weight"},       {"openpbr+fuzz", "fuzz_weight"},
      {"openpbr+coat+fuzz", "coat_weight"},  {"openpbr+coat+fuzz", "fuzz_weight"},
      {"gltf+clearcoat", "clearcoatFactor"}, {"gltf+clearcoat+sheen", "clearcoatFactor"}};
  for (const auto& [name, weight] : weights) {
    const Model& model = *find_model(name);
    SCOPED_TRACE(std::string(name) + ", " + weight);
    const int at = model.offset_of(weight);
    ASSERT_GE(at, 0);
    const ParamSpec& p = *model.find_parameter(weight);
    const double h = 1e-7 * (p.upper - p.lower);
    double largest = 0.0;
    for (int trial = 0; trial < 20; ++trial) {
      std::vector<double> values = test::random_values(model, rng);
      values[at] = 0.0;
      const Vec3 l = test::random_upper_direction(rng), v = test::random_upper_direction(rng);
      std::vector<double> jacobian(3 * model.num_values());
      const Rgb<double> at_zero = model.shade_with_jacobian(values.data(), l, v, jacobian.data());
      std::vector<double> moved = values;
      moved[at] = h;
      const Rgb<double> slope = (model.shade(moved.data(), l, v) - at_zero) / h;
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(jacobian[c * model.num_values() + at], slope[c], 1e-4 * (1.0 + std::fabs(slope[c])));
        largest = std::max(largest, std::fabs(slope[c]));
      }
    }
    EXPECT_GT(largest, 1e-3) << "the layer must matter somewhere";
  }
}

// The models whose derivatives and reciprocity are checked here: anisotropic and two lobes.
std::vector<const Model*> new_models() {
  std::vector<const Model*> models;
  for (const std::string& name : kAnisotropic) models.push_back(find_model(name));
  for (const char* pair : {"ggx+ggx", "cook-torrance+cook-torrance", "ggx+beckmann", "ward-aniso+ashikhmin-shirley"})
    models.push_back(find_model(pair));
  return models;
}

TEST(NewModels, AutomaticDerivativesMatchFiniteDifferences) {
  std::mt19937_64 rng(7);
  for (const Model* model : new_models()) {
    ASSERT_NE(model, nullptr);
    const int n = model->num_values();
    for (int trial = 0; trial < 10; ++trial) {
      std::vector<double> values = test::random_values(*model, rng, 0.1);
      // Exponents over their whole range make lobes too sharp for finite differences at random pairs.
      for (const ParamSpec& p : model->parameters())
        if (p.role == Role::Exponent) values[model->offset_of(p.name)] = 5 + 40 * trial / 10.0;
      const Vec3 l = test::random_upper_direction(rng, 0.2), v = test::random_upper_direction(rng, 0.2);
      std::vector<double> jacobian(3 * n);
      model->shade_with_jacobian(values.data(), l, v, jacobian.data());
      for (int i = 0; i < n; ++i) {
        const double h = 1e-6 * std::max(1.0, std::fabs(values[i]));
        std::vector<double> up = values, down = values;
        up[i] += h;
        down[i] -= h;
        const Rgb<double> numeric = (model->shade(up.data(), l, v) - model->shade(down.data(), l, v)) / (2 * h);
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(jacobian[c * n + i], numeric[c], 1e-5 * (1 + std::fabs(numeric[c])))
              << model->name() << " value " << i << " channel " << c;
      }
    }
  }
}

TEST(NewModels, Reciprocal) {
  std::mt19937_64 rng(11);
  for (const Model* model : new_models()) {
    ASSERT_TRUE(model->has_brdf());
    for (int trial = 0; trial < 50; ++trial) {
      const std::vector<double> values = test::random_values(*model, rng);
      const Vec3 l = test::random_upper_direction(rng), v = test::random_upper_direction(rng);
      const Rgb<double> a = *model->brdf(values.data(), l, v), b = *model->brdf(values.data(), v, l);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-12 * (1 + std::fabs(a[c]))) << model->name();
    }
  }
}

// Fits `model` to a table and checks the recovered frame against the truth (3 % on the widths,
// 1° on φ₀, compared in canonical form).
void expect_frame_recovered(const Model& model, const SampleSet& data, const test::TangentFrame& truth,
                            double width_tolerance = 0.03, double angle_tolerance_deg = 1.0) {
  FitOptions options;
  options.threads = 1;
  const FitResult fit = fit_model(model, data, options);
  ASSERT_TRUE(fit.ok) << fit.error;
  const std::vector<ParamSpec>& params = model.parameters();
  const int x = model.offset_of(params[params.size() - 3].name), y = x + 1, phi0 = x + 2;
  const test::TangentFrame got = test::canonical_frame(fit.values[x], fit.values[y], fit.values[phi0]);
  EXPECT_NEAR(got.along_x / truth.along_x, 1.0, width_tolerance) << data.source;
  EXPECT_NEAR(got.along_y / truth.along_y, 1.0, width_tolerance) << data.source;
  EXPECT_LT(test::angle_difference(got.phi0, truth.phi0), angle_tolerance_deg)
      << data.source << ": φ₀ " << got.phi0 << " for " << truth.phi0;
}

// Noisy samples at several rotations, read back through CSV: the three anisotropic models
// recover their frame.
TEST(AnisotropicFit, RecoversWidthsAndRotationFromNoisyCsv) {
  const std::vector<test::AnisotropicCase> cases = test::anisotropic_cases();
  int k = 0;
  for (const test::AnisotropicCase& c : cases)
    for (double rotation : {0.0, 37.0, 122.0}) {
      const Model& model = *find_model(c.model);
      const std::vector<double> truth = test::turned_values(model, c.params, c.width_x, c.width_y, rotation);
      const SampleSet samples = test::anisotropic_samples(model, truth, 2000, 0.02, ++k);
      SampleSet csv = parse_csv_samples(format_csv_samples(samples), c.model + ".csv");
      ASSERT_EQ(csv.size(), samples.size());
      const int x = model.num_values() - 3;
      expect_frame_recovered(model, csv, test::canonical_frame(truth[x], truth[x + 1], truth[x + 2]));
    }
}

// The renderer materials whose lobe is stretched along a turned tangent (a strength and a rotation
// in radians, the stretch the same turned by π): gltf+anisotropy and principled recover both from
// noisy samples, at rotations off the axes and on one, and read through CSV.
TEST(AnisotropicFit, RecoversTheStretchAndItsRotationOfTheRendererMaterials) {
  struct Case {
    std::string model, strength, rotation;
    std::vector<std::string> params;
  };
  const std::vector<Case> cases = {
      {"gltf+anisotropy",
       "anisotropyStrength",
       "anisotropyRotation",
       {"baseColor=0.7,0.5,0.3", "metallic=0.8", "roughness=0.3", "anisotropyStrength=0.6"}},
      {"principled",
       "anisotropic",
       "anisotropicRotation",
       {"baseColor=0.7,0.5,0.3", "metallic=0.8", "roughness=0.3", "anisotropic=0.7", "sheenTint=0"}}};
  int seed = 40;
  for (const Case& c : cases)
    for (const double rotation : {0.0, 1.1, 2.2}) {
      SCOPED_TRACE(c.model + " turned by " + std::to_string(rotation));
      const Model& model = *find_model(c.model);
      std::vector<double> truth = parameter_values(model, c.params);
      truth[model.offset_of(c.rotation)] = rotation;
      const SampleSet samples = test::anisotropic_samples(model, truth, 3000, 0.02, ++seed);
      const SampleSet csv = parse_csv_samples(format_csv_samples(samples), c.model + ".csv");
      ASSERT_FALSE(csv.isotropic);
      FitOptions options;
      options.threads = 1;
      const FitResult fit = fit_model(model, csv, options);
      ASSERT_TRUE(fit.ok) << fit.error;
      EXPECT_NEAR(fit.values[model.offset_of(c.strength)], truth[model.offset_of(c.strength)], 0.02);
      const double turned = fit.values[model.offset_of(c.rotation)] - rotation;
      EXPECT_LT(std::abs(turned - kPi * std::round(turned / kPi)), 1.0 * kPi / 180)
          << "rotation " << fit.values[model.offset_of(c.rotation)];
    }
}

// An anisotropic RGL-format file tabulating ggx-aniso, turned to several rotations (one test
// each): the reader evaluates it like the model, samples it over the whole turn of φ, and the
// fit recovers the frame.
class AnisotropicRglFile : public ::testing::TestWithParam<double> {};

TEST_P(AnisotropicRglFile, RecoversTheFrame) {
  const Model& model = *find_model("ggx-aniso");
  const double rotation = GetParam();
  const std::vector<double> truth = test::turned_values(model, {"albedo=0.1", "f0=0.5", "alpha_x=0.15", "alpha_y=0.4"},
                                                        "alpha_x", "alpha_y", rotation);
  const RglBrdf table = RglBrdf::parse(test::tensor_file_bytes(test::anisotropic_rgl_fields(model, truth)),
                                       "ggx-aniso-" + std::to_string(int(rotation)) + ".bsdf");
  ASSERT_FALSE(table.isotropic());
  SamplingOptions sampling;
  sampling.max_angle_deg = 80;
  sampling.max_samples = 4000;
  const SampleSet samples = table.samples(sampling);
  // Half vectors over the whole turn: every quarter of φh holds about a quarter of them.
  std::array<int, 4> quarters{};
  for (const Sample& s : samples.samples) {
    const Vec3 h = half_vector(s.l, s.v);
    ++quarters[int(std::floor((std::atan2(h.y(), h.x()) + kPi) / (kPi / 2))) % 4];
  }
  for (int q : quarters) EXPECT_NEAR(q / double(samples.size()), 0.25, 0.03);
  // The table reproduces the model within a few percent where the lobe matters.
  double error = 0, total = 0;
  for (const Sample& s : samples.samples) {
    error += (s.value - model.shade(truth.data(), s.l, s.v)).cwiseAbs().sum();
    total += s.value.sum();
  }
  EXPECT_LT(error / total, 0.02);
  expect_frame_recovered(model, samples, test::canonical_frame(truth[6], truth[7], truth[8]));
}

INSTANTIATE_TEST_SUITE_P(AnisotropicFit, AnisotropicRglFile, ::testing::Values(20.0, 75.0, 150.0),
                         [](const auto& info) { return std::to_string(int(info.param)) + "deg"; });

}  // namespace
}  // namespace brdffit
