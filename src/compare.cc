// Comparing models over fitted materials (see compare.h).
#include "brdffit/compare.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>

#include "brdffit/io.h"

namespace brdffit {

namespace {

namespace fs = std::filesystem;

MaterialRanking rank_material(const FitDocument& document, Metric metric) {
  MaterialRanking ranking;
  ranking.document = document.path;
  ranking.input = document.input_path;
  for (const FitResult& fit : document.results) {
    const double error = fit.metrics.get(metric);
    const bool ok = fit.ok && std::isfinite(error);
    ranking.models.push_back({fit.model, ok, ok ? error : NAN, 0, ok ? fit.verdict : Verdict::Failed});
  }
  std::stable_sort(ranking.models.begin(), ranking.models.end(), [](const RankedModel& a, const RankedModel& b) {
    if (a.ok != b.ok) return a.ok;
    return a.ok && a.error < b.error;
  });
  const int fitted = static_cast<int>(
      std::count_if(ranking.models.begin(), ranking.models.end(), [](const RankedModel& m) { return m.ok; }));
  for (size_t i = 0; i < ranking.models.size(); ++i) {
    RankedModel& m = ranking.models[i];
    if (!m.ok)
      m.rank = fitted + 1;
    else if (i > 0 && m.error == ranking.models[i - 1].error)
      m.rank = ranking.models[i - 1].rank;
    else
      m.rank = static_cast<int>(i) + 1;
  }
  const auto usable = std::find_if(ranking.models.begin(), ranking.models.end(),
                                   [](const RankedModel& m) { return m.ok && m.verdict == Verdict::Good; });
  if (usable != ranking.models.end()) ranking.best_usable = usable->model;
  return ranking;
}

double median(std::vector<double> xs) {
  if (xs.empty()) return NAN;
  std::sort(xs.begin(), xs.end());
  const size_t half = xs.size() / 2;
  return xs.size() % 2 ? xs[half] : 0.5 * (xs[half - 1] + xs[half]);
}

ModelSummary summarise_model(const std::string& model, const std::vector<MaterialRanking>& materials) {
  ModelSummary summary;
  summary.model = model;
  std::vector<double> errors;
  double rank_sum = 0.0;
  for (const MaterialRanking& material : materials) {
    const RankedModel* m = material.find(model);
    if (!m) continue;
    ++summary.materials;
    rank_sum += m->rank;
    if (!m->ok) {
      ++summary.failed;
      continue;
    }
    errors.push_back(m->error);
    if (m->verdict == Verdict::Poor) ++summary.poor;
    if (material.is_best_usable(*m)) ++summary.wins;
  }
  if (!errors.empty()) {
    double sum = 0.0;
    for (double e : errors) sum += e;
    summary.mean_error = sum / errors.size();
    summary.median_error = median(errors);
  }
  if (summary.materials > 0) summary.mean_rank = rank_sum / summary.materials;
  return summary;
}

std::string number(double x) { return std::isfinite(x) ? fmt::format("{:.4g}", x) : ""; }

// " poor" after a poor fit's error, nothing after a good one's.
const char* poor_mark(const RankedModel& m) { return m.verdict == Verdict::Poor ? " poor" : ""; }

}  // namespace

bool MaterialRanking::is_best_usable(const RankedModel& m) const {
  const RankedModel* best = find(best_usable);
  return best && m.ok && m.verdict == Verdict::Good && m.rank == best->rank;
}

const RankedModel* MaterialRanking::find(const std::string& model) const {
  for (const RankedModel& m : models)
    if (m.model == model) return &m;
  return nullptr;
}

Comparison compare_results(const std::vector<FitDocument>& documents, Metric metric) {
  Comparison comparison;
  comparison.metric = metric;
  std::map<std::string, int> name_count;
  for (const FitDocument& document : documents) ++name_count[material_name(document)];
  std::vector<std::string> models;  // in the order first met
  for (const FitDocument& document : documents) {
    MaterialRanking ranking = rank_material(document, metric);
    const std::string name = material_name(document);
    ranking.material = name_count[name] > 1 ? fs::path(document.path).stem().string() : name;
    for (const FitResult& fit : document.results)
      if (std::find(models.begin(), models.end(), fit.model) == models.end()) models.push_back(fit.model);
    comparison.materials.push_back(std::move(ranking));
  }
  for (const std::string& model : models) comparison.models.push_back(summarise_model(model, comparison.materials));
  std::stable_sort(comparison.models.begin(), comparison.models.end(),
                   [](const ModelSummary& a, const ModelSummary& b) {
                     return a.mean_rank != b.mean_rank ? a.mean_rank < b.mean_rank : a.model < b.model;
                   });
  return comparison;
}

Metric common_metric(const std::vector<FitDocument>& documents) {
  std::optional<Metric> common;
  for (const FitDocument& document : documents) {
    const std::optional<Metric> metric = parse_metric(document.json.value("metric", ""));
    if (!metric || (common && *common != *metric)) return Metric::Cosine;
    common = metric;
  }
  return common.value_or(Metric::Cosine);
}

std::string comparison_text(const Comparison& c) {
  const std::string metric = metric_name(c.metric);
  std::string text = fmt::format("{:<18} {:>6} {:>6} {:>6} {:>12} {:>12} {:>9} {:>7}\n", "model", "fitted", "poor",
                                 "failed", "mean " + metric, "median " + metric, "mean rank", "best on");
  for (const ModelSummary& m : c.models)
    text += fmt::format("{:<18} {:>6} {:>6} {:>6} {:>12} {:>12} {:>9.2f} {:>7}\n", m.model, m.materials - m.failed,
                        m.poor, m.failed, number(m.mean_error), number(m.median_error), m.mean_rank, m.wins);
  text += fmt::format("ranked by the {} metric over {}\n", metric, count_of(c.materials.size(), "material"));
  for (const MaterialRanking& material : c.materials) {
    text += fmt::format("\n{}:", material.material);
    for (const RankedModel& m : material.models)
      text += m.ok ? fmt::format("  {}. {} {:.4g}{}", m.rank, m.model, m.error, poor_mark(m))
                   : fmt::format("  -. {} failed", m.model);
    if (material.best_usable.empty()) text += "  (no usable fit)";
    text += "\n";
  }
  return text;
}

std::string comparison_csv(const Comparison& c) {
  std::string csv = "model,fitted,poor,failed,mean,median,mean_rank,wins";
  for (const MaterialRanking& material : c.materials)
    csv += "," + csv_field(material.material) + "," + csv_field(material.material + " rank");
  csv += "\n";
  for (const ModelSummary& m : c.models) {
    csv += fmt::format("{},{},{},{},{},{},{:.6g},{}", csv_field(m.model), m.materials - m.failed, m.poor, m.failed,
                       std::isfinite(m.mean_error) ? fmt::format("{:.9g}", m.mean_error) : "",
                       std::isfinite(m.median_error) ? fmt::format("{:.9g}", m.median_error) : "", m.mean_rank, m.wins);
    for (const MaterialRanking& material : c.materials) {
      const RankedModel* r = material.find(m.model);
      csv += !r ? ",," : fmt::format(",{},{}", r->ok ? fmt::format("{:.9g}", r->error) : "", r->rank);
    }
    csv += "\n";
  }
  return csv;
}

nlohmann::json comparison_json(const Comparison& c) {
  nlohmann::json models = nlohmann::json::array(), materials = nlohmann::json::array();
  for (const ModelSummary& m : c.models)
    models.push_back({{"model", m.model},
                      {"materials", m.materials},
                      {"poor", m.poor},
                      {"failed", m.failed},
                      {"mean_error", number_or_null(m.mean_error)},
                      {"median_error", number_or_null(m.median_error)},
                      {"mean_rank", number_or_null(m.mean_rank)},
                      {"wins", m.wins}});
  for (const MaterialRanking& material : c.materials) {
    nlohmann::json ranked = nlohmann::json::array();
    for (const RankedModel& r : material.models)
      ranked.push_back({{"model", r.model},
                        {"ok", r.ok},
                        {"error", number_or_null(r.error)},
                        {"rank", r.rank},
                        {"verdict", verdict_name(r.verdict)}});
    materials.push_back(
        {{"material", material.material},
         {"document", material.document},
         {"input", material.input},
         {"best_usable", material.best_usable.empty() ? nlohmann::json(nullptr) : nlohmann::json(material.best_usable)},
         {"models", ranked}});
  }
  return {{"metric", metric_name(c.metric)}, {"models", models}, {"materials", materials}};
}

std::string comparison_markdown(const Comparison& c) {
  const std::string metric = metric_name(c.metric);
  std::string md =
      fmt::format("Models ranked by the {} metric over {}.\n\n", metric, count_of(c.materials.size(), "material"));
  md += fmt::format("| model | fitted | poor | failed | mean {0} | median {0} | mean rank | best on |\n", metric);
  md += "|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const ModelSummary& m : c.models)
    md +=
        fmt::format("| {} | {} | {} | {} | {} | {} | {:.2f} | {} |\n", escape_markdown(m.model), m.materials - m.failed,
                    m.poor, m.failed, number(m.mean_error), number(m.median_error), m.mean_rank, m.wins);
  md += "\n| material |";
  for (const ModelSummary& m : c.models) md += " " + escape_markdown(m.model) + " |";
  md += "\n|---|";
  for (size_t i = 0; i < c.models.size(); ++i) md += "---:|";
  md += "\n";
  for (const MaterialRanking& material : c.materials) {
    md += "| " + escape_markdown(material.material) + " |";
    for (const ModelSummary& m : c.models) {
      const RankedModel* r = material.find(m.model);
      if (!r)
        md += " |";
      else if (!r->ok)
        md += " failed |";
      else
        md += fmt::format(material.is_best_usable(*r) ? " **{:.4g}** ({}){} |" : " {:.4g} ({}){} |", r->error, r->rank,
                          poor_mark(*r));
    }
    md += "\n";
  }
  return md;
}

}  // namespace brdffit
