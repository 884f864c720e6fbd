// The command of brdffit-mpi: `batch`, whose materials the ranks of an MPI job share
// (batch_mpi.h). `brdffit batch` started by mpirun hands itself over to it.
#include <fmt/format.h>

#include <memory>

#include "batch_ranks.h"
#include "brdffit/batch_mpi.h"
#include "commands.h"

namespace brdffit::cli {

namespace {

// The ranks of this MPI job share the materials; rank 0 hands them out, holds the lock and
// writes the summary, the others only fit.
class MpiRanks : public BatchRanks {
 public:
  bool reports() const override { return mpi_.rank() == 0; }
  bool shares_materials() const override { return true; }
  std::string plan(const BatchOptions&, size_t) const override {
    return fmt::format(" over {} MPI ranks, one material at a time each", mpi_.size() - 1);
  }
  std::vector<MaterialOutcome> run(const std::vector<BatchMaterial>& materials, const BatchOptions& options,
                                   const BatchEvents& events) override {
    return mpi_.run(materials, options, events);
  }

 private:
  MpiBatch mpi_;  // MPI initialised once the command line is parsed, finalised with the batch
};

}  // namespace

void add_commands(CLI::App& app, int, char**) {
  add_batch_command(app, [] { return std::unique_ptr<BatchRanks>(std::make_unique<MpiRanks>()); });
}

}  // namespace brdffit::cli
