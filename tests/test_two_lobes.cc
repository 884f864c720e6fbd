// Two specular lobes over one Lambert base ("FIRST+SECOND"): the composite's parameters and
// values, its cost function against the templated one, and the guarantee that a two-lobe fit
// started from the one-lobe optimum is never worse.
#include <gtest/gtest.h>

#include <unistd.h>
#include "aniso_tables.h"

#include <filesystem>
#include <map>
#include <sstream>

#include "brdffit/csv_samples.h"
#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/io.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"
#include "test_util.h"

namespace brdffit {
namespace {

std::vector<std::string> names_of(const Model& model) {
  std::vector<std::string> names;
  for (const ParamSpec& p : model.parameters()) names.push_back(p.name);
  return names;
}

TEST(TwoLobes, ParametersOfBothLobesShareOneAlbedo) {
  const Model* ggx2 = find_model("ggx+ggx");
  ASSERT_NE(ggx2, nullptr);
  EXPECT_EQ(ggx2->name(), "ggx+ggx");
  // GGX's f0 at 0 leaves Schlick's (1-l·h)^5: the second lobe gets a weight, and its f0 is
  // stored multiplied by the weight, so both stay linear.
  EXPECT_EQ(names_of(*ggx2),
            (std::vector<std::string>{"albedo", "roughness", "f0", "roughness_2", "f0_2", "weight_2"}));
  EXPECT_TRUE(ggx2->find_parameter("f0")->linear);
  EXPECT_TRUE(ggx2->find_parameter("f0_2")->linear);
  EXPECT_TRUE(ggx2->find_parameter("weight_2")->linear);
  // Cook-Torrance's specular at 0 removes its lobe: no weight needed.
  const Model* ct2 = find_model("cook-torrance+cook-torrance");
  ASSERT_NE(ct2, nullptr);
  EXPECT_EQ(names_of(*ct2), (std::vector<std::string>{"albedo", "specular", "f0", "m", "specular_2", "f0_2", "m_2"}));
  EXPECT_TRUE(ct2->find_parameter("specular_2")->linear);
  EXPECT_EQ(find_model("ggx+ggx"), ggx2) << "built once";
}

TEST(TwoLobes, HandValues) {
  // l = v = n: h = n; a GGX lobe is D·F·G/4 = f0/(4π α²) with α = roughness²; the second
  // lobe's F is f0_2 at normal incidence (its stored f0 is already w·f0):
  // f = albedo/π + f0/(4π α₁²) + f0₂/(4π α₂²).
  const Model& ggx2 = *find_model("ggx+ggx");
  const std::vector<double> values =
      parameter_values(ggx2, {"albedo=0.2", "roughness=0.5", "f0=0.04", "roughness_2=0.3", "f0_2=0.9", "weight_2=0.5"});
  const Vec3 n(0, 0, 1);
  const double expected = 0.2 / kPi + 0.04 / (4 * kPi * std::pow(0.25, 2)) + 0.9 / (4 * kPi * std::pow(0.09, 2));
  EXPECT_NEAR(ggx2.shade(values.data(), n, n)[1], expected, 1e-12);
  // Mirror pair at 60°: h = n, l·h = cos60 = 0.5, G1 = x/(x(1-k)+k) per direction, k = α/2;
  // lobe = D·F·G/(4·0.25)·cos60 with the second lobe's F = f0₂ + (w - f0₂)(1-0.5)^5.
  const Vec3 l(std::sqrt(0.75), 0, 0.5), v(-std::sqrt(0.75), 0, 0.5);
  auto lobe = [](double alpha, double f) {
    const double k = alpha / 2, g1 = 0.5 / (0.5 * (1 - k) + k);
    return 1 / (kPi * alpha * alpha) * f * g1 * g1 / (4 * 0.25);
  };
  const double m5 = std::pow(0.5, 5);
  EXPECT_NEAR(ggx2.shade(values.data(), l, v)[0],
              (0.2 / kPi + lobe(0.25, 0.04 + 0.96 * m5) + lobe(0.09, 0.9 + (0.5 - 0.9) * m5)) * 0.5, 1e-12);
  // Cook-Torrance at l = v = n: D = 1/(π m²), G = 1, F = f0: lobe = specular·f0/(π m²)/π.
  const Model& ct2 = *find_model("cook-torrance+cook-torrance");
  const std::vector<double> ct_values = parameter_values(
      ct2, {"albedo=0.1", "specular=0.5", "f0=0.2", "m=0.3", "specular_2=0.25", "f0_2=0.8", "m_2=0.1"});
  EXPECT_NEAR(ct2.shade(ct_values.data(), n, n)[0],
              0.1 / kPi + 0.5 * 0.2 / (kPi * 0.09) / kPi + 0.25 * 0.8 / (kPi * 0.01) / kPi, 1e-12);
  // Below the horizon: nothing.
  EXPECT_EQ(ggx2.shade(values.data(), Vec3(0.6, 0, -0.8), n), Rgb<double>::Zero());
}

TEST(TwoLobes, NestingsNameTheFirstLobeAndLambertWithHonestExactness) {
  const Model& ggx2 = *find_model("ggx+ggx");
  ASSERT_EQ(ggx2.nestings().size(), 2u);
  EXPECT_EQ(ggx2.nestings()[0].inner, "ggx");
  EXPECT_TRUE(ggx2.nestings()[0].exact);
  EXPECT_EQ(ggx2.nestings()[1].inner, "lambert");
  EXPECT_FALSE(ggx2.nestings()[1].exact) << "GGX's lobe does not vanish at f0 = 0";
  const Model& ct_ggx = *find_model("cook-torrance+ggx");
  EXPECT_EQ(ct_ggx.nestings()[0].inner, "cook-torrance");
  EXPECT_TRUE(ct_ggx.nestings()[1].exact) << "specular = 0 removes Cook-Torrance's lobe";
}

TEST(TwoLobes, UnknownOrUnsuitableComponentsAreRefused) {
  EXPECT_EQ(find_model("ggx+nosuch"), nullptr);
  EXPECT_EQ(find_model("ggx+"), nullptr);
  auto expect_refused = [](const std::string& name, const std::string& why) {
    try {
      find_model(name);
      ADD_FAILURE() << name << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  };
  expect_refused("lambert+ggx", "lambert is not a specular lobe");  // no lobe
  expect_refused("ggx+toon", "toon is not a specular lobe");
  expect_refused("ggx+sgd", "sgd has 33 values");  // a lobe over Lambert, larger than a component may be
  EXPECT_EQ(parse_model_list("ggx,ggx+ggx").size(), 2u);
  EXPECT_EQ(parse_model_list("all").size(), all_models().size()) << "'all' stays the single-lobe set";
}

// '+' also joins glTF's extensions to the core: a registered name is looked up before two lobes,
// the extensions may come in any order, the former name gltf-clearcoat still works, and an
// extension brdffit does not fit is refused naming those it does.
TEST(TwoLobes, GltfExtensionNamesAreModelsNotLobes) {
  const Model* coat = find_model("gltf+clearcoat");
  ASSERT_NE(coat, nullptr);
  EXPECT_NE(coat->find_parameter("clearcoatFactor"), nullptr);
  EXPECT_EQ(find_model("gltf-clearcoat"), coat);
  ASSERT_NE(find_model("gltf+sheen"), nullptr);
  EXPECT_NE(find_model("gltf+sheen")->find_parameter("sheenColorFactor"), nullptr);
  const Model* both = find_model("gltf+clearcoat+sheen");
  ASSERT_NE(both, nullptr);
  EXPECT_EQ(find_model("gltf+sheen+clearcoat"), both);
  EXPECT_EQ(both->num_values(), 11);
  EXPECT_NE(find_model("gltf+anisotropy")->find_parameter("anisotropyStrength"), nullptr);
  // A layer twice, an unknown one, and known ones that no model combines.
  for (const std::string name :
       {"gltf+sheen+sheen", "gltf+ggx", "gltf+sheen+iridescence", "gltf+anisotropy+clearcoat"}) {
    try {
      find_model(name);
      ADD_FAILURE() << name;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("from: clearcoat, sheen, anisotropy (gltf+clearcoat, gltf+sheen, "
                                           "gltf+clearcoat+sheen, gltf+anisotropy)"),
                std::string::npos)
          << e.what();
    }
  }
  EXPECT_EQ(parse_model_list("gltf,gltf-clearcoat,gltf+clearcoat,gltf+sheen").size(), 3u) << "an alias is its model";
  EXPECT_THROW(parse_model_list("gltf+shene"), UsageError);
}

// The two-lobe fit started from the one-lobe optimum (the exact nesting) ends no worse than it,
// on data with two lobes (much better) and with one (equal at worst).
TEST(TwoLobes, ErrorNeverAboveTheOneLobeFit) {
  FitOptions options;
  options.threads = 1;
  const Model& ggx = *find_model("ggx");
  const Model& ggx2 = *find_model("ggx+ggx");
  const std::vector<double> two = parameter_values(
      ggx2, {"albedo=0.1,0.2,0.3", "roughness=0.7", "f0=0.05", "roughness_2=0.25", "f0_2=0.5", "weight_2=1"});
  const std::vector<double> one = parameter_values(ggx, {"albedo=0.3", "roughness=0.4", "f0=0.5"});
  for (const auto& [name, data] : {std::pair{"two lobes", test::anisotropic_samples(ggx2, two, 1200, 0.002, 1)},
                                   std::pair{"one lobe", test::anisotropic_samples(ggx, one, 1200, 0.002, 2)}}) {
    for (const char* pair : {"ggx+ggx", "ggx+beckmann", "ggx+cook-torrance"}) {
      SCOPED_TRACE(std::string(name) + " " + pair);
      const Model& outer = *find_model(pair);
      const FitResult single = fit_model(ggx, data, options);
      FitOptions from_single = options;
      from_single.initial_values = embed_values(outer, outer.nestings()[0], ggx, single.values);
      const FitResult fit = fit_model(outer, data, from_single);
      ASSERT_TRUE(fit.ok) << fit.error;
      EXPECT_LE(fit.metrics.cosine, single.metrics.cosine * (1 + 1e-9));
      // Two lobes in the data, each with Schlick's F reaching 1 at grazing so that either lobe
      // can be the composite's first: ggx+ggx finds them (down to the 0.2 % noise), one cannot.
      if (std::string(name) == "two lobes" && std::string(pair) == "ggx+ggx") {
        const double truth = evaluate_metrics(outer, two, data).cosine;
        EXPECT_LT(fit.metrics.cosine, 1.01 * truth);
        EXPECT_GT(single.metrics.cosine, 3 * truth);
      }
    }
  }
}

// The values a `fit` command printed for its first-ranked model, by parameter name: the line of
// "name=value±stddev" fields, a colour's as "[r,g,b]".
std::map<std::string, std::vector<double>> printed_values(const std::string& output) {
  std::map<std::string, std::vector<double>> values;
  std::istringstream lines(output);
  std::string line;
  while (std::getline(lines, line) && line.find("albedo=") == std::string::npos) {
  }
  std::istringstream fields(line);
  std::string field;
  while (fields >> field) {
    const size_t equals = field.find('='), plus_minus = field.find("±");
    if (equals == std::string::npos) continue;
    std::string value = field.substr(equals + 1, plus_minus - equals - 1);
    if (value.front() == '[') value = value.substr(1, value.size() - 2);
    std::vector<double>& entries = values[field.substr(0, equals)];
    for (const std::vector<std::string>& row : test::csv_rows(value))
      for (const std::string& entry : row) entries.push_back(std::stod(entry));
  }
  return values;
}

// The command line: `models` says how to ask for pairs, `fit` fits one and prints what the
// library's fit finds (to the 4 significant digits it prints), which on noise-free data is the
// truth; an unsuitable pair is an error naming the component.
TEST(TwoLobes, CommandLine) {
  EXPECT_NE(test::run_cli("models").output.find("FIRST+SECOND"), std::string::npos);
  const std::filesystem::path dir = test::fresh_dir("two-lobes");
  const Model& ct2 = *find_model("cook-torrance+cook-torrance");
  const std::vector<double> truth =
      parameter_values(ct2, {"albedo=0.2", "specular=0.3", "m=0.4", "specular_2=0.2", "m_2=0.08"});
  const std::string csv = (dir / "two.csv").string();
  write_file_atomic(csv, format_csv_samples(test::anisotropic_samples(ct2, truth, 800, 0.0, 9)));
  const test::CommandResult fit = test::run_cli("fit " + csv + " --models cook-torrance+cook-torrance --threads 1");
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  const std::map<std::string, std::vector<double>> printed = printed_values(fit.output);
  ASSERT_EQ(printed.size(), ct2.parameters().size()) << fit.output;

  // The library's fit of the same file with the same options.
  FitOptions options;
  options.threads = 1;
  const FitResult library = fit_model(ct2, parse_csv_samples(test::slurp(csv), csv), options);
  ASSERT_TRUE(library.ok) << library.error;
  std::vector<double> flat;  // the printed values in the model's order
  for (const ParameterEstimate& p : library.parameters) {
    SCOPED_TRACE(p.name);
    ASSERT_TRUE(printed.count(p.name)) << fit.output;
    const std::vector<double>& shown = printed.at(p.name);
    ASSERT_EQ(shown.size(), p.value.size());
    for (size_t c = 0; c < shown.size(); ++c) EXPECT_NEAR(shown[c], p.value[c], 5e-4 * std::abs(p.value[c]) + 1e-12);
    flat.insert(flat.end(), shown.begin(), shown.end());
  }
  // Noise-free data: the truth, except that two lobes of one model may come out in either order
  // (the composite is symmetric in them; this fit puts the sharp lobe first).
  std::vector<double> swapped = truth;
  const int first = ct2.offset_of("specular"), second = ct2.offset_of("specular_2");
  std::swap_ranges(swapped.begin() + first, swapped.begin() + second, swapped.begin() + second);
  bool as_truth = true, as_swapped = true;
  for (size_t i = 0; i < flat.size(); ++i) {
    as_truth = as_truth && std::abs(flat[i] - truth[i]) <= 5e-4 * truth[i];
    as_swapped = as_swapped && std::abs(flat[i] - swapped[i]) <= 5e-4 * swapped[i];
  }
  EXPECT_TRUE(as_truth || as_swapped) << fit.output;

  test::expect_cli_errors({{"fit " + csv + " --models lambert+ggx", "lambert is not a specular lobe"},
                           {"fit " + csv + " --models ggx+nosuch", "FIRST+SECOND"}},
                          (dir / "none").string());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace brdffit
