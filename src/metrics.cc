// The error metrics (see metric.h for their definitions), their table's look-ups and the losses' names.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

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

namespace {

// The bins of a histogram of log10 x: kBinsPerDecade per decade from 10^−(kDecades/2) to
// 10^(kDecades/2), the first and last also taking what lies beyond. A bin is found from x's binary
// exponent and a table of log10 over the mantissa, then checked against the bins' edges: a
// logarithm per sample and channel was a sixth of the metrics' pass (lambert on a full MERL
// table: 0.132 -> 0.110 CPU s, every fit has one such pass).
class LogBins {
 public:
  static constexpr int kBinsPerDecade = 200, kDecades = 12, kBins = kBinsPerDecade * kDecades;

  LogBins() {
    for (int b = 0; b <= kBins; ++b) edges_[b] = std::pow(10.0, static_cast<double>(b) / kBinsPerDecade - kDecades / 2);
    for (int k = 0; k < kCells; ++k) cell_log10_[k] = std::log10(0.5 + 0.5 * k / kCells);
  }

  int bin_of(double x) const {
    if (!(x >= edges_[1])) return 0;  // NaN too
    if (x >= edges_[kBins - 1]) return kBins - 1;
    // x = mantissa·2^exponent with mantissa in [½, 1), as frexp gives them (x is normal here),
    // read from x's bits: glibc's frexp is a call per sample and channel.
    uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    const int exponent = static_cast<int>((bits >> 52) & 0x7ff) - 1022;
    const int cell = static_cast<int>((bits >> (52 - kCellBits)) & (kCells - 1));  // the mantissa's leading bits
    const double log10_below = exponent * kLog10Of2 + cell_log10_[cell];           // of the cell's lower end
    // A cell spans a third of a bin: at most one edge lies between its lower end and x.
    const int b = std::clamp(static_cast<int>((log10_below + kDecades / 2) * kBinsPerDecade), 1, kBins - 2);
    if (x >= edges_[b + 1]) return b + 1;
    return x < edges_[b] ? b - 1 : b;
  }

 private:
  static constexpr int kCellBits = 8, kCells = 1 << kCellBits;
  static constexpr double kLog10Of2 = 0.30102999566398120;
  std::array<double, kBins + 1> edges_;
  std::array<double, kCells> cell_log10_;
};

}  // namespace

Metrics evaluate_metrics(const Model& model, const std::vector<double>& values, const SampleSet& data,
                         const std::vector<std::vector<double>>& per_channel_values) {
  // The typical relative error is a weighted median, found in a histogram of log10 of the
  // relative error (LogBins: 1.2% resolution).
  static const LogBins bins;
  constexpr int kBins = LogBins::kBins, kBinsPerDecade = LogBins::kBinsPerDecade, kDecades = LogBins::kDecades;
  double mean_abs = 0.0, mean_weight = 0.0;
  for (const Sample& s : data.samples) {
    mean_abs += s.weight * s.value.cwiseAbs().sum();
    mean_weight += 3.0 * s.weight;
  }
  const double floor = 0.1 * mean_abs / std::max(mean_weight, 1e-300) + 1e-300;
  struct Sums {
    double weight = 0, cosine = 0, log = 0, relative = 0, plain = 0, max = 0;
    size_t count = 0;
  };
  const size_t chunks = 64;
  std::vector<Sums> partial(chunks);
  std::vector<std::vector<double>> typical(chunks, std::vector<double>(kBins, 0.0));  // per chunk
  parallel_chunks(data.size(), chunks, thread_count(0), [&](size_t begin, size_t end, size_t chunk) {
    // Summed in locals, not in partial[chunk]: the histogram's stores could alias its fields,
    // which then went through memory at every sample.
    Sums sums;
    double* histogram = typical[chunk].data();
    for (size_t i = begin; i < end; ++i) {
      const Sample& s = data.samples[i];
      Rgb<double> predicted;
      if (per_channel_values.empty()) {
        predicted = model.shade(values.data(), s.l, s.v);
      } else {
        for (int c = 0; c < 3; ++c) predicted[c] = model.shade(per_channel_values[c].data(), s.l, s.v)[c];
      }
      for (int c = 0; c < 3; ++c) {
        const double p = predicted[c], m = s.value[c], difference = p - m;
        // metric_residual's log(1 + p⁺) − log1p(m⁺) as one logarithm of their ratio: its two
        // calls (glibc's log1p is slow) were a sixth of this pass (lambert: 0.156 -> 0.132 s).
        const double log_residual = std::log((1.0 + std::max(p, 0.0)) / (1.0 + std::max(m, 0.0)));
        sums.weight += s.weight;
        sums.cosine += s.weight * difference * difference;
        sums.log += s.weight * log_residual * log_residual;
        sums.relative += s.weight * std::pow(metric_residual(Metric::Relative, p, m), 2);
        sums.plain += difference * difference;
        sums.max = std::max(sums.max, std::fabs(difference));
        histogram[bins.bin_of(std::fabs(difference) / (std::fabs(m) + floor))] += s.weight;
        ++sums.count;
      }
    }
    partial[chunk] = sums;
  });
  Sums total;
  std::vector<double> total_typical(kBins, 0.0);
  for (size_t chunk = 0; chunk < chunks; ++chunk) {
    const Sums& s = partial[chunk];
    total.weight += s.weight;
    total.cosine += s.cosine;
    total.log += s.log;
    total.relative += s.relative;
    total.plain += s.plain;
    total.max = std::max(total.max, s.max);
    total.count += s.count;
    for (int b = 0; b < kBins; ++b) total_typical[b] += typical[chunk][b];
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
    below += total_typical[b];
    if (below >= 0.5 * total.weight) {
      metrics.typical = std::pow(10.0, (b + 0.5) / kBinsPerDecade - kDecades / 2);
      break;
    }
  }
  return metrics;
}

}  // namespace brdffit
