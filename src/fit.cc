// The generic fitter (see fit.h for the strategy): the orchestration of its stages. The stages
// live in their own units (fit_stages.h: the starts, the least-squares refinements, the
// verdicts), beside the objective with doubles (fit_objective.h), the linear colours solved
// exactly (variable_projection.h), the subset the early stages run on (importance_subset.h),
// Ceres' residuals (fit_residual.h) and the metrics (metrics.cc).
#include "brdffit/fit.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <ctime>
#include <functional>
#include <map>
#include <numeric>
#include <optional>
#include <set>

#include "brdffit/error.h"
#include "brdffit/fit_objective.h"
#include "brdffit/fit_stages.h"
#include "brdffit/held_model.h"
#include "brdffit/importance_subset.h"
#include "brdffit/parallel.h"
#include "brdffit/registry.h"
#include "brdffit/variable_projection.h"

namespace brdffit {

using namespace fitting;

namespace {

// One fit of the given channels: multi-start on the subsample, refinement on larger subsets and
// on every sample, and the final choice among every candidate met on the way by the objective
// on ALL samples.
struct ChannelFit {
  Refinement final;
  std::optional<Metrics> metrics;  // at final.values, where the fit computed them with its cost
  int iterations = 0;
  size_t residuals = 0;
  std::vector<StageProfile> stages;
};

void add_stage(std::vector<StageProfile>& stages, const StageProfile& stage) {
  auto it = std::find_if(stages.begin(), stages.end(), [&](const StageProfile& s) { return s.stage == stage.stage; });
  if (it == stages.end()) return stages.push_back(stage);
  it->cpu_seconds += stage.cpu_seconds;
  it->iterations += stage.iterations;
}

// ChannelFit::stages: each lap gives a stage the process CPU time and the iterations since the last.
class StageClock {
 public:
  explicit StageClock(ChannelFit& fit) : fit_(fit), last_cpu_(std::clock()), last_iterations_(fit.iterations) {}
  void lap(const std::string& stage) {
    const std::clock_t cpu = std::clock();
    add_stage(fit_.stages,
              {stage, static_cast<double>(cpu - last_cpu_) / CLOCKS_PER_SEC, fit_.iterations - last_iterations_});
    last_cpu_ = cpu;
    last_iterations_ = fit_.iterations;
  }

 private:
  ChannelFit& fit_;
  std::clock_t last_cpu_;
  int last_iterations_;
};

// The importance subsamples the fits start on (a count of draws and a seed each): they depend on
// the samples alone, so one fit_models call draws them once for all its models.
class Subsamples {
 public:
  explicit Subsamples(const SampleSet& data) : data_(data) {}
  const std::vector<Sample>& draw(size_t count, uint64_t seed) {
    auto [it, drawn_now] = drawn_.try_emplace({count, seed});
    if (drawn_now) it->second = importance_subset(data_.samples, count, seed);
    return it->second;
  }

 private:
  const SampleSet& data_;
  std::map<std::pair<size_t, uint64_t>, std::vector<Sample>> drawn_;
};

// The polish on all samples after the largest importance subset pays only where that subset
// misjudged the cost at its optimum. Its weights make its cost an unbiased estimate of the cost on
// all samples; where the two disagree, the subset under-represents where the fit now errs (drawn
// rarely because the start fitted it well), and the optimum on all samples lies elsewhere. On the
// shared tables (256 polishes: 32 models on the three MERL proxies and five RGL files), every
// polish that gained more than 3e-5 of the cost followed a disagreement of 1.4 % or more
// (Cook-Torrance on blue-acrylic: 6.6 %, a gain of 2.7 %), every disagreement below 0.45 % a gain
// of at most 2.9e-5: the gains were up to about eight times the square of the disagreement
// (docs/performance.md, twelfth round).
constexpr double kSubsetAgreement = 0.005;

// The model every verdict compares a fit with (judge), fitted in every run.
constexpr const char* kBaselineModel = "lambert";

// Whether `candidate` is the largest subset's optimum, its cost on all samples within
// kSubsetAgreement of the subset's estimate there.
bool subset_stood_in(const Refinement& candidate, const Refinement& subset_optimum) {
  return subset_optimum.usable && candidate.values == subset_optimum.values &&
         std::fabs(candidate.cost - subset_optimum.cost) <= kSubsetAgreement * candidate.cost;
}

// The subsample's best start walks on to kBestStartIterations in all (the others stop at 50),
// and the walks on the importance subset that follow stop at kSubsetWalkIterations (or at
// FitOptions::max_iterations, if fewer). Walks there used to run to their 100 steps, crawling
// (sgd on gold-metallic-paint: 82 steps of 0.2 % each at a constant trust-region radius); walked
// further on the subsample first, at a tenth of the cost per step, they start nearer their end.
constexpr int kBestStartIterations = 150;
constexpr int kSubsetWalkIterations = 40;

// How far above the best cost on all samples a continued start's cost estimated on the largest
// importance subset may lie and the start still be costed on all samples. On the nine shared
// tables (1074 continued starts but the best, 36 models, all costed on all samples), the
// estimates of the 647 starts within 0.5 % of the best missed their cost on all samples by
// −0.11 % to +0.07 % (5th to 95th percentile), +0.45 % at most; the 8 starts that beat the best
// did so by at most 0.19 %, each estimated below it. Twice the largest overestimate: 1 %
// (docs/performance.md, seventeenth round).
constexpr double kLaterStartMargin = 0.01;

// A contained model's optimum in this model's values, with its objective on all samples where
// that is known already (an exact nesting reproduces the contained model's shaded values, whose
// fit has costed them: fit_models); NaN where it is not.
struct NestedStart {
  std::vector<double> values;
  double cost = NAN;
};

// Where the multi-start begins: the best points of two grids, the coordinate searches from them
// where the shape is mostly in colours, and the contained models' optima, each costed on the
// subsample `small`. Laps "grid" and "coordinate search".
std::vector<Start> multi_starts(const Model& model, Subsamples& subsamples, const std::vector<Sample>& small,
                                bool small_is_all, const FitOptions& options, const Channels& channels,
                                const std::vector<double>& initial, const std::vector<NestedStart>& nested_starts,
                                StageClock& clock) {
  std::vector<Start> starts;
  // The best points of two grids: over the scalar shape parameters with the colours at their
  // start, and over the colours as well. Neither contains the other's best basin on every
  // material: the first misses it when the shape is in the colours (sgd's are all colours),
  // the second, with fewer points per parameter, misses it on some tables (openpbr on
  // paper_white, 0.0471 against 0.0313).
  //
  // The grids only rank coarse starts, which a third of the subsample does as well (on the
  // MERL proxies and a baked table every error but two came out the same, for a tenth to a
  // fifth of every model's time: docs/performance.md); the points kept are costed again on the
  // subsample, where the search and the refinements go on.
  const size_t keep_best = static_cast<size_t>(std::max(1, options.starts));
  const std::vector<Sample>& grid_samples = small_is_all ? small : subsamples.draw(options.subsample / 3, options.seed);
  for (bool colours : {false, true}) {
    if (colours && !has_non_linear_colour(model)) break;
    std::vector<Start> grid =
        grid_starts(model, initial, grid_samples, options.metric, channels, options, colours, keep_best);
    if (!small_is_all)
      for (Start& point : grid) point.cost = solved_cost(model, point.values, small, options.metric, channels);
    // Both grids hold the defaults; a model whose shape is all colours (sgd) has nothing else
    // in the first. The same point searched twice cost sgd a fifth of its fit.
    for (Start& point : grid)
      if (std::none_of(starts.begin(), starts.end(), [&](const Start& s) { return s.values == point.values; }))
        starts.push_back(std::move(point));
  }
  clock.lap("grid");
  // Searched from, besides the grid points themselves: the search does not always end in the
  // better basin.
  if (shape_mostly_in_colours(model)) {
    SolvedCosts known(model);
    for (size_t i = 0, n = starts.size(); i < n; ++i)
      starts.push_back(coordinate_search(model, starts[i], small, options.metric, channels, options, known));
  }
  clock.lap("coordinate search");
  // The contained models' optima are refined too: the multi-start grid may not come near them.
  for (const NestedStart& nested : nested_starts) {
    std::vector<double> values = nested.values;
    const double cost = solved_cost(model, values, small, options.metric, channels);
    starts.push_back({std::move(values), cost});
  }
  return starts;
}

// The starts refined on the subsample: every start screened with a few iterations, the best
// 2·options.starts continued, the best of those walked on further. Returned best first. Laps
// "screen" and "continue".
std::vector<Refinement> screen_and_continue(const LeastSquares& on_subsample, const std::vector<Start>& starts,
                                            bool small_is_all, const FitOptions& options, int& iterations,
                                            StageClock& clock) {
  // On the heavy models every start used to run its 50 iterations, most of their fit; on the
  // MERL proxies the start that finishes best was the first after 8 iterations for sgd and among
  // the six first elsewhere but twice, where one ranked lower finished 0.3 % (principled,
  // red-fabric) and 0.08 % (openpbr, gold-metallic-paint) better (docs/performance.md).
  constexpr int kScreenIterations = 8;
  const int refine_iterations = small_is_all ? options.max_iterations : 50;
  std::vector<Refinement> screened;
  std::set<std::vector<double>> refined;
  for (const Start& start : starts) {
    // A search that found nothing better returns its grid point: the same refinement twice.
    if (!refined.insert(start.values).second) continue;
    Refinement r = on_subsample.run(start.values, std::min(kScreenIterations, refine_iterations));
    iterations += r.iterations;
    if (r.usable) screened.push_back(std::move(r));
  }
  clock.lap("screen");
  std::sort(screened.begin(), screened.end(), [](const Refinement& a, const Refinement& b) { return a.cost < b.cost; });
  screened.resize(std::min(screened.size(), 2 * static_cast<size_t>(std::max(1, options.starts))));
  // A continued start stops at a relative cost change of 1e-6, as the subset stages do: below
  // it, a start in its basin crawled on to its 50 iterations for changes no metric shows.
  for (Refinement& r : screened)
    if (r.iterations >= kScreenIterations) {  // stopped by the screen, not converged
      Refinement more = on_subsample.run(r.values, refine_iterations - r.iterations, 1e-6, r.trust_region_radius, &r);
      iterations += more.iterations;
      if (more.usable) r = std::move(more);
    }
  std::stable_sort(screened.begin(), screened.end(),
                   [](const Refinement& a, const Refinement& b) { return a.cost < b.cost; });
  // The best walks on, to kBestStartIterations in all: a step here costs a tenth of one on the
  // importance subset, whose walk from here is capped (kSubsetWalkIterations). Both measured
  // together on the nine shared tables, all 36 models: sgd better on seven (acrylic_felt_green
  // 21 %) and 7-43 % faster on eight, openpbr+coat+fuzz on blue-acrylic 30 % better, four errors
  // worse by at most 0.03 %; 7 % less CPU in all (docs/performance.md, fourteenth round).
  if (!screened.empty() && !small_is_all) {
    Refinement& first = screened.front();
    Refinement more = on_subsample.run(first.values, kBestStartIterations - refine_iterations, 1e-6,
                                       first.trust_region_radius, &first);
    iterations += more.iterations;
    if (more.usable && more.cost <= first.cost) first = std::move(more);
  }
  clock.lap("continue");
  return screened;
}

// Every candidate met on the way, with its objective on all samples (½Σ, as Ceres counts), or
// for one that cannot be chosen, a part of it above the best kept before it.
// Stages work on subsets whose optimum can be worse on all samples than where they started;
// choosing on all samples discards such a stage, and keeping the contained models' optima
// among the candidates means the result is never worse than theirs. A candidate at the same
// optimum as one kept already (same_optimum) is not costed again, nor one whose cost is known
// on all samples already (Costing::Known: a run on all samples ends with it).
class Candidates {
 public:
  // How a candidate's cost on all samples is found: Alone, in a pass of its own given up once past
  // the best kept (it cannot be chosen then); Known already; or in one pass together with what a
  // later stage needs at the same values: its absolute errors (WithErrors, which the importance
  // subsets are drawn from), its metrics (WithMetrics, which the fit reports where it ends), or
  // its linear values solved exactly (WithLinearSolve, the candidate the fit nearly always ends at).
  enum class Costing { Alone, Known, WithErrors, WithMetrics, WithLinearSolve };

  Candidates(const Model& model, const SampleSet& data, const FitOptions& options, const Channels& channels,
             const ceres::LossFunction* loss, int threads)
      : model_(model),
        data_(data),
        options_(options),
        channels_(channels),
        loss_(loss),
        threads_(threads),
        slots_(value_slots(model)),
        // Where the objective follows from the metrics (every channel, no robust loss:
        // metric_weight_sum), the last candidate's cost and the metrics fit_one reports of the
        // fit, which nearly always ends there, come from one pass.
        costs_from_metrics_(channels == kAllChannels && !loss && !options.per_channel),
        // Where the objective is the linear solve's quadratic (no robust loss, not the log
        // metric), one pass of the solve gives both a candidate's cost and the solution.
        costs_from_linear_solve_(!loss && metric_is_quadratic(options.metric)) {}

  void keep(Refinement r, Costing costing = Costing::Alone) {
    if (!r.usable) return;
    if (std::any_of(kept_.begin(), kept_.end(),
                    [&](const Refinement& c) { return same_optimum(slots_, c.values, r.values); }))
      return;
    if (costing == Costing::WithLinearSolve && costs_from_linear_solve_) {
      std::vector<double> solution = r.values;
      double cost_as_given = NAN;
      const double solved_cost =
          solve_linear(model_, solution, data_.samples, options_.metric, channels_, &cost_as_given);
      if (std::isfinite(cost_as_given)) {
        r.cost = 0.5 * cost_as_given;
        solved_.push_back({r.values, std::move(solution), 0.5 * solved_cost});
        costing = Costing::Known;
      }
    }
    if (costing == Costing::WithErrors) {
      r.cost = 0.5 * cost_and_absolute_errors(model_, r.values, data_.samples, options_.metric, channels_, loss_,
                                              threads_, errors_);
      errors_at_ = r.values;
    } else if (costing == Costing::WithMetrics && costs_from_metrics_) {
      metrics_ = evaluate_metrics(model_, r.values, data_);
      r.cost = 0.5 * std::pow(metrics_->get(options_.metric), 2) * metric_weight_sum(data_.samples, options_.metric);
      metrics_at_ = r.values;
    } else if (costing != Costing::Known) {  // Alone, or a linear solve that gave no cost
      const double beaten_above = best_cost();
      r.cost = 0.5 * cost_of(model_, r.values, data_.samples, options_.metric, channels_, loss_, threads_,
                             2.0 * beaten_above);
    }
    if (std::isfinite(r.cost)) kept_.push_back(std::move(r));
  }

  bool empty() const { return kept_.empty(); }
  // The lowest cost kept; HUGE_VAL while none is.
  double best_cost() const {
    double best = HUGE_VAL;
    for (const Refinement& c : kept_) best = std::min(best, c.cost);
    return best;
  }
  // The first candidate of the lowest cost; nullptr while none is kept.
  Refinement* cheapest() {
    Refinement* best = nullptr;
    for (Refinement& c : kept_)
      if (!best || c.cost < best->cost) best = &c;
    return best;
  }

  // The absolute errors on all samples at `values`, which the importance subsets are drawn from:
  // those of the candidate costed WithErrors, where it is at these values, else a pass of their own.
  std::vector<double> absolute_errors_at(const std::vector<double>& values) {
    std::vector<double> errors =
        errors_at_ == values ? std::move(errors_) : absolute_errors(model_, values, data_.samples, channels_, threads_);
    errors_at_.clear();
    return errors;
  }

  // The cheapest candidate with its linear values solved exactly on all samples, kept with its
  // metrics (FitOptions::metrics): the stopping rule (a relative cost change of 1e-6) leaves them
  // wherever the cost is flat enough, which under a bright peak can be a diffuse albedo a percent
  // off its least-squares value. A candidate costed WithLinearSolve has its solution already, and
  // its cost there. A fit without metrics keeps the solution at that cost (for a quadratic
  // metric, from the solve's normal equations): no pass of its own.
  void keep_cheapest_with_exact_linear_values() {
    Refinement exact = *cheapest();
    const auto known =
        std::find_if(solved_.begin(), solved_.end(), [&](const Solved& s) { return s.as_costed == exact.values; });
    double solved_cost = NAN;
    if (known != solved_.end()) {
      exact.values = known->solution;
      solved_cost = known->cost;
    } else {
      const double cost = solve_linear(model_, exact.values, data_.samples, options_.metric, channels_);
      if (costs_from_linear_solve_) solved_cost = 0.5 * cost;  // without a robust loss, which it leaves out
    }
    if (options_.metrics) return keep(std::move(exact), Costing::WithMetrics);
    exact.cost = solved_cost;
    keep(std::move(exact), std::isfinite(solved_cost) ? Costing::Known : Costing::Alone);
  }

  // The metrics computed with a candidate's cost, if that candidate is at `values`.
  std::optional<Metrics> take_metrics_at(const std::vector<double>& values) {
    if (metrics_ && metrics_at_ == values) return std::move(metrics_);
    return std::nullopt;
  }

 private:
  const Model& model_;
  const SampleSet& data_;
  const FitOptions& options_;
  const Channels& channels_;
  const ceres::LossFunction* loss_;
  const int threads_;
  const std::vector<ValueSlot> slots_;
  const bool costs_from_metrics_, costs_from_linear_solve_;
  std::vector<Refinement> kept_;
  std::vector<double> errors_, errors_at_;  // WithErrors' absolute errors, at errors_at_
  std::optional<Metrics> metrics_;          // WithMetrics' metrics, at metrics_at_
  std::vector<double> metrics_at_;
  struct Solved {
    std::vector<double> as_costed, solution;
    double cost;  // at the solution (½Σ), from the same normal equations; NaN where they do not give it
  };
  std::vector<Solved> solved_;
};

ChannelFit fit_channels(const Model& model, const SampleSet& data, Subsamples& subsamples, const FitOptions& options,
                        const Channels& channels, const std::vector<double>& initial,
                        const std::vector<NestedStart>& nested_starts) {
  using Costing = Candidates::Costing;
  ChannelFit fit;
  StageClock clock(fit);
  const int threads = thread_count(options.threads);
  const std::vector<Sample>& small = subsamples.draw(options.subsample, options.seed);
  clock.lap("subsample");
  const bool small_is_all = small.size() == data.samples.size();

  const std::vector<Start> starts = options.single_start ? std::vector<Start>{{initial, 0.0}}
                                                         : multi_starts(model, subsamples, small, small_is_all, options,
                                                                        channels, initial, nested_starts, clock);

  double loss_scale = options.loss_scale;
  if (options.loss != LossKind::None && loss_scale <= 0.0) {
    // 1.4826·MAD estimates σ; Huber's and Cauchy's usual tuning constants for 95% efficiency.
    const double sigma = 1.4826 * median_abs_residual(model, starts[0].values, small, options.metric, channels);
    loss_scale = std::max(sigma, 1e-12) * (options.loss == LossKind::Huber ? 1.345 : 2.385);
  }
  const std::unique_ptr<ceres::LossFunction> loss = make_loss(options.loss, loss_scale);
  // The covariance is estimated where the last run on all samples ended, with its last Jacobian.
  const LeastSquares on_all(model, data.samples, options.metric, channels, loss.get(), options,
                            /*end_jacobian_read=*/options.uncertainties);

  Candidates candidates(model, data, options, channels, loss.get(), threads);
  // The sizes of the importance subsets walked after the subsample (see below). The absolute errors
  // on all samples of the subsample's best start draw them: computed with its cost on all samples,
  // in one pass.
  const std::vector<size_t> ladder = options.single_start
                                         ? std::vector<size_t>{}
                                         : importance_subset_draws(small.size(), data.size(), options.polish_after);
  const bool draws_subsets = !ladder.empty();
  for (const NestedStart& nested : nested_starts) {
    Refinement r;
    r.values = nested.values;
    r.usable = true;
    r.termination = "the optimum of a contained model";
    r.free_index = on_all.free_values();
    r.cost = nested.cost;
    candidates.keep(std::move(r), std::isfinite(nested.cost) ? Costing::Known : Costing::Alone);
  }
  clock.lap("nested starts");

  Refinement best;
  std::vector<Refinement> later_starts;  // continued starts costed after the importance subsets
  if (!options.single_start) {
    const LeastSquares on_subsample(model, small, options.metric, channels, loss.get(), options);
    const std::vector<Refinement> screened =
        screen_and_continue(on_subsample, starts, small_is_all, options, fit.iterations, clock);
    // Every continued start's refinement is a candidate: the best on the subsample is not always
    // the best on all samples (a many-parameter model can fit the subsample's few grazing samples
    // in a way all samples do not confirm). The best is costed first: its errors on all samples
    // draw the importance subset, and the others are given up once past its cost, or where an
    // importance subset follows, looked at after the walk on it (`later_starts`).
    for (size_t i = 0; i < screened.size() && !small_is_all; ++i) {
      // A start that ended where an earlier one did is not costed on all samples again.
      const Refinement& r = screened[i];
      if (std::any_of(screened.begin(), screened.begin() + i,
                      [&](const Refinement& earlier) { return same_cost(earlier.cost, r.cost); }))
        continue;
      if (i > 0 && draws_subsets)
        later_starts.push_back(r);
      else
        candidates.keep(r, i == 0 && draws_subsets ? Costing::WithErrors : Costing::Alone);
    }
    if (!screened.empty()) best = screened.front();
    clock.lap("candidate costs");
    if (!best.usable) {
      best.values = starts[0].values;
      best.termination = "no start converged on the subsample";
    }
  }
  // Refine on ever larger subsets (×10 each, the last at least polish_after draws where the
  // samples are twice that: importance_subset_draws) before all samples: a large table's cost
  // valley can be long, and walking it on a tenth of the data costs a tenth as much per step.
  // Each subset is drawn where the data or the current fit's errors are large.
  const int walk_iterations = std::min(options.max_iterations, kSubsetWalkIterations);
  size_t largest_draws = small.size();
  std::vector<Sample> largest_subset;
  Refinement subset_optimum;  // the last walk on the largest subset, its cost on that subset
  for (size_t rung = 0; rung < ladder.size(); ++rung) {
    const size_t draws = ladder[rung];
    std::vector<Sample> subset =
        importance_subset(data.samples, draws, options.seed, candidates.absolute_errors_at(best.values));
    clock.lap("subset draws");
    const LeastSquares on_subset(model, subset, options.metric, channels, loss.get(), options);
    Refinement r = on_subset.run(best.values, walk_iterations, 1e-6, 0.0, best.usable ? &best : nullptr);
    fit.iterations += r.iterations;
    clock.lap(fmt::format("subset of {}", draws));
    subset_optimum = r;
    if (r.usable) {
      best = r;
      // A larger subset follows (a table whose subsample hit few distinct samples): it is drawn
      // from this optimum's errors, which its cost on all samples gives in the same pass.
      const bool another_subset = rung + 1 < ladder.size();
      candidates.keep(std::move(r), another_subset ? Costing::WithErrors : Costing::WithLinearSolve);
    }
    clock.lap("candidate costs");
    largest_draws = draws;
    largest_subset = std::move(subset);
  }
  // The other continued starts, after the walks on the importance subsets: a start is costed on
  // all samples only where the largest subset cannot tell it costlier than the best candidate.
  // The subset is drawn from the best start's errors, and its weights make sums over it unbiased
  // estimates of sums over all samples; a start that could still be chosen ends near the best,
  // and so errs where the best does, where the subset is dense. First its own cost estimated
  // there, within kLaterStartMargin of the best cost known on all samples; then its difference
  // from the best, estimated draw by draw (later_start_surely_costlier).
  // A subset that does not cover the table (drawn into one spike of a start's errors:
  // subset_covers) judges nothing, and every such start is costed on all samples.
  const bool subset_covers_table = !largest_subset.empty() && subset_covers(largest_subset, data.samples);
  std::vector<double> best_terms, best_terms_at;  // the cheapest candidate's terms on the subset
  for (const Refinement& r : later_starts) {
    if (!subset_covers_table) {
      candidates.keep(r);
      continue;
    }
    const std::vector<double> terms =
        cost_per_sample(model, r.values, largest_subset, options.metric, channels, loss.get(), threads);
    const double estimate = 0.5 * std::accumulate(terms.begin(), terms.end(), 0.0);
    if (estimate > (1.0 + kLaterStartMargin) * candidates.best_cost()) continue;
    const Refinement& best = *candidates.cheapest();
    if (best_terms_at != best.values) {
      best_terms_at = best.values;
      best_terms = cost_per_sample(model, best.values, largest_subset, options.metric, channels, loss.get(), threads);
    }
    if (!later_start_surely_costlier(terms, best_terms, best.cost, r.free_index.size())) candidates.keep(r);
  }
  if (!later_starts.empty()) clock.lap("candidate costs");
  bool polish = !options.single_start && largest_draws >= options.polish_after;
  // The subset stages start from the small subsample's best, which on all samples can be worse
  // than another continued start or a contained model's optimum (the OpenPBR layers'). That
  // candidate is walked on the largest subset too, so that all samples only polish, as for the
  // rest, instead of walking the whole valley at ten times the cost per step (openpbr+coat on
  // gold-metallic-paint: 31 steps, 6.9 s).
  std::vector<double> walked_on_subset;  // that candidate's values
  if (polish && !candidates.empty()) {
    const Refinement on_all_best = *candidates.cheapest();
    if (on_all_best.values != best.values) {
      walked_on_subset = on_all_best.values;
      const LeastSquares on_subset(model, largest_subset, options.metric, channels, loss.get(), options);
      Refinement r = on_subset.run(on_all_best.values, walk_iterations, 1e-6, 0.0, &on_all_best);
      fit.iterations += r.iterations;
      clock.lap(fmt::format("subset of {}", largest_draws));
      subset_optimum = r;
      if (r.usable) {
        best = r;
        candidates.keep(std::move(r), Costing::WithLinearSolve);
      }
      clock.lap("candidate costs");
    }
  }
  if (options.single_start || !small_is_all) {
    // From the best candidate so far on all samples: to a relative cost change of 1e-6, far
    // below any metric's reported precision, or only a few polishing steps after a large
    // subset whose optimum is also the best candidate on all samples (FitOptions).
    Refinement* from = candidates.cheapest();
    const std::vector<double> start = options.single_start ? initial : from ? from->values : best.values;
    // A contained model's optimum that stays the best on all samples after its walk on the subset
    // is polished too, not walked again on all samples (openpbr+coat+fuzz on a baked
    // Cook-Torrance table: three gradients and the covariance on all samples, 5.8 s, for no step).
    polish = polish && from && (from->values == best.values || from->values == walked_on_subset);
    if (polish && options.polish_iterations <= 0) {
      from->termination +=
          fmt::format("; not polished: no steps on all samples after the importance subset ({} draws)", largest_draws);
    } else if (polish && subset_stood_in(*from, subset_optimum)) {
      // The subset's optimum is the fit's: a polish would gain far below any reported digit.
      from->termination += fmt::format(
          "; not polished: on all samples its cost is within {:g} % of the importance subset's estimate ({} draws)",
          100.0 * kSubsetAgreement, largest_draws);
    } else {
      // A candidate that came from a run starts with the values that run held on their bounds.
      const Refinement* earlier = !options.single_start && from && from->iterations > 0 ? from : nullptr;
      Refinement r = polish ? on_all.polish(*from, std::min(options.polish_iterations, options.max_iterations))
                            : on_all.run(start, options.max_iterations, 1e-6, 0.0, earlier);
      fit.iterations += r.iterations;
      clock.lap("all samples");
      if (polish && r.usable && r.iterations >= options.polish_iterations)
        r.termination =
            fmt::format("polished: {} steps on all samples after converging on an importance subset of {} draws",
                        r.iterations, largest_draws);
      candidates.keep(r, Costing::Known);
      if (!r.usable && candidates.empty()) best = std::move(r);  // reported as the failure it is
    }
  } else {
    candidates.keep(best, Costing::Known);  // the subsample is all samples
  }
  if (!candidates.empty()) {
    candidates.keep_cheapest_with_exact_linear_values();
    best = *candidates.cheapest();
    fit.metrics = candidates.take_metrics_at(best.values);
  }
  clock.lap("candidate costs");
  // JᵀJ at the optimum, over all samples. An estimate from the largest importance subset took a
  // tenth of the time, but on the shared tables its standard deviations were up to 30 % off for
  // values inside their bounds (Cook-Torrance's m and specular on blue-acrylic, sgd's f1 on
  // paper_white) and 5 times off for values on a bound (wrap on vch_golden_yellow): the subset
  // holds few of the dim samples that determine some values (docs/performance.md, twenty-third
  // round).
  if (options.uncertainties) {
    on_all.estimate_covariance(best);
    clock.lap("covariance");
  }
  fit.residuals = data.size() * static_cast<size_t>(std::count(channels.begin(), channels.end(), true));
  fit.final = std::move(best);
  return fit;
}

// Fills result.parameters from one or three channel fits. stddev = √(σ² (JᵀJ)⁻¹), with
// σ² = 2·cost/(residuals − free values) the residual variance (Ceres' cost is ½Σr²).
void report_parameters(const Model& model, const std::vector<ChannelFit>& fits, bool per_channel, FitResult& result) {
  const std::vector<ValueSlot> slots = value_slots(model);
  // stddev per flattened value per fit (NaN unless estimated).
  std::vector<std::vector<double>> stddev(fits.size(), std::vector<double>(slots.size(), NAN));
  std::vector<std::vector<bool>> identifiable(fits.size(), std::vector<bool>(slots.size(), true));
  std::string unknown_uncertainty;
  for (size_t f = 0; f < fits.size(); ++f) {
    const Refinement& r = fits[f].final;
    // With no more residuals than free values the residual variance is unknown, and so is every
    // uncertainty (stddevs stay NaN) however well the values fit.
    const double dof = static_cast<double>(fits[f].residuals) - static_cast<double>(r.free_index.size());
    if (dof <= 0.0 && !r.free_index.empty())
      unknown_uncertainty =
          fmt::format("uncertainties unknown: {} residuals for {} free values leave no degrees of freedom",
                      fits[f].residuals, r.free_index.size());
    const double variance = dof > 0.0 ? 2.0 * r.cost / dof : NAN;
    for (size_t k = 0; k < r.free_index.size(); ++k) {
      const int i = r.free_index[k];
      if (!r.identifiable.empty()) identifiable[f][i] = r.identifiable[k];
      // A free value with no variance at all got none from the data: the pseudo-inverse
      // dropped its direction.
      if (r.covariance.size() && !(r.covariance(k, k) > 0.0)) identifiable[f][i] = false;
      if (r.covariance.size() && identifiable[f][i]) stddev[f][i] = std::sqrt(variance * r.covariance(k, k));
    }
  }

  int offset = 0;
  for (const ParamSpec& p : model.parameters()) {
    ParameterEstimate estimate;
    estimate.name = p.name;
    const int entries = (p.channels == 3 || per_channel) ? 3 : 1;
    for (int e = 0; e < entries; ++e) {
      // Which fit determined this entry: the channel's own fit when fitting per channel.
      const size_t f = per_channel ? static_cast<size_t>(e) : 0;
      const int i = offset + (p.channels == 3 ? e : 0);
      const double value = fits[f].final.values[i];
      estimate.value.push_back(value);
      estimate.stddev.push_back(stddev[f][i]);
      estimate.identifiable = estimate.identifiable && identifiable[f][i];
      estimate.at_bound = estimate.at_bound || at_bound(p, value);
    }
    result.parameters.push_back(estimate);
    offset += p.channels;
  }
  if (!unknown_uncertainty.empty()) result.warnings.push_back(unknown_uncertainty);
}

// On isotropic data a lobe's orientation about the normal is not a property of the material:
// the samples are spread over every azimuth (AzimuthSpread), so where the fitted widths are
// equal the orientation changes nothing, and where noise makes them differ a little it would
// report a confident but meaningless angle.
void mark_orientation_unidentifiable(FitResult& result, const Model& model) {
  for (ParameterEstimate& estimate : result.parameters) {
    const ParamSpec* spec = model.find_parameter(estimate.name);
    if (!spec || spec->role != Role::Orientation) continue;
    estimate.identifiable = false;
    std::fill(estimate.stddev.begin(), estimate.stddev.end(), NAN);
  }
}

// A contained model's optimum in the outer model's values, one vector per channel (the three
// are equal unless the contained model was fitted per channel), and its objective on all samples
// over every channel where it is known (NestedStart).
using ChannelVectors = std::array<std::vector<double>, 3>;
struct NestedOptimum {
  ChannelVectors values;
  double cost = NAN;
};

void check_fit_input(const SampleSet& data) {
  if (data.empty()) fail("{}: no samples to fit", data.source.empty() ? "input" : data.source);
  check_sample_magnitudes(data);  // before any solver: values that would overflow its cost are refused
}

// Fits one model from its grid and from the contained models' optima `nested`. A per-channel
// fit first fits the shared model and starts each channel from it, so it contains the shared
// fit as well.
FitResult fit_one(const Model& model, const SampleSet& data, Subsamples& subsamples, const FitOptions& options,
                  const std::vector<NestedOptimum>& nested) {
  const auto started = std::chrono::steady_clock::now();
  FitResult result;
  result.model = model.name();
  result.samples = data.size();
  if (!options.initial_values.empty() && static_cast<int>(options.initial_values.size()) != model.num_values())
    fail("{}: {} initial values given, the model has {}", model.name(), options.initial_values.size(),
         model.num_values());
  const std::vector<double> initial = options.initial_values.empty() ? model.default_values() : options.initial_values;
  // A fit of one channel has another objective than the one known for every channel.
  auto nested_for = [&](int channel) {
    std::vector<NestedStart> starts;
    if (!options.single_start)
      for (const NestedOptimum& n : nested) starts.push_back({n.values[channel], options.per_channel ? NAN : n.cost});
    return starts;
  };

  std::vector<ChannelFit> fits;
  std::string failure;
  auto count = [&](const ChannelFit& fit) {  // its iterations and its profile
    result.iterations += fit.iterations;
    for (const StageProfile& stage : fit.stages) add_stage(result.stages, stage);
  };
  auto record = [&](ChannelFit fit) {
    if (!fit.final.usable && failure.empty()) failure = fit.final.termination;
    count(fit);
    fits.push_back(std::move(fit));
  };
  if (!options.per_channel) {
    record(fit_channels(model, data, subsamples, options, kAllChannels, initial, nested_for(0)));
  } else {
    std::vector<NestedStart> shared_starts;
    for (int c = 0; c < 3; ++c)
      for (NestedStart& s : nested_for(c)) shared_starts.push_back(std::move(s));
    const ChannelFit shared = fit_channels(model, data, subsamples, options, kAllChannels, initial, shared_starts);
    count(shared);
    for (int c = 0; c < 3; ++c) {
      Channels mask{false, false, false};
      mask[c] = true;
      std::vector<NestedStart> starts = nested_for(c);
      if (shared.final.usable) starts.push_back({shared.final.values});
      record(fit_channels(model, data, subsamples, options, mask, shared.final.usable ? shared.final.values : initial,
                          starts));
    }
  }
  result.termination = fits.back().final.termination;

  if (options.per_channel) {
    for (int c = 0; c < 3; ++c) {
      // Channel c's vector: its own fit, with every channel's colour components filled in.
      std::vector<double> values = fits[c].final.values;
      const std::vector<ValueSlot> slots = value_slots(model);
      for (size_t i = 0; i < slots.size(); ++i)
        if (slots[i].param->channels == 3) values[i] = fits[slots[i].channel].final.values[i];
      result.channel_values.push_back(values);
    }
    result.values = result.channel_values[0];
  } else {
    result.values = fits[0].final.values;
  }
  report_parameters(model, fits, options.per_channel, result);
  if (data.isotropic) mark_orientation_unidentifiable(result, model);
  // A fit per channel has no objective over all channels: it keeps its metrics.
  const bool with_metrics = options.metrics || options.per_channel;
  if (!options.per_channel) result.objective = fits[0].final.cost;
  if (!options.per_channel && fits[0].metrics)
    result.metrics = *fits[0].metrics;
  else if (with_metrics)
    result.metrics = evaluate_metrics(model, result.values, data, result.channel_values);

  const bool finite =
      std::all_of(result.values.begin(), result.values.end(), [](double v) { return std::isfinite(v); }) &&
      std::isfinite(with_metrics ? result.metrics.get(options.metric) : result.objective);
  result.ok = failure.empty() && finite;
  if (!result.ok)
    result.error = !failure.empty() ? "the fit diverged (" + failure + ")" : "the fit produced non-finite values";
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace

FitResult fit_model(const Model& model, const SampleSet& data, const FitOptions& options) {
  return fit_models({&model}, data, options).front();
}

namespace {

// fit_one, with a fit that goes wrong reported as failed rather than thrown.
FitResult fit_or_failure(const Model& model, const SampleSet& data, Subsamples& subsamples, const FitOptions& options,
                         const std::vector<NestedOptimum>& nested) {
  FitResult result;
  try {
    result = fit_one(model, data, subsamples, options, nested);
  } catch (const Error&) {
    throw;  // bad input or options: the same for every model
  } catch (const std::exception& e) {
    result.model = model.name();
    result.error = e.what();
    result.samples = data.size();
  }
  return result;
}

// An anisotropic model on isotropic data, as its isotropic form (model.h) fitted: the samples
// are the same at every azimuth, so they cannot tell the widths apart or orient them. Fitted
// freely, the model would trade the azimuthal variation it cannot match for the heavier tail of
// its azimuthal average (ward-aniso on RGL's paper, felt and colodur: widths more than 15% apart
// for a little less error) and report a confident shape the material does not have.
FitResult in_isotropic_form(const Model& model, const Nesting& form, const Model& inner, const FitResult& inner_fit,
                            const SampleSet& data) {
  FitResult r = inner_fit;  // its status, iterations, termination, time and sample count
  r.model = model.name();
  r.values.clear();
  r.channel_values.clear();
  r.parameters.clear();
  r.warnings.clear();  // they name the inner model's parameters; judge() writes this model's
  if (!inner_fit.ok) return r;
  r.values = embed_values(model, form, inner, inner_fit.values);
  for (const std::vector<double>& channel : inner_fit.channel_values)
    r.channel_values.push_back(embed_values(model, form, inner, channel));
  for (const ParamSpec& p : model.parameters()) {
    ParameterEstimate e;
    e.name = p.name;
    const auto copy =
        std::find_if(form.copies.begin(), form.copies.end(), [&](const Nesting::Copy& c) { return c.to == p.name; });
    const auto source = copy == form.copies.end()
                            ? inner_fit.parameters.end()
                            : std::find_if(inner_fit.parameters.begin(), inner_fit.parameters.end(),
                                           [&](const ParameterEstimate& f) { return f.name == copy->from; });
    if (source == inner_fit.parameters.end()) {  // held by the form: the orientation
      e.value.assign(p.channels, r.values[model.offset_of(p.name)]);
      e.stddev.assign(p.channels, NAN);
      e.identifiable = false;
    } else {
      e.identifiable = source->identifiable;
      for (size_t i = 0; i < source->value.size(); ++i) {
        const double x = source->value[i], dx = 1e-6 * std::max(1.0, std::abs(x));
        auto to_outer = [&](double inner_value) {
          return copy->transform ? copy->transform(inner_value) : inner_value;
        };
        e.value.push_back(to_outer(x));
        e.stddev.push_back(source->stddev[i] * std::abs(to_outer(x + dx) - to_outer(x - dx)) / (2.0 * dx));
        e.at_bound = e.at_bound || at_bound(p, e.value.back());
      }
    }
    r.parameters.push_back(std::move(e));
  }
  r.warnings.push_back(fmt::format("isotropic data: {} was fitted in its isotropic form, {} ({})", model.name(),
                                   inner.name(), form.why));
  r.metrics = evaluate_metrics(model, r.values, data, r.channel_values);
  return r;
}

// `nested`: the contained models' optima in the full model's values.
FitResult fit_held(const HeldModel& held, const SampleSet& data, Subsamples& subsamples, const FitOptions& options,
                   const std::vector<NestedOptimum>& nested = {}) {
  FitOptions own = options;
  const int full_count = held.num_values() + held.held_count();
  if (!own.initial_values.empty() && static_cast<int>(own.initial_values.size()) != full_count)
    fail("{}: {} initial values given, the model has {}", held.name(), own.initial_values.size(), full_count);
  if (!own.initial_values.empty()) own.initial_values = held.free_values(own.initial_values);
  std::vector<NestedOptimum> free_nested;
  for (const NestedOptimum& start : nested) {
    NestedOptimum free;
    for (int c = 0; c < 3; ++c) free.values[c] = held.free_values(start.values[c]);
    // Its cost holds where the held values are those the start had.
    if (held.full_values(free.values[0].data()) == start.values[0]) free.cost = start.cost;
    free_nested.push_back(std::move(free));
  }
  return held.full_result(fit_or_failure(held, data, subsamples, own, free_nested));
}

// On isotropic data, a model with neither an isotropic form nor held parameters of the user's
// is fitted with its lobe held isotropic (isotropic_holds); the user's held parameters get
// those added. An isotropic form is fitted in the model's place instead (in_isotropic_form).
std::vector<std::pair<std::string, double>> holds_on(const SampleSet& data, const Model& model,
                                                     std::vector<std::pair<std::string, double>> holds) {
  if (!data.isotropic) return holds;
  for (const auto& hold : isotropic_holds(model))
    if (std::none_of(holds.begin(), holds.end(), [&](const auto& h) { return h.first == hold.first; }))
      holds.push_back(hold);
  return holds;
}

void note_isotropic_holds(const Model& model, FitResult& r) {
  std::string held;
  for (const auto& [name, value] : isotropic_holds(model))
    held += fmt::format("{}{} = {:.4g}", held.empty() ? "" : ", ", name, value);
  r.warnings.push_back(
      fmt::format("isotropic data: {} was fitted with its lobe held isotropic ({})", model.name(), held));
}

}  // namespace

std::vector<FitResult> fit_models(const std::vector<const Model*>& models, const SampleSet& data,
                                  const FitOptions& options) {
  check_fit_input(data);
  check_held(models, options.fixed);
  // Every model fitted in this run, the requested ones and those they contain, by name.
  std::map<std::string, FitResult> fitted;
  Subsamples subsamples(data);
  std::set<std::string> in_progress;
  // A fit's objective on all samples from its error (metric_weight_sum): where no robust loss
  // reweights the residuals and no channel has values of its own. NaN elsewhere.
  const double weight_sum = metric_weight_sum(data.samples, options.metric);
  auto objective_of = [&](const FitResult& r) -> double {
    const bool known = options.loss == LossKind::None && !options.per_channel && r.channel_values.empty();
    if (!known) return NAN;
    const double metric = r.metrics.get(options.metric);
    return std::isfinite(metric) ? 0.5 * metric * metric * weight_sum : r.objective;  // a start's: no metrics
  };
  auto requested = [&](const std::string& name) {
    return std::any_of(models.begin(), models.end(), [&](const Model* m) { return m->name() == name; });
  };
  // A requested model fitted in its isotropic form reports that form's fit, uncertainties included.
  auto reported_as_isotropic_form = [&](const std::string& name) {
    return data.isotropic && std::any_of(models.begin(), models.end(), [&](const Model* m) {
             const Nesting* form = isotropic_form(*m);
             return form && form->inner == name;
           });
  };
  // Fits `model` after the models it contains: exact nestings always (they carry the guarantee),
  // approximate ones only when that model is fitted in this run anyway.
  std::function<const FitResult&(const Model&)> fit = [&](const Model& model) -> const FitResult& {
    if (auto it = fitted.find(model.name()); it != fitted.end()) return it->second;
    in_progress.insert(model.name());
    std::vector<NestedOptimum> nested;
    for (const Nesting& nesting : model.nestings()) {
      const Model* inner = find_model(nesting.inner);
      if (!inner || in_progress.count(inner->name())) continue;
      if (!nesting.exact && !requested(inner->name()) && !fitted.count(inner->name())) continue;
      const FitResult& r = fit(*inner);
      if (!r.ok) continue;
      NestedOptimum embedded;
      for (int c = 0; c < 3; ++c)
        embedded.values[c] =
            embed_values(model, nesting, *inner, r.channel_values.empty() ? r.values : r.channel_values[c]);
      // An exact nesting's values shade as the contained model's optimum: its cost is that fit's.
      if (nesting.exact) embedded.cost = objective_of(r);
      nested.push_back(std::move(embedded));
    }
    // A start given in the options is the requested models'; contained models fitted on the
    // way (and the baseline) start from their own grids. One fitted only as a start is not
    // polished on all samples either: the model that contains it walks on from its optimum on
    // importance subsets of its own and polishes its own end. openpbr's polish on blue-acrylic
    // was 0.5 s of each OpenPBR layer's fit; without it no error changed on the sixteen shared
    // tables.
    // Nor does it need the metrics of its result: the requested fit takes its objective. The
    // baseline keeps them, for the verdicts.
    FitOptions own = options;
    if (!requested(model.name())) {
      const bool reported = reported_as_isotropic_form(model.name());
      own.initial_values.clear();
      own.single_start = false;
      own.uncertainties = reported;
      own.metrics = reported || model.name() == kBaselineModel;
      if (!reported) own.polish_iterations = 0;
    }
    const Nesting* form = data.isotropic ? isotropic_form(model) : nullptr;
    const auto form_fit = form ? fitted.find(form->inner) : fitted.end();
    const HeldModel isotropic(model, form ? std::vector<std::pair<std::string, double>>{} : holds_on(data, model, {}));
    FitResult result;
    if (form_fit != fitted.end()) {
      result = in_isotropic_form(model, *form, *find_model(form->inner), form_fit->second, data);
    } else if (isotropic.holds_any()) {
      result = fit_held(isotropic, data, subsamples, own, nested);
      note_isotropic_holds(model, result);
    } else {
      result = fit_or_failure(model, data, subsamples, own, nested);
    }
    in_progress.erase(model.name());
    return fitted.emplace(model.name(), std::move(result)).first->second;
  };

  const Model* lambert = find_model(kBaselineModel);
  const FitResult* baseline = lambert ? &fit(*lambert) : nullptr;
  const double zero_error = zero_prediction_error(data, options.metric);
  std::vector<FitResult> results;
  for (const Model* model : models) {
    if (options.on_model_start) options.on_model_start(results.size(), models.size(), model->name());
    // Held parameters (FitOptions::fixed): the model of the others, fitted on its own.
    const HeldModel held(*model, options.fixed.empty() ? options.fixed : holds_on(data, *model, options.fixed));
    FitResult r = held.holds_any() ? fit_held(held, data, subsamples, options) : fit(*model);
    if (held.holds_any() && !options.fixed.empty() && data.isotropic && !isotropic_holds(*model).empty())
      note_isotropic_holds(*model, r);
    judge(*model, baseline, zero_error, options.metric, data.isotropic, r);
    results.push_back(std::move(r));
  }
  return results;
}

}  // namespace brdffit
