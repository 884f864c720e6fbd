// Where `brdffit batch` fits its materials: in this process (brdffit: InProcessBatch, cmd_batch.cc)
// or shared over the ranks of an MPI job (brdffit-mpi: commands_mpi.cc, batch_mpi.h). The batch
// command itself is the same in both, compiled once.
#pragma once

#include <string>
#include <vector>

#include "brdffit/batch.h"

namespace brdffit::cli {

class BatchRanks {
 public:
  virtual ~BatchRanks() = default;
  // Whether this process reports: holds the output folder's lock, prints the progress and writes
  // the summary (an MPI job's rank 0; the other ranks only fit).
  virtual bool reports() const = 0;
  // Whether the ranks share the materials out themselves: then --shard is refused.
  virtual bool shares_materials() const = 0;
  // How the materials are fitted, for the opening line after "batch: M materials x N models":
  // ", 2 at a time with 4 threads each".
  virtual std::string plan(const BatchOptions& options, size_t materials) const = 0;
  // Every material's outcome in input order (nothing on a rank that does not report).
  virtual std::vector<MaterialOutcome> run(const std::vector<BatchMaterial>& materials, const BatchOptions& options,
                                           const BatchEvents& events) = 0;
};

}  // namespace brdffit::cli
