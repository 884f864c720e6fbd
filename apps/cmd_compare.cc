// `brdffit compare`: rank models per material and over a set of result documents.
#include <string>
#include <vector>

#include "brdffit/compare.h"
#include "brdffit/io.h"
#include "brdffit/result_json.h"
#include "cli_common.h"
#include "commands.h"
#include "fit_options.h"

namespace brdffit::cli {

namespace {

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

}  // namespace

void add_compare_command(CLI::App& app) {
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
}

}  // namespace brdffit::cli
