// `brdffit batch`: fit every model to many tables, one result document per material and a
// summary; in this process, or (brdffit-mpi) over the ranks of an MPI job (batch_ranks.h).
#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "batch_progress.h"
#include "batch_ranks.h"
#include "brdffit/batch.h"
#include "brdffit/batch_shard.h"
#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/result_json.h"
#include "cli_common.h"
#include "commands.h"
#include "fit_options.h"

namespace brdffit::cli {

namespace {

namespace fs = std::filesystem;

// brdffit's batch: options.jobs materials at a time in this process (run_batch).
class InProcessBatch : public BatchRanks {
 public:
  bool reports() const override { return true; }
  bool shares_materials() const override { return false; }
  std::string plan(const BatchOptions& options, size_t materials) const override {
    const BatchPlan plan = plan_batch(options, materials);
    return fmt::format(", {} at a time with {} threads each", plan.jobs, plan.threads);
  }
  std::vector<MaterialOutcome> run(const std::vector<BatchMaterial>& materials, const BatchOptions& options,
                                   const BatchEvents& events) override {
    return run_batch(materials, options, events);
  }
};

struct BatchArgs {
  std::vector<std::string> inputs;
  std::string models = "all";
  std::string metric = "cosine";
  std::string loss = "none";
  bool per_channel = false;
  ConvergeArg converge;
  FixArg fix;
  SamplingArgs sampling;
  std::string out = "brdffit-batch";
  int jobs = 1;
  int threads = 0;
  bool resume = false;
  std::string shard;   // K/N, auto, auto/N: fit only this share (batch_shard.h)
  bool merge = false;  // fit nothing; the summary of what the shards wrote
};

void run_batch_command(const BatchArgs& args, BatchRanksFactory make_ranks) {
  BatchOptions options;
  options.models = parse_model_list(args.models);
  options.fit =
      fit_options(args.metric, args.loss, args.per_channel, args.threads, args.sampling.seed, args.converge, args.fix);
  options.sampling = args.sampling.options();
  options.out_dir = args.out;
  options.jobs = args.jobs;
  options.resume = args.resume;
  options.merge_only = args.merge;
  const std::optional<Shard> shard =
      args.shard.empty() ? std::nullopt : std::optional<Shard>(option_value([&] { return parse_shard(args.shard); }));
  options.shared_folder = shard.has_value();
  check_output_folder(args.out);
  std::vector<BatchMaterial> materials = batch_materials(args.inputs, args.out);
  const std::unique_ptr<BatchRanks> ranks = make_ranks ? make_ranks() : std::make_unique<InProcessBatch>();
  if (shard && ranks->shares_materials()) fail("--shard and mpirun each divide the batch: use one of them");
  const bool prints = ranks->reports();
  // Held until the summary is written; the shards of one batch each hold their own.
  std::optional<OutputFolderLock> lock;
  if (prints && shard)
    lock.emplace(args.out, shard->index, shard->count);
  else if (prints)
    lock.emplace(args.out);
  if (shard) {
    const size_t all = materials.size();
    materials = shard_materials(materials, *shard);
    inform(stdout, "batch: shard {}/{}: {} of {}\n", shard->index, shard->count, materials.size(),
           count_of(all, "material"));
  }
  check_batch_keeps_models(materials, options);  // before anything is fitted (every MPI rank alike)
  if (prints)
    inform(stdout, "batch: {} x {}{}; results in {}\n", count_of(materials.size(), "material"),
           count_of(options.models.size(), "model"), ranks->plan(options, materials.size()), args.out);
  std::fflush(stdout);

  const auto started = std::chrono::steady_clock::now();
  BatchProgress progress(materials.size(), options.fit.metric, prints && ::isatty(::fileno(stderr)));
  std::vector<MaterialOutcome> outcomes;
  {
    const Ticker ticker([&] { progress.redraw(); });
    const BatchEvents events{[&](const BatchMaterial& m) { progress.started(m); },
                             [&](const MaterialOutcome& o) { progress.finished(o); }};
    outcomes = ranks->run(materials, options, prints ? events : BatchEvents{});
  }
  if (!prints) return;  // an MPI rank that only fitted: rank 0 reports
  progress.close();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

  const fs::path out(args.out);
  // A shard's summary would hide the others': the merge step writes the batch's.
  if (!shard) {
    write_file_atomic((out / "summary.json").string(),
                      json_text(batch_summary_json(outcomes, options, seconds), 2) + "\n");
    write_file_atomic((out / "summary.csv").string(), batch_summary_csv(outcomes, options));
  }
  const OutcomeCounts counts = count_outcomes(outcomes);
  const size_t failed = counts.failed, partial = counts.partial;
  say("batch: {} in {}: {} ok ({} already done), {} partly fitted, {} failed; {}\n",
      count_of(outcomes.size(), "material"), duration_text(seconds), counts.ok, counts.resumed, partial, failed,
      shard ? "summary by `brdffit batch ... --merge` once every shard is done"
            : "summary in " + (out / "summary.csv").string());
  if (failed + partial > 0)
    fail("{} of {} materials failed and {} were only partly fitted (see {})", failed, outcomes.size(), partial,
         shard ? "the lines above" : (out / "summary.json").string());
}

}  // namespace

void add_batch_command(CLI::App& app, BatchRanksFactory make_ranks) {
  auto batch = std::make_shared<BatchArgs>();
  CLI::App* batch_cmd = app.add_subcommand("batch", "Fit every model to many tables; one result document per material");
  batch_cmd->add_option("input", batch->inputs, "Tables, folders of tables, or manifests (one path per line)")
      ->required();
  add_models_option(batch_cmd, batch->models, "Comma-separated models, or 'all'");
  add_minimised_metric_option(batch_cmd, batch->metric);
  batch_cmd->add_option("--loss", batch->loss, "Robust loss per sample: none, huber, cauchy");
  batch_cmd->add_flag("--per-channel", batch->per_channel, "Fit shape parameters per colour channel");
  batch->converge.add_to(batch_cmd);
  batch->fix.add_to(batch_cmd);
  batch_cmd->add_option("-o,--out", batch->out, "Folder for the result documents and summary.{json,csv}");
  batch_cmd->add_option("-j,--jobs", batch->jobs, "Materials fitted at once")->check(kJobsRange);
  batch_cmd->add_option("--threads", batch->threads, "Threads per material (0: the cores shared among the jobs)")
      ->check(kThreadsRange);
  batch_cmd->add_flag("--resume", batch->resume, "Skip materials whose result document is complete and current");
  CLI::Option* shard = batch_cmd->add_option(
      "--shard", batch->shard,
      "Fit only share K of N (K/N, 0-based); auto: from a Slurm job array; auto/N: from a Kubernetes Indexed Job");
  batch_cmd->add_flag("--merge", batch->merge, "Fit nothing: write the summary of what the shards wrote")
      ->excludes(shard);
  batch->sampling.add_to(batch_cmd);
  batch_cmd->callback([batch, make_ranks] { run_batch_command(*batch, make_ranks); });
}

}  // namespace brdffit::cli
