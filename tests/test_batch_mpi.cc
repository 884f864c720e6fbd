// `mpirun -n N brdffit batch ...`: the ranks share one batch (batch_mpi.h) and write what a
// single process writes; a job that died is finished by --resume.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "batch_test_util.h"
#include "brdffit/io.h"
#include "test_util.h"

namespace brdffit {
namespace {

namespace fs = std::filesystem;

// mpirun, as root and with more ranks than cores if need be (this machine has two). In a
// sanitized build the ranks run without LeakSanitizer: OpenMPI's runtime (libopen-pal, hwloc and
// its plugins) leaves its allocations to the exit, which LeakSanitizer reports as leaks in code
// that is not ours. AddressSanitizer still checks every access.
std::string mpirun(int ranks) {
  return "ASAN_OPTIONS=detect_leaks=0 mpirun -x ASAN_OPTIONS --oversubscribe --allow-run-as-root -n " +
         std::to_string(ranks) + " " + BRDFFIT_CLI + " ";
}

// Skips unless brdffit-mpi was built and mpirun runs; under CI (which installs OpenMPI) a build
// without it is a failure.
#define SKIP_UNLESS_MPI()                                                                               \
  do {                                                                                                  \
    if (!BRDFFIT_HAVE_MPI || test::run_command("mpirun --version").exit_code != 0) {                    \
      if (test::running_in_ci()) FAIL() << "CI installs OpenMPI, but brdffit-mpi or mpirun is missing"; \
      GTEST_SKIP() << "brdffit was built without MPI (libopenmpi-dev) or mpirun is missing";            \
    }                                                                                                   \
  } while (0)

TEST(BatchMpi, ThreeRanksWriteWhatOneProcessWrites) {
  SKIP_UNLESS_MPI();
  const std::string dir = test::fresh_dir("mpi-run"), in = test::write_shard_inputs(dir);
  const std::string options = " --models lambert,ward --threads 1 --out ";
  ASSERT_EQ(test::run_cli("batch " + in + options + dir + "/single").exit_code, 0);
  const auto ranks = test::run_command(mpirun(3) + "batch " + in + options + dir + "/mpi");
  ASSERT_EQ(ranks.exit_code, 0) << ranks.output;
  EXPECT_NE(ranks.output.find("over 2 MPI ranks"), std::string::npos) << ranks.output;

  test::expect_same_batch(dir + "/mpi", dir + "/single");
  EXPECT_FALSE(fs::exists(dir + "/mpi/.brdffit-batch.lock"));  // released by rank 0
}

TEST(BatchMpi, ResumeFitsOnlyWhatADeadJobLeftUndone) {
  SKIP_UNLESS_MPI();
  const std::string dir = test::fresh_dir("mpi-resume"), in = test::write_shard_inputs(dir), out = dir + "/out";
  const std::string batch = "batch " + in + " --models lambert --threads 1 --out " + out;
  ASSERT_EQ(test::run_command(mpirun(3) + batch).exit_code, 0);
  // A job killed while a rank fitted "green": its document never written, a temporary left.
  fs::remove(out + "/green.json");
  write_file_atomic(out + "/" + kTempPrefix + "green.json.Xy12Zw", "half");
  const auto resumed = test::run_command(mpirun(3) + batch + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("green: ok in"), std::string::npos) << resumed.output;
  for (const char* material : {"red", "blue", "grey"})
    EXPECT_NE(resumed.output.find(std::string(material) + ": already done"), std::string::npos) << resumed.output;
  EXPECT_TRUE(fs::exists(out + "/green.json"));
  EXPECT_FALSE(fs::exists(out + "/" + kTempPrefix + "green.json.Xy12Zw"));
  EXPECT_EQ(nlohmann::json::parse(read_file(out + "/summary.json"))["counts"]["ok"], 4);
}

}  // namespace
}  // namespace brdffit
