// `brdffit fit`: fit models to a measured table and rank them; `brdffit score`: every metric of
// given parameters on a table, with the same sampling.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/io.h"
#include "brdffit/material_export.h"
#include "brdffit/measured.h"
#include "brdffit/published_fits.h"
#include "brdffit/registry.h"
#include "brdffit/result_json.h"
#include "cli_common.h"
#include "commands.h"
#include "fit_options.h"

namespace brdffit::cli {

namespace {

void print_ranking(const std::vector<FitResult>& results, Metric metric) {
  std::vector<const FitResult*> order;
  for (const FitResult& r : results) order.push_back(&r);
  std::stable_sort(order.begin(), order.end(), [metric](const FitResult* a, const FitResult* b) {
    if (a->ok != b->ok) return a->ok;
    return a->metrics.get(metric) < b->metrics.get(metric);
  });
  // Every metric of kMetrics: typical (how far off a typical sample is, relative to its value) is
  // the column behind most poor verdicts: it explains a poor fit ranked above a good one.
  std::string header = fmt::format("{:>4}  {:<18} {:<7}", "rank", "model", "verdict");
  for (const MetricInfo& info : kMetrics) header += fmt::format(" {:>{}}", info.name, info.width);
  say("{} {:>6} {:>8}\n", header, "iters", "seconds");
  int rank = 0;
  for (const FitResult* r : order) {
    if (!r->ok) {
      say("{:>4}  {:<18} failed: {}\n", "-", r->model, r->error);
      continue;
    }
    std::string row = fmt::format("{:>4}  {:<18} {:<7}", ++rank, r->model, verdict_name(r->verdict));
    for (const MetricInfo& info : kMetrics)
      row += fmt::format(" {:>{}.{}g}", r->metrics.*info.value, info.width, info.digits);
    say("{} {:>6} {:>8.2f}\n", row, r->iterations, r->seconds);
    say("      {}\n", format_parameters(*r));
    print_warnings(*r, "      ");
  }
  say("ranked by the {} metric\n", metric_name(metric));
}

// fit's models without -m: the diffuse baseline (lambert) and its rough-surface form
// (oren-nayar), the microfacet standard (ggx), the two classics of Ngan et al.'s comparison
// (cook-torrance, ward) and the glTF material that `export` writes unconverted (gltf). Seconds
// on a table, where all of them take minutes (the anisotropic and many-lobe ones dominate).
const std::string& fit_default_models() {
  static const std::string list = model_list({"lambert", "oren-nayar", "ggx", "cook-torrance", "ward", "gltf"});
  return list;
}

struct FitArgs {
  std::string data;
  std::string models = fit_default_models();
  std::string metric = "cosine";
  std::string loss = "none";
  SamplingArgs sampling;
  int threads = 0;
  bool per_channel = false;
  ConvergeArg converge;
  FixArg fix;
  std::string out, csv;
  bool json = false;
};

void run_fit(const FitArgs& args) {
  // The command line first, then the outputs, then the work.
  check_table_argument(args.data, "fit");
  FitOptions options =
      fit_options(args.metric, args.loss, args.per_channel, args.threads, args.sampling.seed, args.converge, args.fix);
  const std::vector<const Model*> models = parse_model_list(args.models);
  check_outputs({args.data}, {args.out, args.csv});
  stage("reading {}", args.data);
  const SampleSet data = load_samples(args.data, args.sampling.options());
  if (data.empty()) fail("{}: no samples left to fit (check --max-angle)", args.data);
  if (!args.json) inform(stdout, "{}: {} samples ({} weights)\n", args.data, data.size(), data.weighting);

  stage("fitting {} to {} samples", count_of(models.size(), "model"), data.size());
  ModelProgress progress;
  progress.attach(options);
  const std::vector<FitResult> results = fit_models(models, data, options);
  progress.clear();
  const std::string document = args.json || !args.out.empty()
                                   ? json_text(fit_document_json(args.data, data, options, results), 2) + "\n"
                                   : std::string();
  if (args.json)
    say("{}", document);
  else
    print_ranking(results, options.metric);
  // Outputs only once every model is done, each whole or not at all.
  if (!args.out.empty()) write_file_atomic(args.out, document);
  if (!args.csv.empty()) write_file_atomic(args.csv, fit_results_csv(results));
  if (std::none_of(results.begin(), results.end(), [](const FitResult& r) { return r.ok; }))
    fail("{}: every model failed to fit", args.data);
}

struct ScoreArgs {
  std::string data, model, published, material, name;
  std::vector<std::string> params;
  SamplingArgs sampling;
  bool json = false;
};

// "cosine 0.1  log 0.2  ...": every metric of kMetrics.
std::string metrics_line(const Metrics& m) {
  std::string line;
  for (const MetricInfo& info : kMetrics)
    line += fmt::format("{}{} {:.6g}", line.empty() ? "" : "  ", info.name, m.*info.value);
  return line;
}

// --published: every model the material's published fit maps onto, scored on the table.
void run_score_published(const ScoreArgs& args, const SampleSet& data) {
  const std::string line = !args.name.empty() ? args.name : args.material;
  const std::string material = line.empty() ? table_material_name(args.data) : line;
  const std::vector<PublishedFit> fits = find_published_fits(args.published, material);
  nlohmann::json out = nlohmann::json::array();
  for (const PublishedFit& fit : fits) {
    const Metrics m = evaluate_metrics(*find_model(fit.model), fit.values, data);
    if (args.json) {
      out.push_back({{"material", material},
                     {"model", fit.model},
                     {"published", fit.term},
                     {"values", fit.values},
                     {"metrics", metrics_json(m)}});
    } else {
      say("{} ({} of {} in {}) on {} ({} samples, {} weights)\n{}\n", fit.model, fit.term, material, args.published,
          args.data, data.size(), data.weighting, metrics_line(m));
    }
  }
  if (args.json) say("{}\n", json_text(out));
}

void run_score(const ScoreArgs& args) {
  // --published F.fit names its line with --name (or --material, issue 12's spelling);
  // otherwise --material is a material file (material_formats()) and --name its material.
  if (!args.published.empty()) {
    if (!args.model.empty()) fail_usage("score: give -m or --published, not both");
    if (!args.material.empty() && !args.name.empty()) fail_usage("score: with --published, give the line's name once");
  } else if (args.model.empty() && args.material.empty()) {
    fail_usage("score: give -m MODEL (with --param) or --material FILE, or --published FILE.fit");
  }
  check_table_argument(args.data, "score");
  const Model* model = args.published.empty() && !args.model.empty() ? &named_model(args.model, "score") : nullptr;
  std::vector<double> values;
  if (!args.published.empty()) {
    // scored below, model by model
  } else if (!args.material.empty()) {
    std::vector<std::string> warnings;
    const Material material = material_for_scoring(args.material, args.name, args.model, warnings);
    for (const std::string& warning : warnings) say(stderr, "warning: {}\n", warning);
    model = find_model(material.model);
    values = material.values;
  } else {
    values = option_value([&] { return parameter_values(*model, args.params); });
  }
  const SampleSet data = load_samples(args.data, args.sampling.options());
  if (data.empty()) fail("{}: no samples left to score (check --max-angle)", args.data);
  if (!model) return run_score_published(args, data);
  const Metrics m = evaluate_metrics(*model, values, data);
  if (args.json) {
    say("{}\n", json_text(nlohmann::json{{"metrics", metrics_json(m)}}));
    return;
  }
  say("{} on {} ({} samples)\n{}\n", model->name(), args.data, data.size(), metrics_line(m));
}

}  // namespace

void add_fit_commands(CLI::App& app) {
  auto fit = std::make_shared<FitArgs>();
  CLI::App* fit_cmd = app.add_subcommand("fit", "Fit models to a measured table (MERL, RGL, CSV) and rank them");
  fit_cmd->add_option("data", fit->data, "Measured table")->required();
  add_models_option(fit_cmd, fit->models,
                    "Comma-separated models, or 'all' (every model `brdffit models` lists: minutes on a large "
                    "table). Default: the diffuse baseline and its rough form, the microfacet standard, the two "
                    "classics of Ngan et al. 2005 and the glTF material, seconds on a table");
  add_minimised_metric_option(fit_cmd, fit->metric, " (all are reported)");
  fit_cmd->add_option("--loss", fit->loss, "Robust loss per sample: none, huber, cauchy");
  fit_cmd->add_flag("--per-channel", fit->per_channel, "Fit shape parameters per colour channel");
  fit->converge.add_to(fit_cmd);
  fit->fix.add_to(fit_cmd);
  fit_cmd->add_option("--threads", fit->threads, "Threads (0: every core)")->check(kThreadsRange);
  fit_cmd->add_option("-o,--out", fit->out, "Write the result document (JSON)");
  fit_cmd->add_flag("--json", fit->json, "Print the result document on stdout instead of the ranking");
  fit_cmd->add_option("--csv", fit->csv, "Write one row per model (CSV)");
  fit->sampling.add_to(fit_cmd);
  fit_cmd->callback([fit] { run_fit(*fit); });

  auto score = std::make_shared<ScoreArgs>();
  CLI::App* score_cmd = app.add_subcommand("score", "Every error metric of given model parameters on a table");
  score_cmd->add_option("data", score->data, "Measured table")->required();
  add_models_option(score_cmd, score->model, "The model (with --material: convert the material to it)");
  score_cmd->add_option(
      "--published", score->published,
      "A BBM .fit file of published parameters: scores the material's line for every model it maps onto");
  score_cmd->add_option("--material", score->material,
                        "Score the material of a " + material_format_list(&MaterialFormatInfo::files) +
                            " file (with --published: the line to score)");
  score_cmd->add_option(
      "--name", score->name,
      "The material to score when the file holds several (--published: default the table's file name)");
  score_cmd->add_option("--param", score->params, "NAME=VALUE (colours: one value or R,G,B); repeatable");
  score_cmd->add_flag("--json", score->json, "Print JSON");
  score->sampling.add_to(score_cmd);
  score_cmd->callback([score] { run_score(*score); });
}

}  // namespace brdffit::cli
