// FitOptions::fixed (--fix, Python fix=): held parameters stay exactly at their values, are
// reported as fixed without a standard deviation, the others recover from generated data with
// the uncertainties of a fit of the others alone; bad names and values are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "batch_test_util.h"
#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/io.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"
#include "brdffit/result_json.h"
#include "test_util.h"

namespace brdffit {
namespace {

const ParameterEstimate& estimate(const FitResult& r, const std::string& name) {
  for (const ParameterEstimate& p : r.parameters)
    if (p.name == name) return p;
  throw std::runtime_error("no parameter " + name + " in the " + r.model + " result");
}

SampleSet gltf_table(const std::vector<std::string>& assignments) {
  const Model& gltf = *find_model("gltf");
  return test::model_table(gltf, parameter_values(gltf, assignments), 1500, 0.01, 3, 0.1);
}

TEST(FitFixed, HeldValueStaysExactlyAndTheOthersRecover) {
  const Model& gltf = *find_model("gltf");
  for (const double metallic : {0.0, 0.3}) {
    SCOPED_TRACE(metallic);
    const SampleSet data =
        gltf_table({"baseColor=0.6,0.3,0.2", "metallic=" + std::to_string(metallic), "roughness=0.4"});
    FitOptions options;
    options.fixed = {{"metallic", metallic}};
    const FitResult r = fit_model(gltf, data, options);
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(r.values[gltf.offset_of("metallic")], metallic);  // exactly
    const ParameterEstimate& m = estimate(r, "metallic");
    EXPECT_TRUE(m.fixed);
    EXPECT_FALSE(m.at_bound) << "a held value is not an optimum on a bound";
    ASSERT_EQ(m.stddev.size(), 1u);
    EXPECT_TRUE(std::isnan(m.stddev[0]));
    const ParameterEstimate& roughness = estimate(r, "roughness");
    EXPECT_FALSE(roughness.fixed);
    EXPECT_NEAR(roughness.value[0], 0.4, 0.01);
    EXPECT_GT(roughness.stddev[0], 0.0);
    const ParameterEstimate& base = estimate(r, "baseColor");
    EXPECT_NEAR(base.value[0], 0.6, 0.01);
    EXPECT_NEAR(base.value[2], 0.2, 0.01);
    // The warnings say nothing of the held value sitting on its bound.
    for (const std::string& w : r.warnings) EXPECT_EQ(w.find("metallic"), std::string::npos) << w;
    // The document says fixed, with no stddev.
    const nlohmann::json j = fit_result_json(r);
    EXPECT_EQ(j["parameters"]["metallic"]["fixed"], true);
    EXPECT_TRUE(j["parameters"]["metallic"]["stddev"].is_null());  // a scalar: null, not a number
    EXPECT_FALSE(j["parameters"]["roughness"].contains("fixed"));
  }
}

TEST(FitFixed, KnowingAParameterNarrowsTheOthers) {
  // The held fit's stddevs are those of the remaining parameters given the held one: no larger
  // than the free fit's marginal ones (the inverse of a sub-block of JᵀJ against the sub-block
  // of its inverse), at a nearly equal residual variance. A dielectric with a strong lobe, so
  // that metallic and the colour trade off in the free fit.
  const Model& gltf = *find_model("gltf");
  const SampleSet data = gltf_table({"baseColor=0.5,0.4,0.3", "metallic=0.2", "roughness=0.3"});
  const FitResult free_fit = fit_model(gltf, data, FitOptions{});
  FitOptions options;
  options.fixed = {{"metallic", 0.2}};
  const FitResult held = fit_model(gltf, data, options);
  ASSERT_TRUE(free_fit.ok && held.ok);
  for (const char* name : {"roughness", "baseColor"}) {
    SCOPED_TRACE(name);
    const ParameterEstimate &a = estimate(held, name), &b = estimate(free_fit, name);
    EXPECT_LT(a.stddev[0], b.stddev[0] * 1.02);
  }
  EXPECT_LT(estimate(held, "baseColor").stddev[0], 0.9 * estimate(free_fit, "baseColor").stddev[0])
      << "metallic and the base colour trade off: knowing one pins the other";
}

TEST(FitFixed, ModelsWithoutTheParameterAreFittedAsUsual) {
  const SampleSet data = gltf_table({"baseColor=0.6,0.3,0.2", "metallic=0", "roughness=0.4"});
  FitOptions options;
  options.fixed = {{"metallic", 0.0}};
  const std::vector<FitResult> results = fit_models({find_model("lambert"), find_model("gltf")}, data, options);
  ASSERT_EQ(results.size(), 2u);
  for (const ParameterEstimate& p : results[0].parameters) EXPECT_FALSE(p.fixed) << p.name;
  EXPECT_TRUE(estimate(results[1], "metallic").fixed);
}

TEST(FitFixed, RefusesUnknownNamesValuesOutsideTheBoundsAndRepeats) {
  const SampleSet data = gltf_table({"baseColor=0.6,0.3,0.2", "metallic=0", "roughness=0.4"});
  const std::vector<const Model*> models = {find_model("lambert"), find_model("gltf")};
  const auto message = [&](std::vector<std::pair<std::string, double>> fixed) {
    FitOptions options;
    options.fixed = std::move(fixed);
    try {
      fit_models(models, data, options);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message({{"metalic", 0.0}}),
            "--fix metalic: none of the models fitted (lambert, gltf) has a parameter metalic");
  EXPECT_EQ(message({{"metallic", 1.5}}), "--fix metallic=1.5: outside the gltf model's bounds [0, 1]");
  EXPECT_EQ(message({{"roughness", 0.5}, {"roughness", 0.4}}), "--fix: roughness is given twice");
}

TEST(FitFixed, CommandLineSaysFixed) {
  const std::string dir = test::fresh_dir("fit-fixed-cli");
  const std::string data =
      test::write_model_csv(dir + "/plastic.csv", "gltf", {"baseColor=0.6,0.3,0.2", "metallic=0", "roughness=0.4"});
  const auto run =
      test::run_cli("fit " + data + " -m gltf --fix metallic=0 --out " + dir + "/r.json --csv " + dir + "/r.csv");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("metallic=0 (fixed)"), std::string::npos) << run.output;
  const std::vector<std::vector<std::string>> rows = test::csv_rows(read_file(dir + "/r.csv"));
  ASSERT_EQ(rows.size(), 2u);
  const auto cell = [&](const std::string& column) {
    const auto at = std::find(rows[0].begin(), rows[0].end(), column);
    return at == rows[0].end() ? std::string("(no column)") : rows[1].at(at - rows[0].begin());
  };
  EXPECT_EQ(cell("metallic_fixed"), "1");
  EXPECT_EQ(cell("roughness_fixed"), "0");
  EXPECT_EQ(cell("metallic_stddev"), "");
  const nlohmann::json doc = nlohmann::json::parse(read_file(dir + "/r.json"));
  EXPECT_EQ(doc["fixed"]["metallic"], 0.0);
  EXPECT_EQ(doc["models"][0]["parameters"]["metallic"]["fixed"], true);
  test::expect_cli_errors({{"fit " + data + " -m gltf --fix metallic", "--fix: 'metallic' is not NAME=VALUE"},
                           {"fit " + data + " -m gltf --fix metallic=0,ior=x", "--fix: 'ior=x' is not NAME=VALUE"},
                           {"fit " + data + " -m gltf --fix ior=1.5 --out " + dir + "/bad.json",
                            "--fix ior: none of the models fitted (gltf) has a parameter ior"}},
                          dir + "/bad.json");
}

TEST(FitFixed, BatchHoldsTheValueAndResumesOnlyUnderTheSameHold) {
  const std::string dir = test::fresh_dir("fit-fixed-batch"), in = dir + "/in", out = dir + "/out";
  std::filesystem::create_directories(in);
  test::write_model_csv(in + "/plastic.csv", "gltf", {"baseColor=0.6,0.3,0.2", "metallic=0", "roughness=0.4"}, 800);
  const auto run = test::run_cli("batch " + in + " -m gltf --fix metallic=0 --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json doc = nlohmann::json::parse(read_file(out + "/plastic.json"));
  EXPECT_EQ(doc["fixed"]["metallic"], 0.0);
  EXPECT_EQ(doc["models"][0]["parameters"]["metallic"]["fixed"], true);
  EXPECT_EQ(doc["models"][0]["parameters"]["metallic"]["value"], 0.0);
  // --resume keeps the document under the same hold and fits again under another.
  const auto same = test::run_cli("batch " + in + " -m gltf --fix metallic=0 --out " + out + " --resume");
  ASSERT_EQ(same.exit_code, 0) << same.output;
  EXPECT_NE(same.output.find("plastic: already done"), std::string::npos) << same.output;
  const auto other = test::run_cli("batch " + in + " -m gltf --fix metallic=0.5 --out " + out + " --resume");
  ASSERT_EQ(other.exit_code, 0) << other.output;
  EXPECT_EQ(other.output.find("plastic: already done"), std::string::npos) << other.output;
  const nlohmann::json refitted = nlohmann::json::parse(read_file(out + "/plastic.json"));
  EXPECT_EQ(refitted["models"][0]["parameters"]["metallic"]["value"], 0.5);
}

}  // namespace
}  // namespace brdffit
