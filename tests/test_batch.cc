// batch: which files inputs name, one document per material, failures recorded, --resume, summaries.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "batch_test_util.h"
#include "brdffit/batch.h"
#include "brdffit/error.h"

namespace brdffit {
namespace {

namespace fs = std::filesystem;

using test::names;

TEST(BatchMaterials, FoldersManifestsAndFiles) {
  const std::string dir = test::fresh_dir("batch-inputs");
  fs::create_directories(dir + "/tables/sub");
  fs::create_directories(dir + "/tables/out");
  for (const char* file : {"/tables/b.csv", "/tables/a.binary", "/tables/sub/c.bsdf", "/tables/out/summary.csv",
                           "/tables/notes.txt", "/other/a.csv", "/summary.csv"}) {
    fs::create_directories(fs::path(dir + file).parent_path());
    write_file_atomic(dir + file, "x");
  }
  // A folder: tables only, recursively and sorted, nothing under the output folder.
  const auto in_folder = batch_materials({dir + "/tables"}, dir + "/tables/out");
  EXPECT_EQ(names(in_folder), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(in_folder[0].path, dir + "/tables/a.binary");

  // A manifest: paths relative to it, comments and blank lines skipped, entries that do not exist
  // kept (they fail when fitted); the same file twice counts once; equal names get -2; the name
  // "summary" is the batch's own.
  write_file_atomic(dir + "/list.txt", "# materials\ntables/b.csv\n\n  other/a.csv  \nmissing.binary\n" + dir +
                                           "/tables/b.csv\nsummary.csv\n");
  const auto listed = batch_materials({dir + "/list.txt", dir + "/tables/a.binary"});
  EXPECT_EQ(names(listed), (std::vector<std::string>{"b", "a", "missing", "summary-2", "a-2"}));
  EXPECT_EQ(listed[2].path, dir + "/missing.binary");

  const auto fails = [](const std::vector<std::string>& inputs, const std::string& message) {
    try {
      batch_materials(inputs);
      ADD_FAILURE() << "no error for " << inputs[0];
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  };
  fails({dir + "/nothing-here"}, "nothing-here: no such file or folder");
  fs::create_directories(dir + "/empty");
  fails({dir + "/empty"}, "empty: no tables (.binary, .bsdf, .csv) in this folder");
  write_file_atomic(dir + "/blank.txt", "# nothing\n\n");
  fails({dir + "/blank.txt"}, "blank.txt: the manifest lists no tables");
}

// Two materials that fit and one that cannot be read.
std::string write_batch_inputs(const std::string& dir) {
  fs::create_directories(dir + "/in");
  test::write_model_csv(dir + "/in/red.csv", "ward", {"albedo=0.5,0.1,0.1", "specular=0.08", "alpha=0.2"}, 2000, 1);
  test::write_model_csv(dir + "/in/blue.csv", "lambert", {"albedo=0.1,0.2,0.6"}, 2000, 2);
  write_file_atomic(dir + "/in/broken.csv", "lx,ly,lz,vx,vy,vz,r,g,b\n0,0,1,0,0,1,not-a-number,1,1\n");
  return dir + "/in";
}

TEST(BatchCli, FitsEveryMaterialRecordsTheFailureAndSummarises) {
  const std::string dir = test::fresh_dir("batch-run"), in = write_batch_inputs(dir), out = dir + "/out";
  const auto r = test::run_cli("batch " + in + " --models ward,lambert --jobs 2 --out " + out);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("broken: FAILED: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("1 of 3 materials failed"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("[3/3]"), std::string::npos) << r.output;

  // One document per material that could be read, in fit's schema, plus the material's name.
  const nlohmann::json red = nlohmann::json::parse(read_file(out + "/red.json"));
  EXPECT_EQ(red["schema"], 1);
  EXPECT_EQ(red["material"], "red");
  EXPECT_EQ(red["input"]["path"], in + "/red.csv");
  ASSERT_EQ(red["models"].size(), 2u);
  EXPECT_EQ(red["models"][0]["model"], "ward");
  EXPECT_NEAR(red["models"][0]["parameters"]["alpha"]["value"].get<double>(), 0.2, 1e-5);
  // Read back, parameters come in the model's order (JSON keeps them sorted by name).
  const FitDocument red_document = read_fit_document(out + "/red.json");
  std::vector<std::string> names;
  for (const ParameterEstimate& p : red_document.results[0].parameters) names.push_back(p.name);
  EXPECT_EQ(names, (std::vector<std::string>{"albedo", "specular", "alpha"}));
  EXPECT_TRUE(fs::exists(out + "/blue.json"));
  EXPECT_FALSE(fs::exists(out + "/broken.json"));

  const nlohmann::json summary = nlohmann::json::parse(read_file(out + "/summary.json"));
  EXPECT_EQ(summary["models"], nlohmann::json({"ward", "lambert"}));
  EXPECT_EQ(summary["counts"]["ok"], 2);
  EXPECT_EQ(summary["counts"]["failed"], 1);
  ASSERT_EQ(summary["materials"].size(), 3u);
  const nlohmann::json& broken = summary["materials"][1];  // input order: blue, broken, red
  EXPECT_EQ(broken["material"], "broken");
  EXPECT_EQ(broken["status"], "failed");
  EXPECT_NE(broken["error"].get<std::string>().find("broken.csv"), std::string::npos) << broken["error"];
  EXPECT_TRUE(broken["result"].is_null());
  EXPECT_EQ(summary["materials"][2]["best_model"], "ward");
  EXPECT_LT(summary["materials"][2]["errors"]["ward"].get<double>(), 1e-6);

  const std::string csv = read_file(out + "/summary.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "material,input,status,resumed,error,best_model,best_error,seconds,ward,lambert");
  EXPECT_NE(csv.find("\nbroken," + in + "/broken.csv,failed,no,"), std::string::npos) << csv;
  // blue is Lambertian, which ward also holds exactly (specular 0): either may rank first.
  EXPECT_NE(csv.find("\nblue," + in + "/blue.csv,ok,no,,"), std::string::npos) << csv;
  EXPECT_LT(summary["materials"][0]["errors"]["lambert"].get<double>(), 1e-6);

  // What a shell glob over the folder gives compare: the summary stands for the documents it
  // lists, each counted once.
  const auto compared = test::run_cli("compare " + out + "/summary.json " + out + "/red.json " + out + "/blue.json");
  EXPECT_EQ(compared.exit_code, 0) << compared.output;
  EXPECT_NE(compared.output.find("over 2 materials"), std::string::npos) << compared.output;
}

TEST(BatchCli, ResumeSkipsMaterialsAlreadyDoneAndRetriesTheOthers) {
  const std::string dir = test::fresh_dir("batch-resume"), in = write_batch_inputs(dir), out = dir + "/out";
  const std::string command = "batch " + in + " --models lambert --out " + out;
  ASSERT_EQ(test::run_cli(command).exit_code, 1);
  const std::string red_before = read_file(out + "/red.json"), blue_before = read_file(out + "/blue.json");

  // Repair the broken table and change blue's: resume fits those two and leaves red alone.
  test::write_model_csv(in + "/broken.csv", "lambert", {"albedo=0.3"}, 500, 3);
  test::write_model_csv(in + "/blue.csv", "lambert", {"albedo=0.2,0.2,0.6"}, 2000, 2);
  const auto r = test::run_cli(command + " --resume");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("red: already done"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("broken: ok"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("blue: ok"), std::string::npos) << r.output;
  EXPECT_EQ(read_file(out + "/red.json"), red_before);  // not rewritten: its seconds would differ
  EXPECT_NE(read_file(out + "/blue.json"), blue_before);

  // Asking for another model is not done yet either.
  const auto more = test::run_cli("batch " + in + " --models lambert,ward --out " + out + " --resume");
  EXPECT_EQ(more.exit_code, 0) << more.output;
  EXPECT_EQ(more.output.find(": already done"), std::string::npos) << more.output;
  const nlohmann::json summary = nlohmann::json::parse(read_file(out + "/summary.json"));
  EXPECT_EQ(summary["counts"]["ok"], 3);
  EXPECT_EQ(summary["counts"]["resumed"], 0);
}

TEST(BatchCli, BadOptionsFailBeforeAnyWork) {
  const std::string dir = test::fresh_dir("batch-bad"), in = write_batch_inputs(dir);
  test::expect_cli_errors({{"batch " + in + " --models nosuch --out " + dir + "/out", "unknown model 'nosuch'"},
                           {"batch " + in + " --metric nosuch --out " + dir + "/out", "unknown metric 'nosuch'"},
                           {"batch " + dir + "/nothing --out " + dir + "/out", "nothing: no such file or folder"}},
                          dir + "/out");
}

}  // namespace
}  // namespace brdffit
