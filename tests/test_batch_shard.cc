// Batches split over scheduler tasks: --shard K/N|auto|auto/N, disjoint shares balanced by table
// size, and --merge giving the same documents and summary as one process.
#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>

#include "batch_test_util.h"
#include "brdffit/batch_shard.h"
#include "brdffit/error.h"

namespace brdffit {
namespace {

namespace fs = std::filesystem;

EnvironmentLookup fake_environment(std::map<std::string, std::string> variables) {
  return [variables](const std::string& name) -> std::optional<std::string> {
    const auto found = variables.find(name);
    return found == variables.end() ? std::nullopt : std::optional<std::string>(found->second);
  };
}

void expect_shard(const Shard& shard, int index, int count) {
  EXPECT_EQ(shard.index, index);
  EXPECT_EQ(shard.count, count);
}

TEST(BatchShard, ParsesExplicitSlurmAndKubernetesShards) {
  const EnvironmentLookup none = fake_environment({});
  expect_shard(parse_shard("0/1", none), 0, 1);
  expect_shard(parse_shard("2/3", none), 2, 3);
  // Slurm arrays start anywhere and may step: --array=4-6 is tasks 4, 5, 6; --array=2-6:2 is 2, 4, 6.
  expect_shard(parse_shard("auto", fake_environment({{"SLURM_ARRAY_TASK_ID", "5"},
                                                     {"SLURM_ARRAY_TASK_MIN", "4"},
                                                     {"SLURM_ARRAY_TASK_COUNT", "3"}})),
               1, 3);
  expect_shard(parse_shard("auto", fake_environment({{"SLURM_ARRAY_TASK_ID", "6"},
                                                     {"SLURM_ARRAY_TASK_MIN", "2"},
                                                     {"SLURM_ARRAY_TASK_STEP", "2"},
                                                     {"SLURM_ARRAY_TASK_COUNT", "3"}})),
               2, 3);
  expect_shard(parse_shard("auto/4", fake_environment({{"JOB_COMPLETION_INDEX", "3"}})), 3, 4);
  expect_shard(parse_shard("auto/4", fake_environment({{"SLURM_ARRAY_TASK_ID", "1"}})), 1, 4);
}

TEST(BatchShard, RejectsShardsThatDoNotExist) {
  const EnvironmentLookup none = fake_environment({});
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"3/3", "shard 3 does not exist among 3"},   {"1/0", "expected K/N"},
      {"x/2", "K must be a whole number"},         {"2", "expected K/N"},
      {"-1/2", "K must be a whole number"},        {"auto", "SLURM_ARRAY_TASK_ID is not set"},
      {"auto/2", "SLURM_ARRAY_TASK_ID is not set"}};
  for (const auto& [text, message] : cases) {
    SCOPED_TRACE(text);
    try {
      parse_shard(text, none);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(parse_shard("auto/2", fake_environment({{"JOB_COMPLETION_INDEX", "2"}})), Error);
  EXPECT_THROW(parse_shard("auto", fake_environment({{"SLURM_ARRAY_TASK_ID", "x"}, {"SLURM_ARRAY_TASK_COUNT", "2"}})),
               Error);
}

std::vector<BatchMaterial> materials_of_sizes(const std::string& dir, const std::vector<size_t>& sizes) {
  std::vector<BatchMaterial> materials;
  for (size_t i = 0; i < sizes.size(); ++i) {
    const std::string path = dir + "/m" + std::to_string(i) + ".csv";
    write_file_atomic(path, std::string(sizes[i], 'x'));
    materials.push_back({"m" + std::to_string(i), path});
  }
  return materials;
}

using test::names;

TEST(BatchShard, SharesAreBalancedBySizeLargestFirst) {
  // By hand: largest first to the lighter shard (sizes + 1): m0 (100) -> 0; m2 (50) -> 1;
  // m3 (50) -> 1 (51 < 101); m1 (10) -> 0 (101 < 102); m4 (5) -> 1 (102 < 112).
  const auto materials = materials_of_sizes(test::fresh_dir("shard-sizes"), {100, 10, 50, 50, 5});
  EXPECT_EQ(names(shard_materials(materials, {0, 2})), (std::vector<std::string>{"m0", "m1"}));
  EXPECT_EQ(names(shard_materials(materials, {1, 2})), (std::vector<std::string>{"m2", "m3", "m4"}));
  EXPECT_EQ(names(shard_materials(materials, {0, 1})), names(materials));
  // More shards than materials: the last ones are empty, and no material is lost.
  std::vector<std::string> all;
  for (int k = 0; k < 7; ++k)
    for (const std::string& name : names(shard_materials(materials, {k, 7}))) all.push_back(name);
  std::sort(all.begin(), all.end());
  EXPECT_EQ(all, names(materials));
  EXPECT_TRUE(shard_materials(materials, {6, 7}).empty());
}

// Result documents without their timings, which differ from run to run.
TEST(BatchShardCli, ThreeShardsAndAMergeEqualOneProcess) {
  const std::string dir = test::fresh_dir("shard-run"), in = test::write_shard_inputs(dir);
  const std::string options = " --models lambert,ward --threads 1 --out ";
  ASSERT_EQ(test::run_cli("batch " + in + options + dir + "/single").exit_code, 0);

  const std::string sharded = dir + "/sharded";
  for (int k = 0; k < 3; ++k) {
    const auto r = test::run_cli("batch " + in + options + sharded + " --shard " + std::to_string(k) + "/3");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find(fmt::format("shard {}/3", k)), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(sharded + "/summary.json"));  // a shard's summary would hide the others'
  const auto merged = test::run_cli("batch " + in + options + sharded + " --merge");
  ASSERT_EQ(merged.exit_code, 0) << merged.output;

  test::expect_same_batch(sharded, dir + "/single");
}

TEST(BatchShardCli, AShardThatDiedIsReportedByTheMergeAndRecoveredByResume) {
  const std::string dir = test::fresh_dir("shard-died"), in = test::write_shard_inputs(dir), out = dir + "/out";
  const std::string batch = "batch " + in + " --models lambert --threads 1 --out " + out;
  // Shards 0 and 2 of 3 finish (2 from a Kubernetes Indexed Job's index); shard 1 never runs.
  ASSERT_EQ(test::run_cli(batch + " --shard 0/3").exit_code, 0);
  ASSERT_EQ(test::run_command("JOB_COMPLETION_INDEX=2 " + std::string(BRDFFIT_CLI) + " " + batch + " --shard auto/3")
                .exit_code,
            0);
  const auto incomplete = test::run_cli(batch + " --merge");
  EXPECT_EQ(incomplete.exit_code, 1) << incomplete.output;
  EXPECT_NE(incomplete.output.find("its shard did not finish it"), std::string::npos) << incomplete.output;
  const nlohmann::json partial = nlohmann::json::parse(read_file(out + "/summary.json"));
  EXPECT_EQ(partial["counts"]["failed"].get<int>() + partial["counts"]["ok"].get<int>(), 4);
  EXPECT_GE(partial["counts"]["failed"].get<int>(), 1);

  // Shard 1 again, as a Slurm array task (--array=0-2, task 1), with --resume; then the merge.
  const auto rerun = test::run_command("SLURM_ARRAY_TASK_ID=1 SLURM_ARRAY_TASK_MIN=0 SLURM_ARRAY_TASK_COUNT=3 " +
                                       std::string(BRDFFIT_CLI) + " " + batch + " --shard auto --resume");
  ASSERT_EQ(rerun.exit_code, 0) << rerun.output;
  EXPECT_EQ(rerun.output.find(": already done"), std::string::npos) << rerun.output;  // its own were never written
  const auto merged = test::run_cli(batch + " --merge");
  EXPECT_EQ(merged.exit_code, 0) << merged.output;
  EXPECT_EQ(nlohmann::json::parse(read_file(out + "/summary.json"))["counts"]["ok"], 4);
}

TEST(BatchShardCli, ShardsShareTheFolderButNoShardRunsTwice) {
  const std::string dir = test::fresh_dir("shard-lock"), in = test::write_shard_inputs(dir), out = dir + "/out";
  const std::string batch = "batch " + in + " --models lambert --threads 1 --out " + out;
  // Shard 0 is running (this process holds it): shard 1 goes ahead, shard 0 may not.
  const OutputFolderLock shard0(out, 0, 2);
  const auto other = test::run_cli(batch + " --shard 1/2");
  EXPECT_EQ(other.exit_code, 0) << other.output;
  const auto same = test::run_cli(batch + " --shard 0/2");
  EXPECT_NE(same.exit_code, 0);
  EXPECT_NE(same.output.find("another batch (shard 0/2)"), std::string::npos) << same.output;
  EXPECT_TRUE(fs::exists(out + "/" + std::string(OutputFolderLock::kLockName)));  // still held by shard 0
}

TEST(BatchShardCli, MergeAndShardExcludeEachOther) {
  const std::string dir = test::fresh_dir("shard-options");
  test::expect_cli_errors({{"batch " + dir + " --shard 0/2 --merge --out " + dir + "/out", "excludes"},
                           {"batch " + dir + " --shard 2/2 --out " + dir + "/out", "shard 2 does not exist among 2"}},
                          dir + "/out/summary.json");
}

// docs/cluster.md's Slurm script, run as the array tasks 0-2 of `sbatch --array=0-2` would be
// (the #SBATCH lines are comments to bash), then as the dependent merge job.
TEST(ClusterDocs, SbatchScriptRunsAsThreeArrayTasksAndAMerge) {
  const std::string dir = test::fresh_dir("shard-sbatch"), in = test::write_shard_inputs(dir), out = dir + "/out";
  const std::string script = std::string(BRDFFIT_SOURCE_DIR) + "/docs/cluster/brdffit-array.sbatch";
  const std::string environment =
      fmt::format("BRDFFIT={} INPUTS={} OUT={} MODELS=lambert SLURM_CPUS_PER_TASK=1 ", BRDFFIT_CLI, in, out);
  for (int task = 0; task < 3; ++task) {
    const auto r = test::run_command(environment + fmt::format("SLURM_ARRAY_TASK_ID={} SLURM_ARRAY_TASK_MIN=0 "
                                                               "SLURM_ARRAY_TASK_COUNT=3 bash {}",
                                                               task, script));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find(fmt::format("shard {}/3", task)), std::string::npos) << r.output;
  }
  const auto merged = test::run_command(environment + "BRDFFIT_MERGE=1 bash " + script);
  ASSERT_EQ(merged.exit_code, 0) << merged.output;
  EXPECT_EQ(nlohmann::json::parse(read_file(out + "/summary.json"))["counts"]["ok"], 4);
}

// The Kubernetes manifests: the Job's completions is the N of --shard auto/N, and the merge Job
// names the same inputs, models and folder.
TEST(ClusterDocs, IndexedJobShardsMatchItsCompletionsAndTheMerge) {
  const std::string dir = std::string(BRDFFIT_SOURCE_DIR) + "/docs/cluster/";
  const std::string job = read_file(dir + "brdffit-indexed-job.yaml"),
                    merge = read_file(dir + "brdffit-merge-job.yaml");
  const size_t completions = job.find("completions: ");
  ASSERT_NE(completions, std::string::npos);
  const std::string n = job.substr(completions + 13, job.find_first_of(" \n", completions + 13) - completions - 13);
  EXPECT_NE(job.find("\"auto/" + n + "\""), std::string::npos) << "--shard auto/" << n;
  EXPECT_NE(job.find("completionMode: Indexed"), std::string::npos);
  const std::string batch = R"("batch", "/data/tables", "--models", "all", "--out", "/data/results")";
  EXPECT_NE(job.find(batch), std::string::npos);
  EXPECT_NE(merge.find(batch), std::string::npos);
  EXPECT_NE(merge.find("\"--merge\""), std::string::npos);
}

}  // namespace
}  // namespace brdffit
