// The fit and score commands end to end: the result document, CSV, and bad input.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "brdffit/csv_samples.h"
#include "brdffit/io.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"
#include "test_util.h"

namespace brdffit {
namespace {

namespace fs = std::filesystem;

// A CSV of Ward samples at known parameters.
std::string ward_csv(const std::string& dir) {
  const Model& ward = *find_model("ward");
  const std::vector<double> values = parameter_values(ward, {"albedo=0.3,0.2,0.1", "specular=0.1", "alpha=0.15"});
  SampleSet set;
  std::mt19937_64 rng(5);
  for (int i = 0; i < 3000; ++i) {
    const Vec3 l = test::random_upper_direction(rng, 0.05), v = test::random_upper_direction(rng, 0.05);
    set.samples.push_back({l, v, ward.shade(values.data(), l, v), 1.0});
  }
  const std::string path = dir + "/ward.csv";
  write_file_atomic(path, format_csv_samples(set));
  return path;
}

TEST(FitCli, WritesTheResultDocumentAndCsv) {
  const std::string dir = test::fresh_dir("fit-cli"), data = ward_csv(dir);
  const auto r =
      test::run_cli("fit " + data + " --models ward,lambert --out " + dir + "/r.json --csv " + dir + "/r.csv");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("ranked by the cosine metric"), std::string::npos);
  const nlohmann::json doc = nlohmann::json::parse(read_file(dir + "/r.json"));
  EXPECT_EQ(doc["schema"], 1);
  EXPECT_EQ(doc["tool"], "brdffit " BRDFFIT_VERSION);
  EXPECT_EQ(doc["input"]["path"], data);
  EXPECT_EQ(doc["input"]["sha256"].get<std::string>().size(), 64u);
  EXPECT_EQ(doc["samples"], 3000);
  EXPECT_EQ(doc["metric"], "cosine");
  ASSERT_EQ(doc["models"].size(), 2u);
  const nlohmann::json& ward = doc["models"][0];
  EXPECT_EQ(ward["model"], "ward");
  EXPECT_EQ(ward["status"], "ok");
  EXPECT_TRUE(ward["error"].is_null());
  EXPECT_NEAR(ward["parameters"]["alpha"]["value"].get<double>(), 0.15, 1e-6);
  EXPECT_NEAR(ward["parameters"]["albedo"]["value"][1].get<double>(), 0.2, 1e-6);
  EXPECT_TRUE(ward["parameters"]["alpha"]["stddev"].is_number());
  for (const char* metric : {"cosine", "log", "relative", "l2", "max"})
    EXPECT_TRUE(ward["metrics"][metric].is_number());
  EXPECT_LT(ward["metrics"]["cosine"].get<double>(), 1e-6);
  EXPECT_GT(doc["models"][1]["metrics"]["cosine"].get<double>(), 1e-3);  // Lambert cannot fit Ward
  // The CSV: a column per parameter component, its stddev and two flags; lambert leaves
  // ward's own parameters empty.
  const std::vector<std::vector<std::string>> rows = test::csv_rows(read_file(dir + "/r.csv"));
  ASSERT_EQ(rows.size(), 3u);
  const std::vector<std::string>& header = rows[0];
  EXPECT_EQ(std::vector<std::string>(header.begin(), header.begin() + 14),
            (std::vector<std::string>{"model", "status", "verdict", "cosine", "log", "relative", "l2", "max", "typical",
                                      "iterations", "seconds", "albedo_r", "albedo_g", "albedo_b"}));
  auto cell = [&](size_t row, const std::string& column) {
    const auto at = std::find(header.begin(), header.end(), column);
    EXPECT_NE(at, header.end()) << column;
    return at == header.end() ? std::string() : rows[row].at(at - header.begin());
  };
  ASSERT_EQ(rows[1].size(), header.size());
  EXPECT_EQ(cell(1, "model"), "ward");
  EXPECT_NEAR(std::stod(cell(1, "alpha")), 0.15, 1e-6);
  EXPECT_NEAR(std::stod(cell(1, "albedo_g")), 0.2, 1e-6);
  EXPECT_GT(std::stod(cell(1, "alpha_stddev")), 0.0);
  EXPECT_EQ(cell(1, "alpha_identifiable"), "1");
  EXPECT_EQ(cell(1, "alpha_at_bound"), "0");
  // Every metric of the document is a column (metric.h's one table feeds both), to 9 digits.
  for (const auto& [metric, value] : ward["metrics"].items())
    EXPECT_NEAR(std::stod(cell(1, metric)), value.get<double>(), 1e-8 * std::max(1.0, value.get<double>())) << metric;
  EXPECT_EQ(cell(2, "model"), "lambert");
  EXPECT_EQ(cell(2, "alpha"), "");
  EXPECT_NEAR(std::stod(cell(2, "albedo_r")), doc["models"][1]["parameters"]["albedo"]["value"][0].get<double>(), 1e-8);

  // score agrees with the fitted metrics.
  const auto score = test::run_cli("score " + data +
                                   " -m ward --param albedo=0.3,0.2,0.1 --param specular=0.1 "
                                   "--param alpha=0.15 --json");
  ASSERT_EQ(score.exit_code, 0) << score.output;
  const nlohmann::json scored = nlohmann::json::parse(score.output)["metrics"];
  EXPECT_LT(scored["cosine"].get<double>(), 1e-12);
  // Every metric the document has: typical too, at the exact parameters the lowest bin of its
  // histogram (10^-6, metrics.cc), where every sample's relative error is 0.
  for (const auto& [metric, value] : ward["metrics"].items()) EXPECT_TRUE(scored.contains(metric)) << metric;
  EXPECT_EQ(scored.size(), ward["metrics"].size());
  EXPECT_LT(scored["typical"].get<double>(), 1.1e-6);
}

TEST(FitCli, BadInputExitsNonZeroWithAClearMessageAndWritesNothing) {
  const std::string dir = test::fresh_dir("fit-cli"), data = ward_csv(dir);
  write_file_atomic(dir + "/empty.csv", "lx,ly,lz,vx,vy,vz,r,g,b\n");
  const std::string out = dir + "/never.json";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"fit /nonexistent/table.binary --out " + out, "/nonexistent/table.binary: cannot open"},
      {"fit " + dir + "/empty.csv --out " + out, "empty.csv: no samples"},
      {"fit " + data + " --models ward,nosuch --out " + out, "unknown model 'nosuch'"},
      {"fit " + data + " --metric nosuch --out " + out, "unknown metric 'nosuch'"},
      {"fit " + data + " --loss nosuch --out " + out, "unknown loss 'nosuch'"},
      {"score " + data + " -m ward --param alpha=7", "alpha must lie in"},
  };
  for (const auto& [args, message] : cases) {
    SCOPED_TRACE(args);
    const auto r = test::run_cli(args);
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
  }
}

}  // namespace
}  // namespace brdffit
