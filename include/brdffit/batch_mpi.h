// A batch over the ranks of an MPI job: `mpirun -n N brdffit batch ...` (docs/cluster.md, "MPI").
//
// Rank 0 hands the materials out one per request, largest input first (dynamic load
// balancing: a rank that finishes early asks again), and fits none itself; every other rank
// fits what it is handed exactly as a single-process batch does, writing the material's result
// document into the shared output folder (atomically) before asking for the next. Rank 0 then
// has every outcome and writes the one summary. Results are files, so `--resume` works across
// runs, and a job that dies (OpenMPI ends the whole job when one rank dies) loses only the
// materials in progress: the next `--resume` fits just those.
//
// In brdffit_mpi, linked only by the brdffit-mpi executable: `brdffit` itself loads no MPI
// library and hands a batch started by mpirun over to brdffit-mpi.
#pragma once

#include <vector>

#include "brdffit/batch.h"

namespace brdffit {

class MpiBatch {
 public:
  MpiBatch();   // initialises MPI (funnelled threads: only the calling thread talks to MPI)
  ~MpiBatch();  // finalises it
  MpiBatch(const MpiBatch&) = delete;
  MpiBatch& operator=(const MpiBatch&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }

  // Rank 0: every material's outcome in input order, as run_batch returns them, with `events`
  // called as ranks start and finish materials. Other ranks: fit until no material is left, then
  // return nothing. options.jobs is 1 per rank; options.fit.threads 0 shares the node's cores
  // among the ranks on it. The caller on rank 0 holds the OutputFolderLock.
  std::vector<MaterialOutcome> run(const std::vector<BatchMaterial>& materials, const BatchOptions& options,
                                   const BatchEvents& events = {});

 private:
  int rank_ = 0, size_ = 1;
};

}  // namespace brdffit
