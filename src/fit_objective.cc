// The fitter's objective with plain doubles (see fit_objective.h).
#include "brdffit/fit_objective.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>

#include "brdffit/fit_residual.h"
#include "brdffit/parallel.h"

namespace brdffit {

namespace {

// Chunk `order` of 2^bits in bit-reversed order (0, half, quarter, three quarters, ...): a few
// chunks taken so spread over the whole table.
size_t bit_reversed(size_t order, size_t chunks) {
  size_t reversed = 0;
  for (size_t bit = 1, mirror = chunks / 2; mirror > 0; bit <<= 1, mirror >>= 1)
    if (order & bit) reversed |= mirror;
  return reversed;
}

// The one loop over a fit's residuals: calls visit(chunk, i, r) for every sample i and fitted
// channel with r = metric residual · √weight, over `chunks` (a power of two) ranges of the
// samples in parallel, taken in bit-reversed order, and chunk_done(chunk) after each. Where
// give_up(chunk) holds, at a chunk's start or every 256 of its samples, the rest of the chunk is
// skipped (and chunk_done not called). Each sample's shaded value is also shown to seen(i, shade).
template <class Visit, class ChunkDone, class GiveUp, class Seen = void (*)(size_t, const Rgb<double>&)>
void for_each_residual(
    const Model& model, const std::vector<double>& values, const std::vector<Sample>& samples, Metric metric,
    const Channels& channels, size_t chunks, int threads, Visit&& visit, ChunkDone&& chunk_done, GiveUp&& give_up,
    Seen&& seen = [](size_t, const Rgb<double>&) {}) {
  const size_t per_chunk = (samples.size() + chunks - 1) / chunks;
  parallel_for(chunks, threads, [&](size_t order) {
    const size_t chunk = bit_reversed(order, chunks);
    const size_t begin = std::min(samples.size(), chunk * per_chunk);
    const size_t end = std::min(samples.size(), begin + per_chunk);
    for (size_t i = begin; i < end; ++i) {
      if ((i - begin) % 256 == 0 && give_up(chunk)) return;
      const Sample& s = samples[i];
      const Rgb<double> shade = model.shade(values.data(), s.l, s.v);
      seen(i, shade);
      const double sqrt_w = std::sqrt(metric_weight(metric, s.weight));
      for (int c = 0; c < 3; ++c)
        if (channels[c]) visit(chunk, i, metric_residual(metric, shade[c], s.value[c]) * sqrt_w);
    }
    chunk_done(chunk);
  });
}

// |prediction − measurement| of one sample, averaged over the fitted channels (0 where not finite).
double absolute_error(const Rgb<double>& shade, const Sample& s, const Channels& channels) {
  double sum = 0.0;
  for (int c = 0; c < 3; ++c)
    if (channels[c]) sum += std::fabs(shade[c] - s.value[c]);
  return std::isfinite(sum) ? sum / static_cast<double>(std::count(channels.begin(), channels.end(), true)) : 0.0;
}

// cost_of, showing each sample's shaded value to seen(i, shade).
template <class Seen>
double summed_cost(const Model& model, const std::vector<double>& values, const std::vector<Sample>& samples,
                   Metric metric, const Channels& channels, const ceres::LossFunction* loss, int threads,
                   double give_up_above, Seen&& seen) {
  // Chunks even on one thread: the sum then does not depend on the number of threads.
  const size_t chunks = samples.size() >= 50000 ? 64 : 1;
  std::vector<double> partial(chunks, 0.0);
  // The sum over the chunks done so far. Bit-reversed, the chunks make it grow about evenly
  // however the error is spread over the table: a candidate at twice the bound is given up
  // about halfway. Within a chunk its own sum so far counts too (every term is ≥ 0), which is
  // what gives a set of one chunk (fewer than 50 000 samples: the grids') its chance.
  std::atomic<double> done{0.0};
  std::atomic<bool> given_up{false};
  auto passed = [&](size_t chunk) {
    if (!given_up.load() && done.load() + partial[chunk] > give_up_above) given_up = true;
    return given_up.load();
  };
  for_each_residual(
      model, values, samples, metric, channels, chunks, chunks > 1 ? threads : 1,
      [&](size_t chunk, size_t, double residual) {
        double r, scale;
        detail::robustify(loss, residual, r, scale);
        partial[chunk] += r * r;
      },
      [&](size_t chunk) {
        for (double seen_so_far = done.load();
             !done.compare_exchange_weak(seen_so_far, seen_so_far + partial[chunk]);) {
        }
      },
      passed, seen);
  // Given up, the sum so far: above the bound, and at most the whole sum.
  const double sum = std::accumulate(partial.begin(), partial.end(), 0.0);
  return std::isfinite(sum) ? sum : HUGE_VAL;
}

}  // namespace

double cost_of(const Model& model, const std::vector<double>& values, const std::vector<Sample>& samples, Metric metric,
               const Channels& channels, const ceres::LossFunction* loss, int threads, double give_up_above) {
  return summed_cost(model, values, samples, metric, channels, loss, threads, give_up_above,
                     [](size_t, const Rgb<double>&) {});
}

std::vector<double> cost_per_sample(const Model& model, const std::vector<double>& values,
                                    const std::vector<Sample>& samples, Metric metric, const Channels& channels,
                                    const ceres::LossFunction* loss, int threads) {
  std::vector<double> costs(samples.size(), 0.0);
  const size_t chunks = samples.size() >= 50000 ? 64 : 1;
  for_each_residual(
      model, values, samples, metric, channels, chunks, chunks > 1 ? threads : 1,
      [&](size_t, size_t sample, double residual) {
        double r, scale;
        detail::robustify(loss, residual, r, scale);
        costs[sample] += r * r;
      },
      [](size_t) {}, [](size_t) { return false; });
  return costs;
}

double cost_and_absolute_errors(const Model& model, const std::vector<double>& values,
                                const std::vector<Sample>& samples, Metric metric, const Channels& channels,
                                const ceres::LossFunction* loss, int threads, std::vector<double>& errors) {
  errors.resize(samples.size());
  return summed_cost(
      model, values, samples, metric, channels, loss, threads, HUGE_VAL,
      [&](size_t i, const Rgb<double>& shade) { errors[i] = absolute_error(shade, samples[i], channels); });
}

double median_abs_residual(const Model& model, const std::vector<double>& values, const std::vector<Sample>& samples,
                           Metric metric, const Channels& channels) {
  std::vector<double> abs_residuals;
  for_each_residual(
      model, values, samples, metric, channels, 1, 1,
      [&](size_t, size_t, double residual) { abs_residuals.push_back(std::fabs(residual)); }, [](size_t) {},
      [](size_t) { return false; });
  if (abs_residuals.empty()) return 0.0;
  auto middle = abs_residuals.begin() + abs_residuals.size() / 2;
  std::nth_element(abs_residuals.begin(), middle, abs_residuals.end());
  return *middle;
}

std::vector<double> absolute_errors(const Model& model, const std::vector<double>& values,
                                    const std::vector<Sample>& samples, const Channels& channels, int threads) {
  std::vector<double> error(samples.size());
  parallel_chunks(samples.size(), 64, threads, [&](size_t begin, size_t end, size_t) {
    for (size_t i = begin; i < end; ++i)
      error[i] = absolute_error(model.shade(values.data(), samples[i].l, samples[i].v), samples[i], channels);
  });
  return error;
}

double metric_weight_sum(const std::vector<Sample>& samples, Metric metric) {
  double sum = 0.0;
  for (const Sample& s : samples) sum += 3.0 * metric_weight(metric, s.weight);
  return sum;
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
