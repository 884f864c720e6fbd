// Comparing models over a set of fitted materials: per material the models ranked by one
// metric; per model the mean and median error, the mean rank and the number of materials on
// which it is best. The library side of `brdffit compare`, also used by the report.
//
// Ranking: models that fitted are ranked by ascending error, equal errors sharing the better
// rank (1, 2, 2, 4); models whose fit failed (or whose error is not a number) share the place
// after every model that fitted. Mean and median run over the materials where the model fitted;
// the mean rank over every material that has the model, failures included, so that failing is
// not better than fitting badly. A model is best on a material when it is the best-ranked of
// the fits judged good there (a poor fit can rank first by the metric, never be best).
#pragma once

#include <string>
#include <vector>

#include "brdffit/metric.h"
#include "brdffit/result_json.h"

namespace brdffit {

struct RankedModel {
  std::string model;
  bool ok = false;
  double error = NAN;  // under the comparison's metric; NaN when the fit failed
  int rank = 0;
  Verdict verdict = Verdict::Failed;  // as the document says: a poor fit is ranked but marked
};

struct MaterialRanking {
  std::string material;             // the input's file name without extension (the document's, if two share it)
  std::string document;             // path of the result document
  std::string input;                // the measured table the document names
  std::vector<RankedModel> models;  // best first; failed fits last
  std::string best_usable;          // the best-ranked good fit; empty when every fit is poor or failed

  // Whether m is a good fit that ranks with the best good fit (ties share it).
  bool is_best_usable(const RankedModel& m) const;

  const RankedModel* find(const std::string& model) const;
};

struct ModelSummary {
  std::string model;
  int materials = 0;                            // materials whose document has this model
  int failed = 0;                               // of those, where its fit failed
  int poor = 0;                                 // of those, where its fit was judged poor
  double mean_error = NAN, median_error = NAN;  // over the materials where it fitted
  double mean_rank = NAN;
  int wins = 0;  // materials where it is the best usable (good) fit: a poor fit is never best
};

struct Comparison {
  Metric metric = Metric::Cosine;
  std::vector<MaterialRanking> materials;  // in document order
  std::vector<ModelSummary> models;        // best mean rank first (then by name)
};

Comparison compare_results(const std::vector<FitDocument>& documents, Metric metric);

// The metric the documents were fitted with when they agree, else cosine.
Metric common_metric(const std::vector<FitDocument>& documents);

// Plain-text tables for the terminal: the per-model summary, then each material's ranking.
std::string comparison_text(const Comparison& comparison);
// One row per model: model,fitted,failed,mean,median,mean_rank,wins, then for each material its
// error and its rank ("<material>", "<material> rank"); empty cells where a model has no number.
std::string comparison_csv(const Comparison& comparison);
// The per-model summary and a materials x models table of errors with ranks, the best in bold.
std::string comparison_markdown(const Comparison& comparison);
// The whole comparison as JSON (`brdffit compare --json`): {"metric", "models": [summary...],
// "materials": [{"material", "document", "input", "models": [{"model", "ok", "error", "rank",
// "verdict"}...]}...]}; errors that are not numbers are null.
nlohmann::json comparison_json(const Comparison& comparison);

}  // namespace brdffit
