// `brdffit batch`: fit many tables; `compare`: rank models over result documents; `export`: a fit
// as a glTF 2.0, OpenPBR (MaterialX) or Mitsuba 3 material.
#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>
#include <set>
#include <thread>

#include "brdffit/batch.h"
#include "brdffit/batch_shard.h"
#ifdef BRDFFIT_MPI_BATCH
#include "brdffit/batch_mpi.h"
#endif
#include "brdffit/compare.h"
#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/material_export.h"
#include "brdffit/registry.h"
#include "brdffit/result_json.h"
#include "cli_common.h"
#include "commands.h"
#include "fit_options.h"

namespace brdffit::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// The models' warnings of a batch: the first of each kind, and how many more like it. Two
// warnings are alike when they differ only in their numbers (the material's values): a batch of
// 300 materials where roughness sits at its bound prints that once, "(and 299 more like it)".
class RepeatedWarnings {
 public:
  void add(const std::string& material, const std::string& model, const std::string& warning) {
    static const std::regex number(R"([-+]?[0-9]*\.?[0-9]+([eE][-+]?[0-9]+)?)");
    const std::string kind = model + ": " + std::regex_replace(warning, number, "#");
    const auto [seen, first] = repeats_.try_emplace(kind, 0);
    if (first)
      order_.push_back({kind, fmt::format("    {} {}: warning: {}", material, model, warning)});
    else
      ++seen->second;
  }
  // Each kind once, with its count; then forgets them.
  void print() {
    for (const auto& [kind, line] : order_)
      say(stderr, "{}{}\n", line, repeats_[kind] > 0 ? fmt::format(" (and {} more like it)", repeats_[kind]) : "");
    order_.clear();
    repeats_.clear();
  }

 private:
  std::vector<std::pair<std::string, std::string>> order_;  // kind, its first line
  std::map<std::string, size_t> repeats_;                   // kind, how many more
};

// Progress of a batch on stderr: a line per finished material, and on a terminal a bar below
// them with counts, elapsed time and ETA, redrawn every second; the models' warnings once per
// kind at the end (RepeatedWarnings). With -q only the failures and the warnings; with -v
// every warning where it arises.
class BatchProgress {
 public:
  BatchProgress(size_t total, Metric metric, bool terminal)
      : total_(total), metric_(metric), terminal_(terminal && verbosity() != Verbosity::Quiet), start_(Clock::now()) {}

  void started(const BatchMaterial& material) {
    const std::lock_guard<std::mutex> lock(mutex_);
    running_.insert(material.name);
    draw_bar();
  }

  void finished(const MaterialOutcome& o) {
    const std::lock_guard<std::mutex> lock(mutex_);
    running_.erase(o.material.name);
    ++done_;
    if (o.resumed) ++resumed_;
    if (o.status != MaterialStatus::Ok) ++failed_;
    if (!o.resumed) fitting_seconds_ = elapsed();
    std::string line = fmt::format("[{}/{}] {}: ", done_, total_, o.material.name);
    if (o.status == MaterialStatus::Failed) {
      line += "FAILED: " + o.error;
    } else {
      line += o.resumed ? "already done" : fmt::format("{} in {:.1f} s", material_status_name(o.status), o.seconds);
      const int poor = count_poor(o.fits);
      if (const FitResult* best = best_result(o.fits, metric_))
        line += fmt::format(", best {} ({} {:.4g})", best->model, metric_name(metric_), best->metrics.get(metric_));
      else if (!o.fits.empty())
        line += ", no usable fit";
      if (poor > 0) line += fmt::format(" ({} poor)", poor);
      if (o.status == MaterialStatus::Partial) line += "; failed: " + o.error;
    }
    if (!terminal_ && fitted() > 0 && done_ < total_) line += ", ETA " + duration_text(eta());
    // A poor fit and a parameter on a bound or not identifiable: a warning line each, with -v
    // here, else once per kind at the end.
    for (const FitResult& fit : o.fits)
      for (const std::string& warning : fit.warnings)
        if (verbosity() == Verbosity::Verbose)
          line += fmt::format("\n    {} {}: warning: {}", o.material.name, fit.model, warning);
        else
          warnings_.add(o.material.name, fit.model, warning);
    clear_bar();
    if (verbosity() != Verbosity::Quiet || o.status != MaterialStatus::Ok) say(stderr, "{}\n", line);
    draw_bar();
  }

  void redraw() {
    const std::lock_guard<std::mutex> lock(mutex_);
    draw_bar();
  }

  void close() {
    const std::lock_guard<std::mutex> lock(mutex_);
    clear_bar();
    warnings_.print();
  }

 private:
  double elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  size_t fitted() const { return done_ - resumed_; }
  // Materials still to do at the rate fitted ones went so far (resumed ones take no time).
  double eta() const { return fitting_seconds_ / fitted() * (total_ - done_); }

  void clear_bar() {
    if (terminal_) rewind_line();
  }

  void draw_bar() {
    if (!terminal_) return;
    constexpr int kWidth = 30;
    const int filled = total_ ? static_cast<int>(kWidth * done_ / total_) : kWidth;
    std::string running;
    for (const std::string& name : running_) running += (running.empty() ? "" : ", ") + name;
    if (running.size() > 40) running = running.substr(0, 37) + "...";
    rewind_line();
    say(stderr, "[{}{}] {}/{}  failed {}  {}{}  {}", std::string(filled, '#'), std::string(kWidth - filled, '-'), done_,
        total_, failed_, duration_text(elapsed()),
        fitted() > 0 && done_ < total_ ? ", ETA " + duration_text(eta()) : std::string(), running);
    std::fflush(stderr);
  }

  std::mutex mutex_;
  const size_t total_;
  const Metric metric_;
  const bool terminal_;
  const Clock::time_point start_;
  size_t done_ = 0, resumed_ = 0, failed_ = 0;
  double fitting_seconds_ = 0.0;  // elapsed when the last fitted (not resumed) material finished
  std::set<std::string> running_;
  RepeatedWarnings warnings_;
};

// Calls tick() every second on its own thread until destroyed.
class Ticker {
 public:
  explicit Ticker(std::function<void()> tick)
      : thread_([this, tick] {
          std::unique_lock<std::mutex> lock(mutex_);
          while (!stop_.wait_for(lock, std::chrono::seconds(1), [this] { return stopping_; })) tick();
        }) {}
  ~Ticker() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    stop_.notify_one();
    thread_.join();
  }

 private:
  std::mutex mutex_;
  std::condition_variable stop_;
  bool stopping_ = false;
  std::thread thread_;
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

void run_batch_command(const BatchArgs& args) {
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
#ifdef BRDFFIT_MPI_BATCH
  // brdffit-mpi: the ranks of this MPI job share the materials; rank 0 hands them out, holds the
  // lock and writes the summary, the others only fit.
  MpiBatch ranks;
  if (shard) fail("--shard and mpirun each divide the batch: use one of them");
  const bool prints = ranks.rank() == 0;
#else
  const bool prints = true;
#endif
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
#ifdef BRDFFIT_MPI_BATCH
  if (prints)
    inform(stdout, "batch: {} x {} over {} MPI ranks, one material at a time each; results in {}\n",
           count_of(materials.size(), "material"), count_of(options.models.size(), "model"), ranks.size() - 1,
           args.out);
#else
  const BatchPlan plan = plan_batch(options, materials.size());
  inform(stdout, "batch: {} x {}, {} at a time with {} threads each; results in {}\n",
         count_of(materials.size(), "material"), count_of(options.models.size(), "model"), plan.jobs, plan.threads,
         args.out);
#endif
  std::fflush(stdout);

  const auto started = Clock::now();
  BatchProgress progress(materials.size(), options.fit.metric, prints && ::isatty(::fileno(stderr)));
  std::vector<MaterialOutcome> outcomes;
  {
    const Ticker ticker([&] { progress.redraw(); });
    const BatchEvents events{[&](const BatchMaterial& m) { progress.started(m); },
                             [&](const MaterialOutcome& o) { progress.finished(o); }};
#ifdef BRDFFIT_MPI_BATCH
    outcomes = ranks.run(materials, options, prints ? events : BatchEvents{});
#else
    outcomes = run_batch(materials, options, events);
#endif
  }
  if (!prints) return;  // an MPI rank that only fitted: rank 0 reports
  progress.close();
  const double seconds = std::chrono::duration<double>(Clock::now() - started).count();

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

struct CompareArgs {
  std::vector<std::string> results;
  std::string metric, csv, markdown;
  bool json = false;
};

void run_compare(const CompareArgs& args) {
  check_document_arguments(args.results);
  check_outputs(args.results, {args.csv, args.markdown});
  const std::vector<FitDocument> documents = read_fit_documents(args.results);
  check_outputs(document_paths(documents), {args.csv, args.markdown});
  const Metric metric = args.metric.empty() ? common_metric(documents) : metric_from_name(args.metric, "--metric");
  const Comparison comparison = compare_results(documents, metric);
  if (args.json)
    say("{}\n", json_text(comparison_json(comparison), 2));
  else
    say("{}", comparison_text(comparison));
  if (!args.csv.empty()) write_file_atomic(args.csv, comparison_csv(comparison));
  if (!args.markdown.empty()) write_file_atomic(args.markdown, comparison_markdown(comparison));
}

struct ExportArgs {
  std::string result, model, format, out;
  bool force = false;
};

void run_export(const ExportArgs& args) {
  ExportRequest request;
  request.format = option_value([&] { return material_format(args.format, args.out); });
  request.model = args.model.empty() ? args.model : named_model(args.model, "export").name();
  request.force = args.force;
  check_document_arguments({args.result});
  check_outputs({args.result}, {args.out});
  const MaterialExport exported = export_material(read_fit_document(args.result), request);
  for (const std::string& warning : exported.warnings) say(stderr, "warning: {}\n", warning);
  write_file_atomic(args.out, exported.text);
  const Model& model = *find_model(exported.material.model);
  std::string values;
  size_t offset = 0;
  for (const ParamSpec& p : model.parameters()) {
    const std::vector<double> value(exported.material.values.begin() + offset,
                                    exported.material.values.begin() + offset + p.channels);
    values += " " + p.name + "=" + format_values(value, "{:.4g}");
    offset += p.channels;
  }
  say("wrote {}: the {} material{}\n", args.out, model.name(), values);
  if (!exported.converted) {
    say("  the {} fit unchanged ({} error {:.4g})\n", exported.source_model, exported.metric, exported.fit_error);
    return;
  }
  say("  converted from the {} fit {} ({} error {:.4g}); on the original data, all samples: converted {:.4g}, "
      "the {} fit {:.4g}; the converted material against the {} fit on fixed directions: {} {:.4g}\n",
      exported.source_model, exported.conversion, exported.metric, exported.fit_error, exported.converted_error,
      exported.source_model, exported.source_error_on_data, exported.source_model, exported.metric,
      exported.converted_vs_fit);
}

}  // namespace

void add_batch_commands(CLI::App& app) {
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
  batch_cmd->callback([batch] { run_batch_command(*batch); });

  auto compare = std::make_shared<CompareArgs>();
  CLI::App* compare_cmd = app.add_subcommand("compare", "Rank models per material and over a set of result documents");
  compare_cmd->add_option("results", compare->results, "Result documents, or folders of them (a batch's --out)")
      ->required();
  add_ranking_metric_option(compare_cmd, compare->metric);
  compare_cmd->add_option("--csv", compare->csv,
                          "Write the per-model table with every material's error and rank (CSV)");
  compare_cmd->add_option("--markdown", compare->markdown, "Write the tables as Markdown");
  compare_cmd->add_flag("--json", compare->json, "Print the comparison as JSON instead of the tables");
  compare_cmd->callback([compare] { run_compare(*compare); });

  auto export_args = std::make_shared<ExportArgs>();
  CLI::App* export_cmd = app.add_subcommand(
      "export", "Write a fit as the renderer's material: glTF 2.0, OpenPBR (MaterialX) or Mitsuba 3 principled");
  export_cmd->add_option("result", export_args->result, "Result document (from fit or batch)")->required();
  add_models_option(export_cmd, export_args->model,
                    "The fit to export (default: the format's own: gltf, gltf-specular or gltf-clearcoat, openpbr, "
                    "mitsuba-principled; "
                    "another fit is converted and its error reported)");
  export_cmd->add_option("--format", export_args->format, "gltf, openpbr or mitsuba (default: from --out's extension)");
  export_cmd->add_option("-o,--out", export_args->out, "File to write (.gltf, .mtlx, .xml)")->required();
  export_cmd->add_flag("--force", export_args->force, "Export a fit whose verdict is poor or failed (with a warning)");
  export_cmd->callback([export_args] { run_export(*export_args); });
}

}  // namespace brdffit::cli
