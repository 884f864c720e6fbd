// The command line's common conventions: `help COMMAND`, one error prefix, -m/-o everywhere,
// old spellings that still work with a note, and --json documents on stdout.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "brdffit/csv_samples.h"
#include "brdffit/io.h"
#include "brdffit/metric.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"
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

// The user's documentation: the README and every file under docs/ it leads to.
std::vector<std::string> documentation_files() {
  std::vector<std::string> files = {std::string(BRDFFIT_SOURCE_DIR) + "/README.md"};
  for (const fs::directory_entry& entry : fs::directory_iterator(std::string(BRDFFIT_SOURCE_DIR) + "/docs"))
    if (entry.path().extension() == ".md") files.push_back(entry.path().string());
  std::sort(files.begin() + 1, files.end());
  return files;
}

// The code in a Markdown text: each line of a fenced block, and each inline code span (its line
// breaks as spaces, for a span that wraps).
std::vector<std::string> code_texts(const std::string& markdown) {
  std::vector<std::string> code;
  std::string prose;
  bool fenced = false;
  for (size_t start = 0; start < markdown.size();) {
    const size_t end = std::min(markdown.find('\n', start), markdown.size());
    const std::string line = markdown.substr(start, end - start);
    start = end + 1;
    if (line.rfind("```", 0) == 0)
      fenced = !fenced;
    else if (fenced)
      code.push_back(line);
    else
      prose += line + " ";
  }
  for (size_t open = prose.find('`'); open != std::string::npos;) {
    const size_t close = prose.find('`', open + 1);
    if (close == std::string::npos) break;
    code.push_back(prose.substr(open + 1, close - open - 1));
    open = prose.find('`', close + 1);
  }
  return code;
}

// A brdffit command line the documentation shows: the command and the options given to it.
struct DocumentedCommand {
  std::string where, command;
  std::vector<std::string> options;  // "--models", "-m", ...
};

// Every `brdffit COMMAND ...` in a piece of code (also `./build/apps/brdffit COMMAND`, or after
// `mpirun ... `), up to the end of the line or quote, a comment or another command.
std::vector<DocumentedCommand> documented_commands(const std::string& code, const std::string& file) {
  std::vector<DocumentedCommand> commands;
  const std::string program = "brdffit ";
  for (size_t at = code.find(program); at != std::string::npos; at = code.find(program, at + 1)) {
    if (at > 0 && std::isalnum(static_cast<unsigned char>(code[at - 1]))) continue;
    // In a fenced block a backquote closes a command quoted in a comment ("# `brdffit fit --out`").
    const size_t from = at + program.size(), tick = code.find('`', from);
    std::istringstream words(code.substr(from, tick == std::string::npos ? std::string::npos : tick - from));
    DocumentedCommand command{file + ": " + code, "", {}};
    if (!(words >> command.command) || !std::islower(static_cast<unsigned char>(command.command[0]))) continue;
    for (std::string word; words >> word;) {
      if (word == "#" || word == "|" || word == ";" || word == "&&" || word == "brdffit") break;
      const size_t begin = word.find_first_not_of("[(");
      if (begin == std::string::npos || word[begin] != '-' || word.size() < begin + 2 ||
          !(std::isalpha(static_cast<unsigned char>(word[begin + 1])) || word[begin + 1] == '-'))
        continue;  // a value, a path or a negative number
      const size_t name_end = word.find_first_of("=]),", begin);
      command.options.push_back(
          word.substr(begin, name_end == std::string::npos ? std::string::npos : name_end - begin));
    }
    commands.push_back(command);
  }
  return commands;
}

// Whether a command's help lists this option ("-m,--models TEXT", "  -o,--out", "  --force").
bool help_lists(const std::string& help, const std::string& option) {
  for (size_t at = help.find(option); at != std::string::npos; at = help.find(option, at + 1)) {
    const char before = at > 0 ? help[at - 1] : ' ',
               after = at + option.size() < help.size() ? help[at + option.size()] : ' ';
    if ((before == ' ' || before == ',') && !std::isalnum(static_cast<unsigned char>(after)) && after != '-' &&
        after != '_')
      return true;
  }
  return false;
}

// The README and docs/ show brdffit command lines; each command is one brdffit has, and each
// option one its help lists, so what people copy works. Misspellings the documentation shows on
// purpose (the near misses it says are refused) must be refused.
TEST(CliConsistency, EveryDocumentedCommandAndOptionExists) {
  const std::set<std::string> shown_as_refused = {"hlep"};
  std::map<std::string, test::CommandResult> helps;
  std::set<std::string> documented;
  size_t lines = 0, options = 0;
  for (const std::string& file : documentation_files())
    for (const std::string& code : code_texts(read_file(file)))
      for (const DocumentedCommand& command : documented_commands(code, fs::path(file).filename().string())) {
        SCOPED_TRACE(command.where);
        ++lines;
        if (shown_as_refused.count(command.command)) {
          const test::CommandResult refused = test::run_cli(command.command);
          EXPECT_EQ(refused.exit_code, 2) << refused.output;
          EXPECT_NE(refused.output.find("did you mean"), std::string::npos) << refused.output;
          continue;
        }
        documented.insert(command.command);
        if (!helps.count(command.command)) helps[command.command] = test::run_cli("help " + command.command);
        const test::CommandResult& help = helps[command.command];
        ASSERT_EQ(help.exit_code, 0) << "no command '" << command.command << "'\n" << help.output;
        for (const std::string& option : command.options) {
          ++options;
          EXPECT_TRUE(help_lists(help.output, option)) << command.command << " has no option " << option << "\n"
                                                       << help.output;
        }
      }
  // The documentation shows every command at least once, with many options.
  const test::CommandResult usage = test::run_cli("--help");
  ASSERT_EQ(usage.exit_code, 0) << usage.output;
  for (const char* command : {"fit", "score", "models", "eval", "info", "lookup", "bake", "sphere", "capture", "batch",
                              "compare", "report", "render", "export", "help"}) {
    EXPECT_TRUE(help_lists(usage.output, command)) << command << "\n" << usage.output;
    EXPECT_TRUE(documented.count(command)) << "the documentation never shows `brdffit " << command << "`";
  }
  EXPECT_GE(lines, 50u);  // 53 command lines with 74 options when this was written
  EXPECT_GE(options, 70u);
}

// The README documents what the command line does: its metric list is what --metric accepts, it
// opens with the two commands, and it leads to every file under docs/; no documentation file
// names anything outside the repository, and every link in them leads to a file that exists.
TEST(CliConsistency, ReadmeMatchesTheCommandLine) {
  const std::string readme = read_file(std::string(BRDFFIT_SOURCE_DIR) + "/README.md");
  EXPECT_EQ(readme.rfind("# brdffit\n\n```sh\nbash scripts/demo.sh", 0), 0u);
  EXPECT_NE(readme.find("\nbash scripts/test.sh "), std::string::npos);
  const size_t metrics = readme.find("**Error metrics.**");
  ASSERT_NE(metrics, std::string::npos);
  std::string paragraph = readme.substr(metrics, readme.find("\n\n", metrics) - metrics);
  std::replace(paragraph.begin(), paragraph.end(), '\n', ' ');
  // Every metric of the table (metric.h), the ones only reported too, with its meaning.
  for (const MetricInfo& info : kMetrics)
    EXPECT_NE(paragraph.find(std::string("`") + info.name + "` (" + info.meaning + ")"), std::string::npos)
        << info.name;
  EXPECT_FALSE(parse_metric("max"));  // reported, not minimised: the README says so
  const test::CommandResult help = test::run_cli("help fit");
  EXPECT_NE(help.output.find("cosine, log, relative, l2"), std::string::npos) << help.output;

  const std::vector<std::string> files = documentation_files();
  ASSERT_GE(files.size(), 8u);  // the README, reference, library, cluster, testing, benchmarks, data, ...
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    const std::string text = read_file(file);
    if (file != files.front())
      EXPECT_NE(readme.find("](docs/" + fs::path(file).filename().string() + ")"), std::string::npos)
          << "the README does not lead to it";
    for (const char* outside : {"../shared", "seed 0"}) EXPECT_EQ(text.find(outside), std::string::npos) << outside;
    for (size_t at = text.find("]("); at != std::string::npos; at = text.find("](", at + 1)) {
      const std::string target = text.substr(at + 2, text.find_first_of(")#", at + 2) - at - 2);
      if (target.rfind("http", 0) == 0) continue;
      EXPECT_TRUE(fs::exists(fs::path(file).parent_path() / target)) << target;
    }
  }
}

}  // namespace
}  // namespace brdffit
