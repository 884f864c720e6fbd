// The fitter's objective evaluated with plain doubles: the cost every stage minimises and every
// candidate is judged by, and the per-sample errors the importance subset and the robust
// loss's scale are drawn from. (Ceres' derivatives come from fit_residual.h, on the same
// residuals.)
#pragma once

#include <ceres/loss_function.h>

#include <array>
#include <cmath>
#include <vector>

#include "brdffit/metric.h"
#include "brdffit/model.h"
#include "brdffit/samples.h"

namespace brdffit {

// Which colour channels a fit adjusts (a per-channel fit runs once per channel).
using Channels = std::array<bool, 3>;
constexpr Channels kAllChannels{true, true, true};

// Σ over samples and fitted channels of ρ((metric residual · √weight)²), ρ the robust loss
// (identity when loss is null). Parallel over chunks on `threads` threads when the set is large.
// HUGE_VAL when the sum is not finite, so a diverging candidate always loses. A sum that passes
// give_up_above is given up: the value returned is then only known to be above that bound (the
// candidate cannot beat one of that cost).
double cost_of(const Model& model, const std::vector<double>& values, const std::vector<Sample>& samples, Metric metric,
               const Channels& channels, const ceres::LossFunction* loss, int threads = 1,
               double give_up_above = HUGE_VAL);

// cost_of's terms one per sample, its fitted channels summed (never given up). On an importance
// subset, whose weights make sums over it estimates of sums over all samples, the spread of two
// fits' differences term by term says how well the subset tells which of them costs less.
std::vector<double> cost_per_sample(const Model& model, const std::vector<double>& values,
                                    const std::vector<Sample>& samples, Metric metric, const Channels& channels,
                                    const ceres::LossFunction* loss, int threads = 1);

// The median of |metric residual · √weight| over samples and fitted channels: the robust loss's
// automatic scale (σ ≈ 1.4826 × this for Gaussian noise).
double median_abs_residual(const Model& model, const std::vector<double>& values, const std::vector<Sample>& samples,
                           Metric metric, const Channels& channels);

// |prediction − measurement| per sample, averaged over the fitted channels (0 where not finite).
std::vector<double> absolute_errors(const Model& model, const std::vector<double>& values,
                                    const std::vector<Sample>& samples, const Channels& channels, int threads);

// cost_of (never given up) and absolute_errors, the same values bit for bit, from one evaluation of
// the model per sample: the fitter costs its subsample's best start on all samples and then draws
// its importance subset from that start's errors.
double cost_and_absolute_errors(const Model& model, const std::vector<double>& values,
                                const std::vector<Sample>& samples, Metric metric, const Channels& channels,
                                const ceres::LossFunction* loss, int threads, std::vector<double>& errors);

// Σ over samples and all three channels of the metric's sample weight: a fit's objective over every
// channel without a robust loss, ½ cost_of, is ½·error²·this, its error in the metric (Metrics)
// being the weighted RMS of the same residuals.
double metric_weight_sum(const std::vector<Sample>& samples, Metric metric);

// The error, in the metric, of a model predicting zero everywhere: the data's own scale, which
// a fit's error is judged against.
double zero_prediction_error(const SampleSet& data, Metric metric);

}  // namespace brdffit
