// OpenPBR's coat and fuzz (models/openpbr_layers.h): values derived by hand at a generic pair of
// directions, the exact nestings, what each weight does, parameter recovery from generated data,
// the family's names, and the .mtlx round trip and conversions.
#include <gtest/gtest.h>

#include <random>

#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/io.h"
#include "brdffit/material_convert.h"
#include "brdffit/material_export.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"
#include "test_util.h"

namespace brdffit {
namespace {

// The generic pair: l and v in different planes, v at 61° (where the fuzz is well lit), no term
// at a bound (MaterialX's clamped albedo fit, the min of the roughening) or vanishing.
const Vec3 kLight = Vec3(0.3, 0.2, 0.9).normalized(), kView = Vec3(-0.8, 0.15, 0.45).normalized();

const std::vector<std::string> kBaseAssignments = {"base_color=0.6,0.4,0.2",     "base_metalness=0.3",
                                                   "base_diffuse_roughness=0.4", "specular_color=0.9,0.8,0.7",
                                                   "specular_roughness=0.35",    "specular_ior=1.45"};
const std::vector<std::string> kCoat = {"coat_weight=0.7", "coat_color=0.9,0.7,0.5", "coat_roughness=0.6",
                                        "coat_ior=1.8"};
const std::vector<std::string> kFuzz = {"fuzz_weight=0.6", "fuzz_color=0.8,0.5,0.3", "fuzz_roughness=0.45"};

std::vector<std::string> joined(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

Rgb<double> brdf_of(const std::string& model, const std::vector<std::string>& assignments) {
  const Model& m = *find_model(model);
  return *m.brdf(parameter_values(m, assignments).data(), kLight, kView);
}

// The coat at kLight, kView, derived by hand (numpy, from the formulas at the head of
// openpbr_layers.h, written independently of the C++: the Fresnel from the polarised amplitudes
// Rs, Rp with Snell's law, D in its isotropic form α²/(π((n·h)²(α²-1)+1)²), G2 as 1/(1+Λl+Λv)
// with Λ = (-1+√(1+α²tan²θ))/2, MaterialX's albedo fit as its 4-vector of rational polynomials):
//   αc = 0.36; F(v·h, 1.8) = 0.087497522, D = 0.50266961, G2 = 0.90758054;
//   MaterialX's fit at (n·v 0.48384300, 0.36): a = 0.76868636, b = 0.017323677 (neither clamped),
//   comp = 1 + F(1 - a - b)/(a + b) = 1.0238211;
//   f_coat = 0.7·D·F·G2·comp/(4 n·l n·v) = 0.015923650009864815;
//   τ = 1 - 0.7(F0c·a + b)comp with F0c = (0.8/2.8)², K = 1 - (1 - F0c)/1.8²,
//   Δ = 1 + 0.7((1-K)/(1-ρK) - 1), A = 1 + 0.7(coat_color - 1): τΔA per channel below;
//   the base under it: specular_roughness r' = 0.3·0.35 + 0.7·(0.35⁴ + 2·0.6⁴)^¼ = 0.61154424,
//   specular_ior η_s = 0.3·1.45 + 0.7·(1.8/1.45) = 1.3039655 (the coat's index above the base's).
TEST(OpenPbrLayers, CoatMatchesHandDerivedValues) {
  const double lobe = 0.015923650009864815;
  const Rgb<double> factor(0.5681011038656604, 0.4305135996233194, 0.3257130597178589);
  std::vector<std::string> under = kBaseAssignments;
  under[4] = "specular_roughness=0.6115442354485287";
  under[5] = "specular_ior=1.3039655172413793";
  const Rgb<double> base = brdf_of("openpbr", under);
  const Rgb<double> coated = brdf_of("openpbr+coat", joined(kBaseAssignments, kCoat));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(coated[c], lobe + factor[c] * base[c], 1e-12 * coated[c]) << c;
  // Not the base alone: the coat's terms all count here.
  EXPECT_GT((coated - brdf_of("openpbr", kBaseAssignments)).cwiseAbs().minCoeff(), 0.01 * coated.minCoeff());
}

// The fuzz at kLight, kView, derived by hand (numpy): MaterialX's fits at (n·v 0.48384300, σ 0.45)
// give E = 0.12018843, a⁻¹ = 0.44291960, b⁻¹ = -0.049543428; l in the frame of v's tangential
// direction, w = M⁻¹ l with M⁻¹ = [[a⁻¹, 0, b⁻¹], [0, a⁻¹, 0], [0, 0, 1]] and the LTC's general
// form D = D₀(w/|w|)·|det M⁻¹|/|w|³ (D₀ the clamped cosine over π) = 0.071280078;
// the fuzz's BRDF per unit of fuzz_color: 0.6·E·D/(n·l) = 0.00553736948638021, and what it lets
// through: 1 - 0.6·E = 0.9278869404180389.
TEST(OpenPbrLayers, FuzzMatchesHandDerivedValues) {
  const double fuzz = 0.00553736948638021, through = 0.9278869404180389;
  const Rgb<double> colour(0.8, 0.5, 0.3);
  const Rgb<double> base = brdf_of("openpbr", kBaseAssignments),
                    fuzzed = brdf_of("openpbr+fuzz", joined(kBaseAssignments, kFuzz));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(fuzzed[c], colour[c] * fuzz + through * base[c], 1e-12 * fuzzed[c]) << c;
  // With both layers the fuzz lies on the coat.
  const Rgb<double> coated = brdf_of("openpbr+coat", joined(kBaseAssignments, kCoat)),
                    both = brdf_of("openpbr+coat+fuzz", joined(joined(kBaseAssignments, kCoat), kFuzz));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(both[c], colour[c] * fuzz + through * coated[c], 1e-12 * both[c]) << c;
}

// Every declared nesting reproduces the inner model to rounding, at random values and directions
// (the layer's other parameters anywhere in their bounds).
TEST(OpenPbrLayers, NestingsAreExact) {
  std::mt19937_64 rng(5);
  for (const char* name : {"openpbr+coat", "openpbr+fuzz", "openpbr+coat+fuzz"}) {
    const Model& outer = *find_model(name);
    ASSERT_FALSE(outer.nestings().empty()) << name;
    for (const Nesting& nesting : outer.nestings()) {
      SCOPED_TRACE(std::string(name) + " ⊃ " + nesting.inner);
      EXPECT_TRUE(nesting.exact);
      const Model& inner = *find_model(nesting.inner);
      for (int trial = 0; trial < 200; ++trial) {
        const std::vector<double> inner_values = test::random_values_with_bounds(inner, rng);
        // The outer model's own values random too, then the nesting's copies and fixed values.
        std::vector<double> outer_values = test::random_values_with_bounds(outer, rng);
        const std::vector<double> embedded = embed_values(outer, nesting, inner, inner_values);
        for (const ParamSpec& p : outer.parameters()) {
          const bool set_by_nesting =
              std::any_of(nesting.copies.begin(), nesting.copies.end(), [&](auto& c) { return c.to == p.name; }) ||
              std::any_of(nesting.fixed.begin(), nesting.fixed.end(), [&](auto& f) { return f.first == p.name; });
          if (set_by_nesting)
            std::copy_n(embedded.begin() + outer.offset_of(p.name), p.channels,
                        outer_values.begin() + outer.offset_of(p.name));
        }
        const Vec3 l = test::random_direction_up_to(rng, 89), v = test::random_direction_up_to(rng, 89);
        const Rgb<double> a = outer.shade(outer_values.data(), l, v), b = inner.shade(inner_values.data(), l, v);
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(a[c], b[c], 1e-15 * std::max(1.0, b[c]));
      }
    }
  }
  EXPECT_EQ(find_model("openpbr+coat+fuzz")->nestings().size(), 2u);
}

// What the weights do. A coat of coat_color 0 at full weight absorbs everything under it: only
// its own reflection is left, the same over any base. A coat brightens the mirror direction of a
// rough base (its sharp lobe) and, with its weight, grows there. The fuzz, dark (fuzz_color 0),
// only takes away: (1 - W·E) of the base, less with more weight; white, it brightens a dark base at
// grazing view.
TEST(OpenPbrLayers, WeightsDoWhatTheyMean) {
  const Vec3 v = test::dir(-0.8, 0, 0.3), mirror = test::dir(0.8, 0, 0.3), l = test::dir(0.2, 0.3, 1);
  const std::vector<std::string> rough = {"base_color=0.5,0.4,0.3", "specular_roughness=0.8"};
  const auto coat_shade = [&](const std::vector<std::string>& coat, const std::vector<std::string>& base,
                              const Vec3& light) { return test::shade("openpbr+coat", joined(base, coat), light, v); };
  const Rgb<double> absorbed = coat_shade({"coat_weight=1", "coat_color=0", "coat_roughness=0.2"}, rough, l);
  const Rgb<double> absorbed_dark = coat_shade({"coat_weight=1", "coat_color=0", "coat_roughness=0.2"},
                                               {"base_color=0.05", "specular_roughness=0.3", "base_metalness=1"}, l);
  EXPECT_GT(absorbed[0], 0.0);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(absorbed[c], absorbed_dark[c], 1e-15);
  double previous = test::shade("openpbr", rough, mirror, v)[1];
  for (const char* weight : {"coat_weight=0.25", "coat_weight=0.5", "coat_weight=1"}) {
    const double coated = coat_shade({weight, "coat_roughness=0.1"}, rough, mirror)[1];
    EXPECT_GT(coated, 1.2 * previous) << weight;
    previous = coated;
  }
  const std::vector<std::string> dark = {"base_color=0.05", "specular_ior=1.2"};
  const auto fuzz_shade = [&](const std::vector<std::string>& fuzz, const std::vector<std::string>& base) {
    return test::shade("openpbr+fuzz", joined(base, fuzz), l, v);
  };
  const Rgb<double> bare = test::shade("openpbr", rough, l, v);
  const Rgb<double> half = fuzz_shade({"fuzz_weight=0.5", "fuzz_color=0"}, rough),
                    full = fuzz_shade({"fuzz_weight=1", "fuzz_color=0"}, rough);
  for (int c = 0; c < 3; ++c) {
    EXPECT_LT(half[c], bare[c]);
    EXPECT_LT(full[c], half[c]);
    // Linear in the weight: (1 - W·E) of the base.
    EXPECT_NEAR(bare[c] - half[c], 0.5 * (bare[c] - full[c]), 1e-14);
  }
  EXPECT_GT(fuzz_shade({"fuzz_weight=1", "fuzz_color=1"}, dark)[0], 1.5 * test::shade("openpbr", dark, l, v)[0]);
}

// The fitter recovers a coat and a fuzz from their own values (20,000 samples, 1 % noise), with the
// base's metal, diffuse roughness, ior and specular tint held as known (their trade-offs are
// openpbr's, model.h's RecoveryFacts): each layer's weight and roughness, the fuzz's colour and the
// base colour within 2 %. Under a coat, base_color and coat_color reach the diffuse as a product
// ρ·lerp(1, coat_color, coat_weight), and coat_color alone only through the base's faint dielectric
// reflection (η_s 1.24 here: F0 1 %): they trade off (measured: coat_color 4 % off with base_color
// 2 % off the other way, at a cost 0.1 % from the truth's), so the product is what is checked.
FitResult fit_of_own_values(const Model& model, const std::vector<double>& truth) {
  const SampleSet data = test::model_table(model, truth, 20000, 0.01, 3, 0.02);
  FitOptions options;
  options.fixed = {
      {"base_metalness", 0.0}, {"base_diffuse_roughness", 0.0}, {"specular_ior", 1.5}, {"specular_color", 1.0}};
  if (model.find_parameter("coat_ior")) options.fixed.push_back({"coat_ior", 1.6});
  FitResult fit = fit_model(model, data, options);
  EXPECT_TRUE(fit.ok) << fit.error;
  // The optimiser's own test: at least as good as the truth on these data.
  EXPECT_LE(fit.metrics.cosine, 1.001 * evaluate_metrics(model, truth, data).cosine);
  EXPECT_LT(fit.metrics.relative, 0.03);
  return fit;
}

std::vector<double> fitted_values(const FitResult& fit) {
  std::vector<double> values;
  for (const ParameterEstimate& p : fit.parameters) values.insert(values.end(), p.value.begin(), p.value.end());
  return values;
}

void expect_within(const Model& model, const std::vector<double>& fitted, const std::vector<double>& truth,
                   const std::vector<std::string>& names, double relative) {
  for (const std::string& name : names) {
    const int offset = model.offset_of(name);
    for (int c = 0; c < model.find_parameter(name)->channels; ++c)
      EXPECT_NEAR(fitted[offset + c], truth[offset + c], relative * truth[offset + c]) << name << "[" << c << "]";
  }
}

TEST(OpenPbrLayers, FitRecoversTheCoat) {
  const Model& model = *find_model("openpbr+coat");
  const std::vector<double> truth =
      parameter_values(model, {"base_color=0.5,0.3,0.2", "specular_roughness=0.4", "base_metalness=0",
                               "coat_weight=0.6", "coat_color=0.9,0.7,0.5", "coat_roughness=0.15"});
  const std::vector<double> fitted = fitted_values(fit_of_own_values(model, truth));
  expect_within(model, fitted, truth, {"coat_weight", "coat_roughness", "specular_roughness"}, 0.02);
  const int base = model.offset_of("base_color"), coat = model.offset_of("coat_color");
  const double weight = truth[model.offset_of("coat_weight")];
  const auto under_coat = [&](const std::vector<double>& x, int c) {
    return x[base + c] * (1.0 + weight * (x[coat + c] - 1.0));
  };
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(under_coat(fitted, c), under_coat(truth, c), 0.01 * under_coat(truth, c));
}

TEST(OpenPbrLayers, FitRecoversTheFuzz) {
  const Model& model = *find_model("openpbr+fuzz");
  const std::vector<double> truth =
      parameter_values(model, {"base_color=0.5,0.3,0.2", "specular_roughness=0.5", "base_metalness=0",
                               "fuzz_weight=0.8", "fuzz_color=0.9,0.6,0.4", "fuzz_roughness=0.4"});
  expect_within(model, fitted_values(fit_of_own_values(model, truth)), truth,
                {"base_color", "specular_roughness", "fuzz_weight", "fuzz_color", "fuzz_roughness"}, 0.02);
}

// The layers in any order name the registered model; a layer OpenPBR's models do not have is
// refused naming those they do.
TEST(OpenPbrLayers, LayersMayBeNamedInAnyOrder) {
  EXPECT_EQ(find_model("openpbr+fuzz+coat"), find_model("openpbr+coat+fuzz"));
  EXPECT_EQ(find_model("openpbr+fuzz+coat")->name(), "openpbr+coat+fuzz");
  EXPECT_EQ(parse_model_list("openpbr+coat,openpbr+fuzz+coat,openpbr+coat+fuzz").size(), 2u);
  for (const std::string name : {"openpbr+sheen", "openpbr+coat+coat", "openpbr+ggx", "openpbr+fuzz+clearcoat"}) {
    try {
      find_model(name);
      ADD_FAILURE() << name;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("from: coat, fuzz (openpbr+coat, openpbr+fuzz, openpbr+coat+fuzz)"),
                std::string::npos)
          << e.what();
    }
  }
  EXPECT_THROW(parse_model_list("openpbr+cote"), UsageError);
}

// A .mtlx written from each model reads back as the smallest model holding its layers, with the
// same values (nine significant digits, so these short decimals come back exactly); the weights
// decide, not the presence of the other inputs.
TEST(OpenPbrLayers, MtlxRoundTripReadsTheSmallestModelHoldingTheLayers) {
  const std::string dir = test::fresh_dir("openpbr-layers-mtlx");
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"openpbr+coat", joined(kBaseAssignments, kCoat)},
      {"openpbr+fuzz", joined(kBaseAssignments, kFuzz)},
      {"openpbr+coat+fuzz", joined(joined(kBaseAssignments, kCoat), kFuzz)}};
  for (const auto& [name, assignments] : cases) {
    SCOPED_TRACE(name);
    const Model& model = *find_model(name);
    const Material written{"m", name, parameter_values(model, assignments)};
    const std::string path = dir + "/" + std::to_string(model.num_values()) + ".mtlx";
    write_file_atomic(path, materialx_document(written, "test"));
    std::vector<std::string> warnings;
    const Material read = read_material(path, "", warnings);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    EXPECT_EQ(read.model, name);
    EXPECT_EQ(read.values, written.values);
  }
  // coat_weight 0 with the coat's other inputs given: the base alone, silently.
  std::vector<double> off = parameter_values(*find_model("openpbr+coat"), joined(kBaseAssignments, kCoat));
  off[find_model("openpbr+coat")->offset_of("coat_weight")] = 0.0;
  write_file_atomic(dir + "/off.mtlx", materialx_document({"m", "openpbr+coat", off}, "test"));
  std::vector<std::string> warnings;
  const Material base = read_material(dir + "/off.mtlx", "", warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(base.model, "openpbr");
  EXPECT_EQ(base.values, parameter_values(*find_model("openpbr"), kBaseAssignments));
  // A coat without coat_roughness: OpenPBR's default 0, clamped to the model's bound with a warning;
  // a coat_darkening other than the held 1 is reported.
  write_file_atomic(dir + "/bare.mtlx",
                    "<materialx version=\"1.39\">\n  <open_pbr_surface name=\"s\" type=\"surfaceshader\">\n"
                    "    <input name=\"coat_weight\" type=\"float\" value=\"0.5\" />\n"
                    "    <input name=\"coat_darkening\" type=\"float\" value=\"0.5\" />\n"
                    "  </open_pbr_surface>\n</materialx>\n");
  warnings.clear();
  const Material bare = read_material(dir + "/bare.mtlx", "", warnings);
  EXPECT_EQ(bare.model, "openpbr+coat");
  EXPECT_EQ(bare.values[find_model("openpbr+coat")->offset_of("coat_roughness")], 0.01);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("coat_roughness of 's' is 0, outside the openpbr+coat model's [0.01, 1]"),
            std::string::npos)
      << warnings[0];
  EXPECT_NE(warnings[1].find("coat_darkening 0.5 of 's' is held at 1"), std::string::npos) << warnings[1];
}

// Conversions keep the layers the target has: glTF's clear coat and sheen become OpenPBR's coat
// and fuzz, and back; a layer the target has not is left out.
TEST(OpenPbrLayers, ConversionsKeepTheLayersTheTargetHas) {
  const Model& gltf_both = *find_model("gltf+clearcoat+sheen");
  const std::vector<double> gltf_values = parameter_values(
      gltf_both, {"baseColor=0.8,0.5,0.25", "roughness=0.45", "clearcoatFactor=0.7", "clearcoatRoughnessFactor=0.15",
                  "sheenColorFactor=0.6,0.3,0.2", "sheenRoughnessFactor=0.35"});
  const Material openpbr = convert_material("gltf+clearcoat+sheen", gltf_values, "openpbr+coat+fuzz");
  const Model& target = *find_model("openpbr+coat+fuzz");
  EXPECT_EQ(value_at(target, openpbr.values, "coat_weight"), 0.7);
  EXPECT_EQ(value_at(target, openpbr.values, "coat_roughness"), 0.15);
  EXPECT_EQ(value_at(target, openpbr.values, "coat_ior"), 1.5);
  EXPECT_EQ(value_at(target, openpbr.values, "fuzz_weight"), 0.6);
  EXPECT_TRUE(colour_at(target, openpbr.values, "fuzz_color").isApprox(Rgb<double>(1, 0.5, 1.0 / 3), 1e-15));
  EXPECT_EQ(value_at(target, openpbr.values, "fuzz_roughness"), 0.35);
  // And back: the same factors.
  const Material gltf = convert_material("openpbr+coat+fuzz", openpbr.values, "gltf+clearcoat+sheen");
  EXPECT_EQ(value_at(gltf_both, gltf.values, "clearcoatFactor"), 0.7);
  EXPECT_TRUE(colour_at(gltf_both, gltf.values, "sheenColorFactor").isApprox(Rgb<double>(0.6, 0.3, 0.2), 1e-15));
  // Into a target without the layers: the base, the layers off.
  const Material coat_only = convert_material("gltf+clearcoat+sheen", gltf_values, "openpbr+coat");
  EXPECT_EQ(coat_only.model, "openpbr+coat");
  EXPECT_EQ(value_at(*find_model("openpbr+coat"), coat_only.values, "coat_weight"), 0.7);
  // A contained model converts parameter by parameter: openpbr into openpbr+coat is exact.
  const std::vector<double> base = parameter_values(*find_model("openpbr"), kBaseAssignments);
  const Material nested = convert_material("openpbr", base, "openpbr+coat");
  EXPECT_EQ(value_at(*find_model("openpbr+coat"), nested.values, "coat_weight"), 0.0);
  EXPECT_EQ(find_model("openpbr+coat")->shade(nested.values.data(), kLight, kView),
            find_model("openpbr")->shade(base.data(), kLight, kView));
}

}  // namespace
}  // namespace brdffit
