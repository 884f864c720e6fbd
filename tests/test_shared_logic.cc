// The one copy of what the commands share (best and named results, numbers in JSON and text,
// material names, how a batch splits the cores, outcome counts), the split of the CLI into
// brdffit (no image library) and brdffit-imaging, and of the library's tree into core and imaging.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "batch_test_util.h"
#include "brdffit/batch.h"
#include "brdffit/io.h"
#include "brdffit/measured.h"
#include "brdffit/parallel.h"
#include "brdffit/result_json.h"
#include "test_util.h"

namespace brdffit {
namespace {

FitResult result(const std::string& model, bool ok, double cosine) {
  FitResult r;
  r.model = model;
  r.ok = ok;
  r.verdict = ok ? Verdict::Good : Verdict::Failed;
  r.metrics.cosine = cosine;
  return r;
}

TEST(SharedLogic, BestResultSkipsFailedFitsAndErrorsThatAreNotNumbers) {
  // ggx has the lowest number but failed; ward's error is NaN (a batch's progress line used to
  // take it, comparing NaN is always false); lambert's 0.05 is the best that fitted.
  const std::vector<FitResult> results = {result("ward", true, NAN), result("ggx", false, 0.01),
                                          result("lambert", true, 0.05), result("phong", true, 0.07)};
  ASSERT_NE(best_result(results, Metric::Cosine), nullptr);
  EXPECT_EQ(best_result(results, Metric::Cosine)->model, "lambert");
  EXPECT_EQ(best_result({result("ward", true, NAN), result("ggx", false, 0.01)}, Metric::Cosine), nullptr);
  EXPECT_EQ(find_result(results, "ggx"), &results[1]);
  EXPECT_EQ(find_result(results, "beckmann"), nullptr);
}

TEST(SharedLogic, CountsTakeTheirNounsPluralUnlessOne) {
  EXPECT_EQ(count_of(1, "material"), "1 material");
  EXPECT_EQ(count_of(0, "material"), "0 materials");
  EXPECT_EQ(count_of(28, "model"), "28 models");
}

TEST(SharedLogic, NumbersAsJsonAndAsText) {
  EXPECT_EQ(number_or_null(0.25).dump(), "0.25");
  EXPECT_TRUE(number_or_null(NAN).is_null());
  EXPECT_TRUE(number_or_null(INFINITY).is_null());
  EXPECT_EQ(format_values({0.123456}, "{:.3g}"), "0.123");
  EXPECT_EQ(format_values({1, 0.5, 0.25}), "[1,0.5,0.25]");
  EXPECT_EQ(csv_field("ggx"), "ggx");
  EXPECT_EQ(csv_field("a=[1,2]"), "\"a=[1,2]\"");
  EXPECT_EQ(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
}

TEST(SharedLogic, MaterialNames) {
  EXPECT_EQ(table_material_name("/data/gold-metallic-paint.binary"), "gold-metallic-paint");
  EXPECT_EQ(table_material_name("cc_ibiza.BSDF"), "cc_ibiza");
  EXPECT_EQ(table_material_name("dir/samples.csv"), "samples");
  EXPECT_EQ(table_material_name("dir/merl_table.dat"), "merl_table.dat");  // not a table extension
  FitDocument fitted;
  fitted.input_path = "/data/blue-acrylic.binary";
  EXPECT_EQ(material_name(fitted), "blue-acrylic");
  fitted.json = {{"material", "blue-acrylic-2"}};  // a batch's name for the second of two
  EXPECT_EQ(material_name(fitted), "blue-acrylic-2");
}

TEST(SharedLogic, BatchPlanSharesTheCoresAmongTheJobs) {
  BatchOptions options;
  options.jobs = 4;
  BatchPlan plan = plan_batch(options, 10);
  EXPECT_EQ(plan.jobs, 4);
  EXPECT_EQ(plan.threads, std::max(1, thread_count(0) / 4));
  plan = plan_batch(options, 2);  // no more jobs than materials
  EXPECT_EQ(plan.jobs, 2);
  EXPECT_EQ(plan.threads, std::max(1, thread_count(0) / 2));
  EXPECT_EQ(plan_batch(options, 0).jobs, 1);
  options.fit.threads = 3;
  EXPECT_EQ(plan_batch(options, 10).threads, 3);
}

TEST(SharedLogic, ThreadsDefaultToTheCoresThisProcessMayUse) {
  // A scheduler's cpuset or mpirun's binding narrows the affinity: "every core" means those.
  cpu_set_t saved;
  ASSERT_EQ(sched_getaffinity(0, sizeof(saved), &saved), 0);
  EXPECT_EQ(available_cores(), CPU_COUNT(&saved));
  EXPECT_EQ(thread_count(0), CPU_COUNT(&saved));
  EXPECT_EQ(thread_count(5), 5);
  cpu_set_t one;
  CPU_ZERO(&one);
  for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu)
    if (CPU_ISSET(cpu, &saved)) {
      CPU_SET(cpu, &one);
      break;
    }
  ASSERT_EQ(sched_setaffinity(0, sizeof(one), &one), 0);  // this thread only
  EXPECT_EQ(thread_count(0), 1);
  BatchOptions options;
  options.jobs = 2;
  EXPECT_EQ(plan_batch(options, 10).threads, 1);
  ASSERT_EQ(sched_setaffinity(0, sizeof(saved), &saved), 0);
}

TEST(SharedLogic, OutcomeCounts) {
  std::vector<MaterialOutcome> outcomes(5);
  outcomes[0].status = MaterialStatus::Ok;
  outcomes[1].status = MaterialStatus::Ok;
  outcomes[1].resumed = true;
  outcomes[2].status = MaterialStatus::Partial;
  outcomes[3].status = MaterialStatus::Failed;
  outcomes[4].status = MaterialStatus::Failed;
  const OutcomeCounts counts = count_outcomes(outcomes);
  EXPECT_EQ(counts.ok, 2u);
  EXPECT_EQ(counts.resumed, 1u);
  EXPECT_EQ(counts.partial, 1u);
  EXPECT_EQ(counts.failed, 2u);
}

// The shared libraries the dynamic loader maps for an executable (what ldd prints).
std::string loaded_libraries(const std::string& executable) {
  return test::run_command("LD_TRACE_LOADED_OBJECTS=1 " + executable).output;
}

TEST(CliSplit, BrdffitLoadsNoImageLibrary) {
  const std::string brdffit = loaded_libraries(BRDFFIT_CLI);
  ASSERT_NE(brdffit.find("libc.so"), std::string::npos) << brdffit;
  EXPECT_EQ(brdffit.find("opencv"), std::string::npos) << brdffit;
  EXPECT_EQ(brdffit.find("OpenImageIO"), std::string::npos) << brdffit;
  const std::string imaging =
      loaded_libraries((std::filesystem::path(BRDFFIT_CLI).parent_path() / "brdffit-imaging").string());
  EXPECT_NE(imaging.find("libopencv_imgproc"), std::string::npos) << imaging;
}

TEST(CliSplit, ImageCommandsRunThroughBrdffit) {
  const test::CommandResult help = test::run_cli("--help");
  for (const char* command : {"sphere", "capture", "render", "report", "fit", "batch"})
    EXPECT_NE(help.output.find(std::string("\n  ") + command + " "), std::string::npos) << command;
  const test::CommandResult render = test::run_cli("render --help");
  EXPECT_EQ(render.exit_code, 0);
  EXPECT_NE(render.output.find("--reference"), std::string::npos) << render.output;
}

TEST(CliSplit, AMissingBrdffitImagingIsOneClearError) {
  const std::string dir = test::fresh_dir("cli-split");
  const std::string lone = dir + "/brdffit";
  std::filesystem::copy_file(BRDFFIT_CLI, lone);
  std::filesystem::permissions(lone, std::filesystem::perms::owner_exec, std::filesystem::perm_options::add);
  const test::CommandResult r = test::run_command("PATH=" + dir + " " + lone + " render x.binary --out x.png");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("brdffit: error: render: needs brdffit-imaging"), std::string::npos) << r.output;
  EXPECT_EQ(test::run_command("PATH=" + dir + " " + lone + " models").exit_code, 0);
}

// The library's core (src/, include/brdffit/) includes no header of its imaging part
// (include/brdffit/imaging/): brdffit_core links no image library, and a core file that needed one
// belongs in an imaging/ folder. Every file of src/ and include/brdffit/ is read, so the imaging
// sources, which include their headers, show that the include lines are seen.
TEST(LibrarySplit, CoreIncludesNoImagingHeader) {
  std::vector<std::string> core_offenders;
  int imaging_include_lines = 0;
  for (const char* root : {"/src", "/include/brdffit"}) {
    for (const auto& entry : std::filesystem::recursive_directory_iterator(std::string(BRDFFIT_SOURCE_DIR) + root)) {
      const std::filesystem::path& path = entry.path();
      if (path.extension() != ".cc" && path.extension() != ".h") continue;
      const bool in_imaging = path.parent_path().filename() == "imaging";
      std::istringstream lines(test::slurp(path.string()));
      std::string line;
      for (int number = 1; std::getline(lines, line); ++number) {
        if (line.rfind("#include", 0) != 0 || line.find("brdffit/imaging/") == std::string::npos) continue;
        if (in_imaging)
          ++imaging_include_lines;
        else
          core_offenders.push_back(path.string() + ":" + std::to_string(number) + ": " + line);
      }
    }
  }
  EXPECT_GE(imaging_include_lines, 8);  // each of the eight imaging sources includes an imaging header
  EXPECT_TRUE(core_offenders.empty()) << ::testing::PrintToString(core_offenders);
}

}  // namespace
}  // namespace brdffit
