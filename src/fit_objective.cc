// The fitter's objective with plain doubles (see fit_objective.h).
#include "brdffit/fit_objective.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "brdffit/fit_residual.h"
#include "brdffit/parallel.h"

namespace brdffit {

namespace {

// The one loop over a fit's residuals: calls visit(chunk, r) for every sample and fitted
// channel with r = metric residual · √weight, over `chunks` ranges of the samples in parallel.
template <class Visit>
void for_each_residual(const Model& model, const std::vector<double>& values, const std::vector<Sample>& samples,
                       Metric metric, const Channels& channels, size_t chunks, int threads, Visit&& visit) {
  parallel_chunks(samples.size(), chunks, threads, [&](size_t begin, size_t end, size_t chunk) {
    for (size_t i = begin; i < end; ++i) {
      const Sample& s = samples[i];
      const Rgb<double> shade = model.shade(values.data(), s.l, s.v);
      const double sqrt_w = std::sqrt(metric_weight(metric, s.weight));
      for (int c = 0; c < 3; ++c)
        if (channels[c]) visit(chunk, metric_residual(metric, shade[c], s.value[c]) * sqrt_w);
    }
  });
}

}  // namespace

double cost_of(const Model& model, const std::vector<double>& values, const std::vector<Sample>& samples, Metric metric,
               const Channels& channels, const ceres::LossFunction* loss, int threads) {
  // Chunks even on one thread: the sum then does not depend on the number of threads.
  const size_t chunks = samples.size() >= 50000 ? 64 : 1;
  std::vector<double> partial(chunks, 0.0);
  for_each_residual(model, values, samples, metric, channels, chunks, chunks > 1 ? threads : 1,
                    [&](size_t chunk, double residual) {
                      double r, scale;
                      detail::robustify(loss, residual, r, scale);
                      partial[chunk] += r * r;
                    });
  const double sum = std::accumulate(partial.begin(), partial.end(), 0.0);
  return std::isfinite(sum) ? sum : HUGE_VAL;
}

double median_abs_residual(const Model& model, const std::vector<double>& values, const std::vector<Sample>& samples,
                           Metric metric, const Channels& channels) {
  std::vector<double> abs_residuals;
  for_each_residual(model, values, samples, metric, channels, 1, 1,
                    [&](size_t, double residual) { abs_residuals.push_back(std::fabs(residual)); });
  if (abs_residuals.empty()) return 0.0;
  auto middle = abs_residuals.begin() + abs_residuals.size() / 2;
  std::nth_element(abs_residuals.begin(), middle, abs_residuals.end());
  return *middle;
}

std::vector<double> absolute_errors(const Model& model, const std::vector<double>& values,
                                    const std::vector<Sample>& samples, const Channels& channels, int threads) {
  std::vector<double> error(samples.size());
  const int fitted = static_cast<int>(std::count(channels.begin(), channels.end(), true));
  parallel_chunks(samples.size(), 64, threads, [&](size_t begin, size_t end, size_t) {
    for (size_t i = begin; i < end; ++i) {
      const Rgb<double> shade = model.shade(values.data(), samples[i].l, samples[i].v);
      double sum = 0.0;
      for (int c = 0; c < 3; ++c)
        if (channels[c]) sum += std::fabs(shade[c] - samples[i].value[c]);
      error[i] = std::isfinite(sum) ? sum / fitted : 0.0;
    }
  });
  return error;
}

double zero_prediction_error(const SampleSet& data, Metric metric) {
  double sum = 0.0, weight = 0.0;
  for (const Sample& s : data.samples)
    for (int c = 0; c < 3; ++c) {
      const double w = metric_weight(metric, s.weight);
      sum += w * std::pow(metric_residual(metric, 0.0, s.value[c]), 2);
      weight += w;
    }
  return weight > 0.0 ? std::sqrt(sum / weight) : 0.0;
}

}  // namespace brdffit
