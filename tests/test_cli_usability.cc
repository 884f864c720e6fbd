// The command line as a new user meets it (issue 26): usage errors exit 2 with a "did you mean",
// inputs of the wrong kind name the command that takes them, outputs are checked before any
// work, -q/-v, fit's default models, batch never drops a document's models, render's default -o.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "batch_test_util.h"
#include "brdffit/io.h"
#include "brdffit/names.h"
#include "test_util.h"

namespace brdffit {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using test::run_cli;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// How often `part` occurs in `text`.
size_t count_of_text(const std::string& text, const std::string& part) {
  size_t count = 0;
  for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + part.size())) ++count;
  return count;
}

// A small Lambert table: every fit on it takes milliseconds.
std::string small_table(const std::string& dir, const std::string& name = "t", const std::string& albedo = "0.5") {
  return test::write_model_csv(dir + "/" + name + ".csv", "lambert", {"albedo=" + albedo}, 200);
}

TEST(CliUsability, NamesAreMatchedFoldedAndWithinATypo) {
  const std::vector<std::string> known{"help", "fit", "ggx", "cook-torrance", "lambert", "oren-nayar"};
  EXPECT_EQ(folded_name("  Cook_Torrance "), "cook-torrance");
  EXPECT_EQ(closest_name("hlep", known), "help");  // a swap of neighbours is one edit
  EXPECT_EQ(closest_name("GGX", known), "ggx");
  EXPECT_EQ(closest_name("cook_torrance", known), "cook-torrance");
  EXPECT_EQ(closest_name(" lambert", known), "lambert");
  EXPECT_EQ(closest_name("orennayar", known), "oren-nayar");  // 1 edit in 10 characters
  EXPECT_EQ(closest_name("ggz", known), "ggx");
  // Beyond a typo (2 edits in a 3-letter name; 4 in 7): no suggestion rather than a wrong one.
  EXPECT_EQ(closest_name("gzz", known), "");
  EXPECT_EQ(closest_name("xyzzyab", known), "");
  EXPECT_EQ(did_you_mean("hlep", known), "; did you mean 'help'?");
  EXPECT_EQ(did_you_mean("", known), "");
}

TEST(CliUsability, UsageErrorsExitTwoWithTheNearestName) {
  const std::string dir = test::fresh_dir("usability-usage"), table = small_table(dir);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"hlep", "no command 'hlep'; did you mean 'help'?"},
      {"help fitt", "no command 'fitt'; did you mean 'fit'?"},
      {"fit " + table + " --no-such-option", "--no-such-option"},
      {"fit " + table + " --max-sample 5", "did you mean '--max-samples'?"},
      {"models --jsn", "did you mean '--json'?"},
      {"fit " + table + " --threads -5", "--threads"},
      {"fit " + table + " -m GGX", "unknown model 'GGX'; did you mean -m ggx?"},
      {"fit " + table + " -m cook_torrance", "unknown model 'cook_torrance'; did you mean -m cook-torrance?"},
      {"fit " + table + " -m 'ggx, lambert'", "unknown model ' lambert'; did you mean -m ggx,lambert?"},
      {"fit " + table + " -m GGX+ggx", "did you mean -m ggx+ggx?"},
      {"fit " + table + " --metric cosin", "unknown metric 'cosin'; did you mean 'cosine'?"},
      {"fit " + table + " --loss hubber", "unknown loss 'hubber'; did you mean 'huber'?"},
      {"fit " + table + " --fix roughness", "--fix: 'roughness' is not NAME=VALUE"},
      {"eval -m Lambert --light 0,0,1 --view 0,0,1", "did you mean -m lambert?"},
      {"eval -m ggx --param roughnes=0.2 --light 0,0,1 --view 0,0,1", "has no parameter 'roughnes'"},
      {"eval -m ggx --light 0,0 --view 0,0,1", "--light"},
      {"score " + table + " -m ward,lambert", "-m takes one model here"},
      {"bake -m all -o " + dir + "/x.binary", "-m takes one model here, not 'all'"},
  };
  for (const auto& [arguments, message] : cases) {
    const CommandResult r = run_cli(arguments);
    EXPECT_EQ(r.exit_code, 2) << arguments << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, message)) << arguments << "\n" << r.output;
  }
  // A name too far from every model gets no suggestion, only the list.
  const CommandResult far = run_cli("fit " + table + " -m qqqqqqq");
  EXPECT_EQ(far.exit_code, 2);
  EXPECT_FALSE(contains(far.output, "did you mean")) << far.output;
  EXPECT_TRUE(contains(far.output, "known: lambert")) << far.output;
  // Not usage errors: a missing input and an unreadable one exit 1.
  EXPECT_EQ(run_cli("fit " + dir + "/missing.csv -m lambert").exit_code, 1);
  test::write_text(dir + "/broken.csv", "lx,ly,lz,vx,vy,vz,r,g,b\n0,0,1,0,0,1,nan,0,0\n");
  EXPECT_EQ(run_cli("fit " + dir + "/broken.csv -m lambert").exit_code, 1);
  // Every --help ends with the exit statuses.
  for (const char* command : {"help fit", "help batch", "fit --help", "render --help"}) {
    const CommandResult help = run_cli(command);
    EXPECT_EQ(help.exit_code, 0) << command;
    EXPECT_TRUE(contains(help.output, "Exit status: 0 done; 1 ")) << command << "\n" << help.output;
    EXPECT_TRUE(contains(help.output, "2 the command line is wrong")) << command;
  }
}

TEST(CliUsability, AnInputOfTheWrongKindNamesTheCommandThatTakesIt) {
  const std::string dir = test::fresh_dir("usability-kinds"), table = small_table(dir);
  test::write_text(dir + "/photo.png", "not really a png");
  CommandResult r = run_cli("fit " + dir + "/photo.png");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, dir + "/photo.png: a photograph")) << r.output;
  EXPECT_TRUE(contains(r.output, "`brdffit sphere " + dir + "/photo.png --lights FILE`")) << r.output;

  r = run_cli("fit " + dir);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, dir + ": a folder; fit takes one measured table (`brdffit batch " + dir + "`"))
      << r.output;

  ASSERT_EQ(run_cli("fit " + table + " -m lambert -o " + dir + "/r.json").exit_code, 0);
  r = run_cli("fit " + dir + "/r.json");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, dir + "/r.json: a result document, not a measured table")) << r.output;

  // A table where result documents belong: said so, not a JSON parser's message.
  for (const std::string& command : {"report " + table + " -o " + dir + "/page.html", "compare " + table,
                                     "export " + table + " -o " + dir + "/m.gltf"}) {
    r = run_cli(command);
    EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, table + ": a measured table, not a result document; `brdffit fit " + table))
        << command << "\n"
        << r.output;
    EXPECT_FALSE(contains(r.output, "parse error")) << r.output;
  }
  EXPECT_FALSE(fs::exists(dir + "/page.html"));
}

TEST(CliUsability, EveryOutputIsCheckedBeforeAnyWork) {
  const std::string dir = test::fresh_dir("usability-outputs"), table = small_table(dir);
  test::write_text(dir + "/file.txt", "a file, not a folder\n");
  const std::string missing = dir + "/nodir/out.json";
  CommandResult r = run_cli("fit " + table + " -m lambert -o " + missing);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(contains(r.output, missing + ": cannot write: the folder " + dir + "/nodir does not exist")) << r.output;
  EXPECT_FALSE(contains(r.output, "samples")) << "the table was read before the output was checked:\n" << r.output;

  r = run_cli("fit " + table + " -m lambert --csv " + dir + "/file.txt/fit.csv");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(contains(r.output, dir + "/file.txt/fit.csv: cannot write: " + dir + "/file.txt is a file, not a folder"))
      << r.output;
  EXPECT_FALSE(contains(r.output, "rank")) << r.output;

  const std::vector<std::pair<std::string, std::string>> cases = {
      {"bake -m ggx -o " + dir + "/nodir/ggx.binary", dir + "/nodir/ggx.binary: cannot write"},
      {"render " + table + " -o " + dir + "/nodir/t.png", dir + "/nodir/t.png: cannot write"},
      {"batch " + table + " -m lambert -o " + dir + "/file.txt", dir + "/file.txt: cannot write results into it"},
      {"batch " + table + " -m lambert -o " + dir + "/file.txt/sub", dir + "/file.txt is a file, not a folder"},
  };
  for (const auto& [arguments, message] : cases) {
    r = run_cli(arguments);
    EXPECT_EQ(r.exit_code, 1) << arguments << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, message)) << arguments << "\n" << r.output;
  }
  EXPECT_FALSE(fs::exists(dir + "/nodir"));
  // A batch makes its output folder with its parents.
  r = run_cli("batch " + table + " -m lambert -o " + dir + "/new/deeper");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir + "/new/deeper/t.json"));
  // Writing through /dev/null (a device, not a folder to create in) stays allowed.
  EXPECT_EQ(run_cli("fit " + table + " -m lambert --csv /dev/null").exit_code, 0);
}

TEST(CliUsability, QuietPrintsTheResultsOnlyAndVerboseEveryStage) {
  const std::string dir = test::fresh_dir("usability-verbosity"), table = small_table(dir);
  const CommandResult normal = run_cli("fit " + table + " -m lambert");
  ASSERT_EQ(normal.exit_code, 0) << normal.output;
  EXPECT_TRUE(contains(normal.output, table + ": 200 samples")) << normal.output;

  const CommandResult quiet = run_cli("fit " + table + " -m lambert -q");
  ASSERT_EQ(quiet.exit_code, 0) << quiet.output;
  EXPECT_FALSE(contains(quiet.output, "samples")) << quiet.output;
  EXPECT_TRUE(contains(quiet.output, "ranked by the cosine metric")) << quiet.output;

  const CommandResult verbose = run_cli("fit " + table + " -m lambert,ggx --verbose");
  ASSERT_EQ(verbose.exit_code, 0) << verbose.output;
  for (const std::string& stage :
       std::vector<std::string>{"brdffit: reading " + table, "brdffit: fitting 2 models to 200 samples",
                                "brdffit: [1/2] fitting lambert", "brdffit: [2/2] fitting ggx"})
    EXPECT_TRUE(contains(verbose.output, stage)) << stage << "\n" << verbose.output;

  const CommandResult both = run_cli("fit " + table + " -q -v");
  EXPECT_EQ(both.exit_code, 2) << both.output;

  // batch -q: the closing line only; no plan, no line per material.
  const CommandResult batch = run_cli("batch " + table + " -m lambert -q -o " + dir + "/out");
  ASSERT_EQ(batch.exit_code, 0) << batch.output;
  EXPECT_FALSE(contains(batch.output, "[1/1]")) << batch.output;
  EXPECT_FALSE(contains(batch.output, "at a time")) << batch.output;
  EXPECT_TRUE(contains(batch.output, "batch: 1 material in")) << batch.output;
  // Every other command takes them too.
  for (const char* command : {"models -q", "info -v " BRDFFIT_SOURCE_DIR "/data/cc_ibiza_sunset_rgb.bsdf"})
    EXPECT_EQ(run_cli(command).exit_code, 0) << command;
}

TEST(CliUsability, BatchPrintsARepeatedWarningOnceWithItsCount) {
  const std::string dir = test::fresh_dir("usability-warnings"), in = dir + "/in";
  fs::create_directories(in);
  // Ward fitted to Lambert data: its specular lobe has nothing to fit and sits at a bound, on
  // every material alike.
  for (const auto& [name, albedo] : {std::pair{"a", "0.2"}, {"b", "0.4"}, {"c", "0.6"}, {"d", "0.3"}})
    small_table(in, name, albedo);
  const CommandResult r = run_cli("batch " + in + " -m ward --threads 1 -o " + dir + "/out");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json a = nlohmann::json::parse(test::slurp(dir + "/out/a.json"));
  ASSERT_FALSE(a["models"][0]["warnings"].empty()) << a.dump(2);
  const std::string first = a["models"][0]["warnings"][0];
  // Its first line, once, with the count of the three others; the documents keep every one.
  EXPECT_EQ(count_of_text(r.output, "warning: "), a["models"][0]["warnings"].size()) << r.output;
  EXPECT_TRUE(contains(r.output, "    a ward: warning: " + first + " (and 3 more like it)")) << r.output;
  const CommandResult verbose = run_cli("batch " + in + " -m ward --threads 1 -v -o " + dir + "/out2");
  ASSERT_EQ(verbose.exit_code, 0) << verbose.output;
  EXPECT_EQ(count_of_text(verbose.output, "warning: "), 4 * a["models"][0]["warnings"].size()) << verbose.output;
  EXPECT_FALSE(contains(verbose.output, "more like it")) << verbose.output;
}

TEST(CliUsability, FitWithoutModelsFitsTheDefaultSet) {
  const std::string dir = test::fresh_dir("usability-default"), table = small_table(dir);
  const CommandResult r = run_cli("fit " + table + " --max-samples 100 --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::vector<std::string> models;
  const nlohmann::json document = nlohmann::json::parse(r.output);
  for (const nlohmann::json& m : document["models"]) models.push_back(m["model"]);
  EXPECT_EQ(models, (std::vector<std::string>{"lambert", "oren-nayar", "ggx", "cook-torrance", "ward", "gltf"}));
  const CommandResult help = run_cli("help fit");
  EXPECT_TRUE(contains(help.output, "or 'all' (every model")) << help.output;
  EXPECT_TRUE(contains(help.output, "lambert,oren-nayar,ggx,cook-torrance,ward,gltf")) << help.output;
}

TEST(CliUsability, BatchNeverReplacesADocumentsModelsWithFewer) {
  const std::string dir = test::fresh_dir("usability-batch-models"), table = small_table(dir), out = dir + "/out";
  ASSERT_EQ(run_cli("batch " + table + " -m lambert,ward --threads 1 -o " + out).exit_code, 0);
  const std::string before = test::slurp(out + "/t.json");
  const CommandResult fewer = run_cli("batch " + table + " -m lambert --threads 1 -o " + out);
  EXPECT_EQ(fewer.exit_code, 2) << fewer.output;
  EXPECT_TRUE(contains(fewer.output, "1 result document hold fits of models this batch does not fit")) << fewer.output;
  EXPECT_TRUE(contains(fewer.output, "t.json (ward)")) << fewer.output;
  EXPECT_TRUE(contains(fewer.output, "Fit those models too (-m lambert,ward)")) << fewer.output;
  EXPECT_EQ(test::slurp(out + "/t.json"), before);
  // --resume keeps a complete document as it is: nothing dropped, nothing refused.
  const CommandResult resumed = run_cli("batch " + table + " -m lambert --resume --threads 1 -o " + out);
  EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(test::slurp(out + "/t.json"), before);
  // The same models and more: refitted, nothing lost.
  const CommandResult more = run_cli("batch " + table + " -m lambert,ward,ggx --threads 1 -o " + out);
  EXPECT_EQ(more.exit_code, 0) << more.output;
  EXPECT_EQ(nlohmann::json::parse(test::slurp(out + "/t.json"))["models"].size(), 3u);
}

TEST(CliUsability, RenderWithoutOutWritesBesideTheInput) {
  const std::string dir = test::fresh_dir("usability-render"), table = small_table(dir);
  ASSERT_EQ(run_cli("fit " + table + " -m lambert,ggx -o " + dir + "/r.json").exit_code, 0);
  const CommandResult r = run_cli("render " + dir + "/r.json -m ggx --size 16");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "wrote " + dir + "/r-ggx.png (ggx fitted to")) << r.output;
  EXPECT_TRUE(fs::is_regular_file(dir + "/r-ggx.png"));
  const CommandResult help = run_cli("help render");
  EXPECT_TRUE(contains(help.output, "default: beside the input")) << help.output;
  const CommandResult unknown = run_cli("render " + dir + "/r.json -m GGX --size 16");
  EXPECT_EQ(unknown.exit_code, 2) << unknown.output;
  EXPECT_TRUE(contains(unknown.output, "did you mean -m ggx?")) << unknown.output;
  const CommandResult absent = run_cli("render " + dir + "/r.json -m ward --size 16");
  EXPECT_EQ(absent.exit_code, 2) << absent.output;
  EXPECT_TRUE(contains(absent.output, "has no ward result (it has lambert, ggx)")) << absent.output;
}

}  // namespace
}  // namespace brdffit
