// Splitting one batch over independent tasks of a cluster scheduler (Slurm job arrays,
// Kubernetes Indexed Jobs, or any N processes started by hand): each task fits a deterministic
// share of the materials into the same output folder, and a final merge step writes the summary.
//
// Every task lists the same materials (batch_materials on the same inputs) and keeps those of
// its shard; the shares are disjoint, together they are every material, and they are balanced
// by table size (larger tables take longer), largest first, greedily to the least-loaded shard,
// ties in input order. The share depends only on the materials and their file sizes, so every
// task computes the same split without talking to the others.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "brdffit/batch.h"

namespace brdffit {

struct Shard {
  int index = 0;  // 0-based, < count
  int count = 1;
};

// An environment variable's value, or nullopt when unset (std::getenv by default; tests inject).
using EnvironmentLookup = std::function<std::optional<std::string>(const std::string& name)>;
std::optional<std::string> process_environment(const std::string& name);

// Parses --shard:
//   "K/N"     shard K (0-based) of N;
//   "auto"    from a Slurm job array: K = (SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN) /
//             SLURM_ARRAY_TASK_STEP (min 0 and step 1 when unset), N = SLURM_ARRAY_TASK_COUNT;
//   "auto/N"  N given, K from JOB_COMPLETION_INDEX (Kubernetes Indexed Job), else from Slurm.
// Throws Error naming --shard and the problem (malformed, K outside [0, N), no scheduler
// variables in the environment).
Shard parse_shard(const std::string& text, const EnvironmentLookup& environment = process_environment);

// The materials of one shard, in input order (see the header comment for the split).
std::vector<BatchMaterial> shard_materials(const std::vector<BatchMaterial>& materials, const Shard& shard);

}  // namespace brdffit
