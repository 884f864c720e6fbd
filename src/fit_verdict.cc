// A fitted result's verdict and warnings (fit_stages.h, judge), and the bounds as results report them.
#include <fmt/format.h>
#include <algorithm>
#include <cmath>

#include "brdffit/fit_stages.h"

namespace brdffit {

const char* verdict_name(Verdict verdict) {
  switch (verdict) {
    case Verdict::Good: return "good";
    case Verdict::Poor: return "poor";
    case Verdict::Failed: break;
  }
  return "failed";
}

namespace fitting {

namespace {

std::string format_value(const std::vector<double>& v) {
  if (v.size() == 1) return fmt::format("{:.4g}", v[0]);
  return fmt::format("[{:.4g}, {:.4g}, {:.4g}]", v[0], v[1], v[2]);
}

}  // namespace

bool at_upper_bound(const ParamSpec& p, double value) {
  return p.spacing == Spacing::Log ? value >= p.upper * std::pow(p.lower / p.upper, 1e-6)
                                   : value >= p.upper - 1e-6 * (p.upper - p.lower);
}
bool at_bound(const ParamSpec& p, double value) {
  const bool at_lower = p.spacing == Spacing::Log ? value <= p.lower * std::pow(p.upper / p.lower, 1e-6)
                                                  : value <= p.lower + 1e-6 * (p.upper - p.lower);
  return at_lower || at_upper_bound(p, value);
}

bool same_optimum(const std::vector<ValueSlot>& slots, const std::vector<double>& a, const std::vector<double>& b) {
  constexpr double kSameFraction = 1e-5;
  for (size_t i = 0; i < slots.size(); ++i) {
    const ParamSpec& p = *slots[i].param;
    const bool by_ratio = p.spacing == Spacing::Log && a[i] > 0.0 && b[i] > 0.0 && p.lower > 0.0;
    const double distance = by_ratio ? std::abs(std::log(a[i] / b[i])) / std::log(p.upper / p.lower)
                                     : std::abs(a[i] - b[i]) / (p.upper - p.lower);
    if (!(distance <= kSameFraction)) return false;
  }
  return true;
}

bool same_cost(double a, double b) {
  return std::isfinite(a) && std::isfinite(b) && std::abs(a - b) <= 1e-6 * std::max(std::abs(a), std::abs(b));
}

constexpr double kLaterStartErrors = 4.0;
bool later_start_surely_costlier(const std::vector<double>& terms, const std::vector<double>& best_terms,
                                 double best_cost, size_t free_values) {
  const size_t count = terms.size();
  if (count < 2 || best_terms.size() != count) return false;
  double difference = 0.0;
  for (size_t i = 0; i < count; ++i) difference += terms[i] - best_terms[i];
  const double mean = difference / static_cast<double>(count);
  double squares = 0.0;
  for (size_t i = 0; i < count; ++i) squares += std::pow(terms[i] - best_terms[i] - mean, 2);
  const double standard_error = 0.5 * std::sqrt(squares * static_cast<double>(count) / static_cast<double>(count - 1));
  const double optimism = 2.0 * static_cast<double>(free_values) / static_cast<double>(count) * best_cost;
  return 0.5 * difference > kLaterStartErrors * standard_error + optimism;
}

std::vector<size_t> importance_subset_draws(size_t subsample, size_t samples, size_t polish_after) {
  std::vector<size_t> draws;
  for (size_t n = 10 * std::max<size_t>(subsample, 1); n < samples; n *= 10) draws.push_back(n);
  if (!draws.empty() && draws.back() < polish_after && polish_after <= samples / 2) draws.back() = polish_after;
  return draws;
}

bool subset_covers(const std::vector<Sample>& subset, const std::vector<Sample>& samples) {
  constexpr double kSubsetCoverage = 0.1;
  auto weight_sum = [](const std::vector<Sample>& set) {
    double sum = 0.0;
    for (const Sample& s : set) sum += s.weight;
    return sum;
  };
  const double all = weight_sum(samples);
  return all > 0.0 && std::abs(weight_sum(subset) / all - 1.0) <= kSubsetCoverage;
}

void judge(const Model& model, const FitResult* baseline, double zero_error, Metric metric, bool isotropic_data,
           FitResult& r) {
  constexpr double kPoorRatio = 1.05, kPoorUnexplained = 0.85, kPoorTypical = 1.0, kPoorClampedUnexplained = 0.25;
  const std::vector<Metric> kJudgedMetrics = judged_metrics();  // kMetrics (metric.h)
  if (!r.ok) {
    r.verdict = Verdict::Failed;
    return;
  }
  r.verdict = Verdict::Good;
  const double error = r.metrics.get(metric);
  if (baseline && baseline->ok && baseline->model != r.model) {
    for (const Metric judged : kJudgedMetrics) {
      const double own = r.metrics.get(judged), base = baseline->metrics.get(judged);
      if (!(own > kPoorRatio * base)) continue;
      r.verdict = Verdict::Poor;
      r.warnings.push_back(
          fmt::format("poor fit: its {} error {:.4g} is {:.2f}x that of Lambert ({:.4g}) on the same samples{}",
                      metric_name(judged), own, own / std::max(base, 1e-300), base,
                      judged == metric ? "" : " (not the metric it minimised)"));
    }
  }
  if (zero_error > 0.0 && error > kPoorUnexplained * zero_error) {
    r.verdict = Verdict::Poor;
    r.warnings.push_back(
        fmt::format("poor fit: its {} error {:.4g} is {:.0f}% of the data's own scale ({:.4g}, the "
                    "error of predicting zero): it misses what dominates the data",
                    metric_name(metric), error, 100.0 * error / zero_error, zero_error));
  }
  if (r.metrics.typical > kPoorTypical) {
    r.verdict = Verdict::Poor;
    r.warnings.push_back(
        fmt::format("poor fit: a typical sample is off by {:.0f}% of its own value: it misses the "
                    "body of the data",
                    100.0 * r.metrics.typical));
  }
  for (const ParameterEstimate& p : r.parameters) {
    const ParamSpec* spec = model.find_parameter(p.name);
    if (spec && spec->role == Role::Orientation && isotropic_data) {
      r.warnings.push_back(
          fmt::format("{} is not identifiable: the data are isotropic (the same at every azimuth), so the lobe has "
                      "no orientation to fit; use the isotropic model unless the widths differ",
                      p.name));
      continue;
    }
    if (spec && spec->role == Role::Anisotropy && isotropic_data) {
      r.warnings.push_back(
          fmt::format("{} = {} is held: the data are isotropic (the same at every azimuth), which "
                      "only an isotropic lobe matches",
                      p.name, format_value(p.value)));
      continue;
    }
    const bool clamped = spec && spec->linear && std::all_of(p.value.begin(), p.value.end(), [&](double v) {
                           return at_upper_bound(*spec, v);
                         });
    if (clamped && zero_error > 0.0 && error > kPoorClampedUnexplained * zero_error) {
      r.verdict = Verdict::Poor;
      r.warnings.push_back(
          fmt::format("poor fit: {} is at its upper bound {:.4g} in every channel and the fit leaves "
                      "{:.0f}% of the data's scale: the data are brighter than this model can be",
                      p.name, spec->upper, 100.0 * error / zero_error));
    }
    if (p.at_bound && spec) {
      const bool upper =
          std::any_of(p.value.begin(), p.value.end(), [&](double v) { return at_upper_bound(*spec, v); });
      r.warnings.push_back(
          fmt::format("{} = {} sits at its {} bound {:.4g}: the data would push it further, "
                      "its uncertainty is only indicative",
                      p.name, format_value(p.value), upper ? "upper" : "lower", upper ? spec->upper : spec->lower));
    }
    const char* partner_name = spec ? (spec->only_scales ? spec->only_scales : spec->trades_off_with) : nullptr;
    if (partner_name && (p.at_bound || !p.identifiable)) {
      const ParamSpec* other = model.find_parameter(partner_name);
      const auto partner = std::find_if(r.parameters.begin(), r.parameters.end(),
                                        [&](const ParameterEstimate& e) { return e.name == partner_name; });
      if (other && partner != r.parameters.end()) {
        std::vector<double> product;
        for (size_t i = 0; i < std::max(partner->value.size(), p.value.size()); ++i)
          product.push_back(partner->value[std::min(i, partner->value.size() - 1)] *
                            p.value[std::min(i, p.value.size() - 1)]);
        const char* what = spec->only_scales ? "the lobe's scale" : "the lobe's reflectance at normal incidence";
        r.warnings.push_back(fmt::format(
            "{}·{} = {} is what the data determine ({}); {} was left where the least-squares optimum put it",
            other->name, p.name, format_value(product), what, p.name));
      }
    }
    if (!p.identifiable)
      r.warnings.push_back(
          fmt::format("{} is not identifiable: the data do not determine it (it trades off with "
                      "other parameters); its value is one of many equally good ones",
                      p.name));
  }
}

}  // namespace fitting
}  // namespace brdffit
