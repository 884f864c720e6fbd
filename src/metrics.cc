// The error metrics (see metric.h for their definitions), their table's look-ups and the losses' names.
#include <algorithm>
#include <cmath>

#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/metric.h"
#include "brdffit/names.h"
#include "brdffit/parallel.h"

namespace brdffit {

const MetricInfo& metric_info(Metric metric) {
  for (const MetricInfo& info : kMetrics)
    if (info.minimised == metric) return info;
  return kMetrics[0];
}

const char* metric_name(Metric metric) { return metric_info(metric).name; }

std::optional<Metric> parse_metric(const std::string& name) {
  for (const MetricInfo& info : kMetrics)
    if (info.minimised && name == info.name) return info.minimised;
  return std::nullopt;
}

std::string minimisable_metrics_text() {
  std::string text;
  for (const MetricInfo& info : kMetrics)
    if (info.minimised) text += (text.empty() ? "" : ", ") + std::string(info.name);
  return text;
}

Metric metric_from_name(const std::string& name, const std::string& what) {
  if (const std::optional<Metric> metric = parse_metric(name)) return *metric;
  std::vector<std::string> known;
  for (const MetricInfo& info : kMetrics)
    if (info.minimised) known.push_back(info.name);
  fail_usage("{}: unknown metric '{}'{} ({})", what, name, did_you_mean(name, known), minimisable_metrics_text());
}

std::vector<Metric> judged_metrics() {
  std::vector<Metric> judged;
  for (const MetricInfo& info : kMetrics)
    if (info.judged && info.minimised) judged.push_back(*info.minimised);
  return judged;
}

namespace {

constexpr std::pair<LossKind, const char*> kLosses[] = {
    {LossKind::None, "none"}, {LossKind::Huber, "huber"}, {LossKind::Cauchy, "cauchy"}};

}  // namespace

const char* loss_name(LossKind loss) {
  for (const auto& [kind, name] : kLosses)
    if (kind == loss) return name;
  return "none";
}

LossKind loss_from_name(const std::string& name, const std::string& what) {
  std::vector<std::string> known;
  for (const auto& [kind, spelling] : kLosses) {
    if (name == spelling) return kind;
    known.push_back(spelling);
  }
  std::string list;
  for (const std::string& spelling : known) list += (list.empty() ? "" : ", ") + spelling;
  fail_usage("{}: unknown loss '{}'{} ({})", what, name, did_you_mean(name, known), list);
}

double Metrics::get(Metric metric) const { return this->*metric_info(metric).value; }

Metrics evaluate_metrics(const Model& model, const std::vector<double>& values, const SampleSet& data,
                         const std::vector<std::vector<double>>& per_channel_values) {
  // The typical relative error is a weighted median, found in a histogram of log10 of the
  // relative error (kBinsPerDecade bins per decade from 1e-6 to 1e6: 1.2% resolution).
  constexpr int kBinsPerDecade = 200, kDecades = 12;
  constexpr int kBins = kBinsPerDecade * kDecades;
  auto bin_of = [](double relative) {
    const double position = (std::log10(std::max(relative, 1e-300)) + kDecades / 2) * kBinsPerDecade;
    return std::clamp(static_cast<int>(position), 0, kBins - 1);
  };
  double mean_abs = 0.0, mean_weight = 0.0;
  for (const Sample& s : data.samples) {
    mean_abs += s.weight * s.value.cwiseAbs().sum();
    mean_weight += 3.0 * s.weight;
  }
  const double floor = 0.1 * mean_abs / std::max(mean_weight, 1e-300) + 1e-300;
  struct Sums {
    double weight = 0, cosine = 0, log = 0, relative = 0, plain = 0, max = 0;
    size_t count = 0;
    std::vector<double> typical = std::vector<double>(kBins, 0.0);
  };
  const size_t chunks = 64;
  std::vector<Sums> partial(chunks);
  parallel_chunks(data.size(), chunks, thread_count(0), [&](size_t begin, size_t end, size_t chunk) {
    Sums& sums = partial[chunk];
    for (size_t i = begin; i < end; ++i) {
      const Sample& s = data.samples[i];
      Rgb<double> predicted;
      if (per_channel_values.empty()) {
        predicted = model.shade(values.data(), s.l, s.v);
      } else {
        for (int c = 0; c < 3; ++c) predicted[c] = model.shade(per_channel_values[c].data(), s.l, s.v)[c];
      }
      for (int c = 0; c < 3; ++c) {
        const double p = predicted[c], m = s.value[c];
        sums.weight += s.weight;
        sums.cosine += s.weight * std::pow(metric_residual(Metric::Cosine, p, m), 2);
        sums.log += s.weight * std::pow(metric_residual(Metric::Log, p, m), 2);
        sums.relative += s.weight * std::pow(metric_residual(Metric::Relative, p, m), 2);
        sums.plain += std::pow(p - m, 2);
        sums.max = std::max(sums.max, std::fabs(p - m));
        sums.typical[bin_of(std::fabs(p - m) / (std::fabs(m) + floor))] += s.weight;
        ++sums.count;
      }
    }
  });
  Sums total;
  for (const Sums& s : partial) {
    total.weight += s.weight;
    total.cosine += s.cosine;
    total.log += s.log;
    total.relative += s.relative;
    total.plain += s.plain;
    total.max = std::max(total.max, s.max);
    total.count += s.count;
    for (int b = 0; b < kBins; ++b) total.typical[b] += s.typical[b];
  }
  Metrics metrics;
  if (total.count == 0) return metrics;
  metrics.cosine = std::sqrt(total.cosine / total.weight);
  metrics.log = std::sqrt(total.log / total.weight);
  metrics.relative = std::sqrt(total.relative / total.weight);
  metrics.l2 = std::sqrt(total.plain / total.count);
  metrics.max = total.max;
  double below = 0.0;
  for (int b = 0; b < kBins; ++b) {
    below += total.typical[b];
    if (below >= 0.5 * total.weight) {
      metrics.typical = std::pow(10.0, (b + 0.5) / kBinsPerDecade - kDecades / 2);
      break;
    }
  }
  return metrics;
}

}  // namespace brdffit
