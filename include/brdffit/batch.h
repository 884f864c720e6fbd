// Fitting many materials: which files an input names, one result document per material, and
// the summary of the whole set. The library side of `brdffit batch`.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "brdffit/fit.h"
#include "brdffit/samples.h"

namespace brdffit {

struct BatchMaterial {
  std::string name;  // unique within the batch; names the result document <name>.json
  std::string path;  // the table, absolute
};

// The materials that inputs name, in order, each file once:
//   - a file with a table extension (.binary, .bsdf, .csv) is one material;
//   - a folder stands for every such file inside it, recursively, in sorted order (nothing under
//     `skip_dir`, the batch's own output folder, whose summary.csv is no table);
//   - any other text file is a manifest: one path per line (relative to the manifest's folder;
//     blank lines and '#' comments skipped), each a table or a folder. A binary file is a table
//     whatever its extension (MERL files are recognised by content).
// Inputs on the command line must exist (Error naming the input otherwise); a manifest's entry
// that does not is kept, and fails as a material when the batch reaches it.
// Names are file names without the table extension, made unique by -2, -3, ... in input order.
std::vector<BatchMaterial> batch_materials(const std::vector<std::string>& inputs, const std::string& skip_dir = "");

struct BatchOptions {
  std::vector<const Model*> models;
  FitOptions fit;  // fit.threads: threads per material; 0: the cores shared among the jobs
  SamplingOptions sampling;
  std::string out_dir;
  int jobs = 1;         // materials fitted at once
  bool resume = false;  // skip materials whose result document is complete and current
  // Fit nothing: take every material's complete and current document (as resume does), and
  // record a material without one as failed. The merge step after the shards of a batch
  // (batch_shard.h) ran, for the summary.
  bool merge_only = false;
  // Other processes (the other shards of this batch) write into out_dir at the same time: the
  // temporary files of a killed run are left for the merge step to remove, not taken for stale.
  bool shared_folder = false;
};

enum class MaterialStatus {
  Ok,       // every model fitted; result document written (or, resumed, already there)
  Partial,  // result document written, but some models failed to fit
  Failed,   // no result document: the table could not be read, or fitting threw
};
const char* material_status_name(MaterialStatus status);  // "ok", "partial", "failed"

struct MaterialOutcome {
  BatchMaterial material;
  MaterialStatus status = MaterialStatus::Failed;
  bool resumed = false;         // skipped: its document was already complete
  std::string error;            // Failed: why; Partial: which models failed
  std::string result_path;      // empty when Failed
  std::vector<FitResult> fits;  // the models' results (read back when resumed)
  double seconds = 0.0;
};

// Called from worker threads, one call at a time.
struct BatchEvents {
  std::function<void(const BatchMaterial&)> started;
  std::function<void(const MaterialOutcome&)> finished;
};

// Holds a batch's output folder for one process, by locks on the lock file kLockName in it:
// one protocol for every run that writes there. A whole-folder run (plain, --merge, rank 0 of an
// MPI job) excludes every other; shard K of N excludes whole-folder runs, shards of another N
// and another shard K of N, and runs beside the other shards of N. The locks are the kernel's
// (open-file-description locks, which NFS supports), so a killed batch holds nothing; the lock
// file (holding a whole-folder owner's pid, for the message) is removed by the last holder.
// Throws Error naming the folder and who holds it. Held around run_batch and the summary, so
// two batches never overwrite each other's results.
class OutputFolderLock {
 public:
  static constexpr const char* kLockName = ".brdffit-batch.lock";
  // The most shards a batch is split into (--shard K/N: N at most this).
  static constexpr int kMaxShards = 100000;
  // The whole folder.
  explicit OutputFolderLock(const std::string& folder);
  // Shard shard_index (0-based) of shard_count.
  OutputFolderLock(const std::string& folder, int shard_index, int shard_count);
  ~OutputFolderLock();
  OutputFolderLock(const OutputFolderLock&) = delete;
  OutputFolderLock& operator=(const OutputFolderLock&) = delete;

 private:
  std::string path_;
  int fd_ = -1;
};

// How a batch of `materials` runs: materials fitted at once (options.jobs, at most one per
// material, at least one), and threads per material (options.fit.threads, or the cores shared
// among the jobs).
struct BatchPlan {
  int jobs = 1;
  int threads = 1;
};
BatchPlan plan_batch(const BatchOptions& options, size_t materials);

// Fits every material with every model, options.jobs materials at a time, each table read only
// when its turn comes (memory holds at most `jobs` tables). Each material's result document
// (fit_document_json, plus "material") is written atomically to <out_dir>/<name>.json as soon as
// it is fitted; a material that fails is recorded and the others go on. With resume, a material
// is skipped when its document exists, names the same input with the same SHA-256, the same
// metric, per-channel and loss settings, and holds every requested model fitted ok. Returns one
// outcome per material, in input order. A material that fails leaves no result document: an
// older one (from a previous run, for an input since changed) is removed, so it cannot be taken
// for this run's. With resume or merge_only (and not shared_folder), temporary files a killed run
// left in out_dir are removed first.
// The caller holds an OutputFolderLock on out_dir. Throws Error only for an unusable output folder.
std::vector<MaterialOutcome> run_batch(const std::vector<BatchMaterial>& materials, const BatchOptions& options,
                                       const BatchEvents& events = {});

// Before a batch starts: throws UsageError when the result document a material would get in
// out_dir already holds fits of models not in options.models, so that rewriting it would drop
// them (with resume, a document complete and current for this batch is kept, not rewritten; with
// merge_only nothing is rewritten). The message names the documents and the -m that keeps every
// model. A batch never silently replaces a document's models with fewer.
void check_batch_keeps_models(const std::vector<BatchMaterial>& materials, const BatchOptions& options);

// How many materials ended in each status; `resumed` counts those skipped (they are also ok).
struct OutcomeCounts {
  size_t ok = 0, partial = 0, failed = 0, resumed = 0;
};
OutcomeCounts count_outcomes(const std::vector<MaterialOutcome>& outcomes);

// summary.json and summary.csv: per material its status, error, best model and every model's
// error under the options' metric (empty/null where a model failed).
nlohmann::json batch_summary_json(const std::vector<MaterialOutcome>& outcomes, const BatchOptions& options,
                                  double seconds);
std::string batch_summary_csv(const std::vector<MaterialOutcome>& outcomes, const BatchOptions& options);

}  // namespace brdffit
