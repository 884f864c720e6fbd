// The generic fitter: any model of the library against any sample set.
//
// For each model: a deterministic multi-start grid over the shape parameters (on a subsample),
// with the linear colour parameters solved exactly for every grid point (variable projection);
// trust-region least squares (Ceres dogleg, automatic derivatives, batched residuals in parallel)
// from the best starts on the subsample (the best walked furthest), then on ten-times larger
// importance subsets and all samples (a few polishing steps when a large subset came before);
// integer parameters searched over their range; standard deviations from Ceres' covariance.
#pragma once

#include <atomic>
#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "brdffit/metric.h"
#include "brdffit/model.h"
#include "brdffit/samples.h"

namespace brdffit {

struct FitOptions {
  Metric metric = Metric::Cosine;  // what is minimised; every metric is reported
  bool per_channel = false;        // shape parameters fitted per channel (colours always are)
  LossKind loss = LossKind::None;  // robust loss per sample-channel (photographs)
  double loss_scale = 0.0;         // residual scale where the robust loss bends; 0 = automatic
  int threads = 0;                 // 0 = all cores
  int max_iterations = 100;        // trust-region iterations per stage (at most 40 on an importance subset)
  int grid_points = 256;           // multi-start grid size over the shape parameters (at most)
  int starts = 3;                  // best grid points refined on the subsample
  size_t subsample = 12000;        // samples used by the grid and the first refinements
  // After a subset of at least polish_after samples, the stage on all samples only polishes, and
  // only where the subset's cost estimate at its optimum is off the cost on all samples by 0.5 % or
  // more: the importance subset's optimum is within a fraction of a percent of the full one in
  // every metric (bench_fit --converge shows the difference), and each step on a million samples
  // costs ten on the subset.
  size_t polish_after = 100000;
  int polish_iterations = 2;           // 0: the importance subset's optimum stands, never polished
  uint64_t seed = 1;                   // for the subsample
  bool single_start = false;           // one refinement from the initial values on all samples
  std::vector<double> initial_values;  // flattened start; empty: the model's defaults
  // The parameters' standard deviations (FitResult::parameters' stddev, identifiable): one pass
  // with derivatives over all samples. fit_models leaves them out for the models it fits only as
  // the starts and the baseline of the requested ones.
  bool uncertainties = true;
  // The result's metrics (FitResult::metrics): one pass over all samples at its values.
  // fit_models leaves them out for the models it fits only as starts of the requested ones, whose
  // objective (FitResult::objective) is all the requested fits need of them.
  bool metrics = true;
  // Parameters held at known values (a dielectric's metallic 0, a known ior 1.5), by name, in every
  // model of the run that has the parameter (every channel of a colour): the fit is that of the
  // remaining parameters, whose standard deviations take the held ones as exact. fit_models
  // throws Error for a name no model of the run has, or a value outside a model's bounds.
  std::vector<std::pair<std::string, double>> fixed;
  // Set to true by another thread to stop the fit: fit_models then throws Cancelled within one
  // solver iteration or grid (a fraction of a second). Null: the fit runs to its end.
  const std::atomic<bool>* cancel = nullptr;
  // Called after each trust-region iteration (Ceres counts the start as iteration 0) with the
  // name of the model being fitted, which may be a model the requested one contains. `cancel`
  // is looked at right after it returns: set there, no further iteration runs (it must not
  // throw through the solver; set `cancel` to stop). Empty: nothing is called.
  std::function<void(const std::string& model, int iteration)> on_iteration;
  // Called before each requested model's fit with its index, the number of models and its name
  // (the command line's progress). Empty: nothing is called.
  std::function<void(size_t index, size_t count, const std::string& model)> on_model_start;
};

struct ParameterEstimate {
  std::string name;
  std::vector<double> value;   // 1 or 3 entries (3 for colours, and for shape parameters fitted per channel)
  std::vector<double> stddev;  // NaN where not identifiable or not estimated
  bool identifiable = true;    // false: the data do not determine this parameter
  bool at_bound = false;       // the optimum sits on a bound (its stddev is only indicative)
  bool fixed = false;          // held at a given value (FitOptions::fixed): not fitted, no stddev
};

// Whether a fit describes its data (see verdict_for in fit.cc for the thresholds):
// good, poor (clearly worse than the baseline, a Lambert fit on the same samples, or leaving
// most of the data unexplained), failed (no usable fit at all).
enum class Verdict { Good, Poor, Failed };
const char* verdict_name(Verdict verdict);

// A profile of one stage of the fitter (grid, coordinate search, screen, subsets, all samples, ...):
// bench_fit --stages prints them.
struct StageProfile {
  std::string stage;
  double cpu_seconds = 0.0;  // the process's: meaningful with one thread and nothing else running in it
  int iterations = 0;        // trust-region iterations
};

struct FitResult {
  std::string model;
  bool ok = false;
  std::string error;  // why the fit failed, when !ok
  Verdict verdict = Verdict::Failed;
  // One line each, for a user: why the verdict is poor, parameters at a bound or not
  // identifiable and what that means, what the fitter pinned and why.
  std::vector<std::string> warnings;
  std::vector<double> values;  // flattened, in the model's parameter order
  // With per_channel: the full value vector fitted for each channel (R, G, B); a channel's
  // prediction uses its own vector. `values` then holds channel R's shape parameters.
  std::vector<std::vector<double>> channel_values;
  std::vector<ParameterEstimate> parameters;
  Metrics metrics;  // NaN where FitOptions::metrics was off
  // What the fit minimised, at `values` over all samples: Ceres' cost, ½Σ of the squared
  // residuals (under the robust loss, if any). NaN for a fit per channel.
  double objective = NAN;
  int iterations = 0;
  std::string termination;  // Ceres' termination type and message
  double seconds = 0.0;
  size_t samples = 0;
  std::vector<StageProfile> stages;  // where the time went, summed over channel fits, in the order first met
};

// Fits one model; never throws for a fit that goes wrong (it returns ok = false with the
// reason), only for invalid options or an empty sample set (Error).
FitResult fit_model(const Model& model, const SampleSet& data, const FitOptions& options);

// Fits each model in turn; a model whose fit fails is reported as failed (ok = false, error set)
// and the others are still fitted.
std::vector<FitResult> fit_models(const std::vector<const Model*>& models, const SampleSet& data,
                                  const FitOptions& options);

// Every metric for given parameter values (flattened, model order) on a sample set.
// per_channel_values: when non-empty, three full value vectors, one per channel.
Metrics evaluate_metrics(const Model& model, const std::vector<double>& values, const SampleSet& data,
                         const std::vector<std::vector<double>>& per_channel_values = {});

}  // namespace brdffit
