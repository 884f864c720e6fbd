// The command line's common conventions: `help COMMAND`, one error prefix, -m/-o everywhere,
// old spellings that still work with a note, and --json documents on stdout.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "brdffit/csv_samples.h"
#include "brdffit/io.h"
#include "brdffit/metric.h"
#include "brdffit/model.h"
#include "test_util.h"

namespace brdffit {
namespace {

namespace fs = std::filesystem;

// A small Ward table (CSV) in a fresh folder.
std::string ward_table(const std::string& dir) {
  const Model& ward = *find_model("ward");
  const SampleSet set = test::model_table(
      ward, parameter_values(ward, {"albedo=0.3,0.2,0.1", "specular=0.1", "alpha=0.15"}), 1500, 0.0, 5, 0.05);
  const std::string path = dir + "/ward.csv";
  write_file_atomic(path, format_csv_samples(set));
  return path;
}

TEST(CliConsistency, HelpShowsACommandsOptionsWithTheirDefaults) {
  const auto fit = test::run_cli("help fit");
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  EXPECT_NE(fit.output.find("Usage: brdffit fit"), std::string::npos) << fit.output;
  EXPECT_NE(fit.output.find("-m,--models TEXT=lambert,oren-nayar,ggx,cook-torrance,ward,gltf"), std::string::npos)
      << fit.output;
  EXPECT_NE(fit.output.find("--metric TEXT=cosine"), std::string::npos) << fit.output;
  EXPECT_NE(fit.output.find("-o,--out"), std::string::npos) << fit.output;
  const auto batch = test::run_cli("help batch");
  EXPECT_NE(batch.output.find("-j,--jobs"), std::string::npos) << batch.output;
  // An image command's help comes from brdffit-imaging.
  const auto sphere = test::run_cli("help sphere");
  ASSERT_EQ(sphere.exit_code, 0) << sphere.output;
  EXPECT_NE(sphere.output.find("--chrome"), std::string::npos) << sphere.output;
  // Where sphere's defaults differ from fit's and batch's, its help says why.
  for (const char* option : {"--loss TEXT=huber", "--max-samples", "--max-angle"}) {
    const size_t at = sphere.output.find(option);
    ASSERT_NE(at, std::string::npos) << option;
    EXPECT_NE(sphere.output.substr(at, sphere.output.find("\n  -", at + 1) - at).find("unlike fit and batch"),
              std::string::npos)
        << option;
  }
  const auto unknown = test::run_cli("help nope");
  EXPECT_EQ(unknown.exit_code, 2);  // a usage error
  EXPECT_NE(unknown.output.find("brdffit: error: no command 'nope'"), std::string::npos) << unknown.output;
}

TEST(CliConsistency, ParseErrorsCarryTheSamePrefixAsEveryOtherError) {
  for (const std::string& arguments : {"fit", "fit x.csv --metric", "eval -m ggx --view 0,0,1", "batch --jobs 0 x"}) {
    const auto r = test::run_cli(arguments);
    EXPECT_NE(r.exit_code, 0) << arguments;
    EXPECT_EQ(r.output.rfind("brdffit: error: ", 0), 0u) << arguments << "\n" << r.output;
  }
}

TEST(CliConsistency, OldSpellingsWorkWithANote) {
  const std::string dir = test::fresh_dir("cli-old"), data = ward_table(dir);
  const std::string directions = " --light 0.3,0,1 --view -0.3,0,1";
  const auto now = test::run_cli("eval -m ggx" + directions);
  const auto positional = test::run_cli("eval ggx" + directions);
  ASSERT_EQ(now.exit_code, 0) << now.output;
  ASSERT_EQ(positional.exit_code, 0) << positional.output;
  EXPECT_NE(positional.output.find("brdffit: note: 'brdffit eval ggx' is deprecated; use 'brdffit eval -m ggx'"),
            std::string::npos)
      << positional.output;
  EXPECT_NE(positional.output.find(now.output), std::string::npos);  // the same values

  const std::string params = " --param albedo=0.3,0.2,0.1 --param specular=0.1 --param alpha=0.15";
  const auto old_score = test::run_cli("score " + data + " --model ward" + params);
  ASSERT_EQ(old_score.exit_code, 0) << old_score.output;
  EXPECT_NE(old_score.output.find("brdffit: note: --model is deprecated; use -m/--models"), std::string::npos);
  const auto two = test::run_cli("score " + data + " -m ward,lambert" + params);
  EXPECT_EQ(two.exit_code, 2);
  EXPECT_NE(two.output.find("score: -m takes one model here, not 'ward,lambert'"), std::string::npos) << two.output;
}

TEST(CliConsistency, JsonOnStdoutIsTheDocumentOutWrites) {
  const std::string dir = test::fresh_dir("cli-json"), data = ward_table(dir);
  const auto fit = test::run_cli("fit " + data + " -m ward,lambert --threads 1 --json -o " + dir + "/r.json");
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  const nlohmann::json printed = nlohmann::json::parse(fit.output);  // nothing else on stdout or stderr
  const nlohmann::json written = nlohmann::json::parse(read_file(dir + "/r.json"));
  ASSERT_EQ(printed["models"].size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(printed["models"][i]["model"], written["models"][i]["model"]);
    EXPECT_EQ(printed["models"][i]["parameters"], written["models"][i]["parameters"]);
  }

  const auto compare = test::run_cli("compare " + dir + "/r.json --json");
  ASSERT_EQ(compare.exit_code, 0) << compare.output;
  const nlohmann::json comparison = nlohmann::json::parse(compare.output);
  EXPECT_EQ(comparison["metric"], "cosine");
  ASSERT_EQ(comparison["materials"].size(), 1u);
  EXPECT_EQ(comparison["materials"][0]["models"][0]["model"], "ward");  // ward made the table
  EXPECT_EQ(comparison["materials"][0]["models"][0]["rank"], 1);
  EXPECT_EQ(comparison["models"][0]["wins"], 1);
  fs::remove_all(dir);
}

// The README documents what the command line does: its metric list is what --metric accepts, it
// opens with the two commands, and it names nothing outside the repository.
TEST(CliConsistency, ReadmeMatchesTheCommandLine) {
  const std::string readme = read_file(std::string(BRDFFIT_SOURCE_DIR) + "/README.md");
  EXPECT_EQ(readme.rfind("# brdffit\n\n```sh\nbash scripts/demo.sh", 0), 0u);
  const size_t metrics = readme.find("**Error metrics.**");
  ASSERT_NE(metrics, std::string::npos);
  const std::string paragraph = readme.substr(metrics, readme.find("\n\n", metrics) - metrics);
  for (Metric metric : {Metric::Cosine, Metric::Log, Metric::Relative, Metric::L2}) {
    EXPECT_NE(paragraph.find(std::string("`") + metric_name(metric) + "` ("), std::string::npos) << metric_name(metric);
    EXPECT_TRUE(parse_metric(metric_name(metric)));
  }
  EXPECT_FALSE(parse_metric("max"));  // reported, not minimised: the README says so
  EXPECT_NE(paragraph.find("`max`"), std::string::npos);
  const test::CommandResult help = test::run_cli("help fit");
  EXPECT_NE(help.output.find("cosine, log, relative, l2"), std::string::npos) << help.output;
  for (const char* outside : {"../shared", "seed 0"}) EXPECT_EQ(readme.find(outside), std::string::npos) << outside;
}

}  // namespace
}  // namespace brdffit
