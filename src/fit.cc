// The generic fitter (see fit.h for the strategy): the orchestration of its stages. The pieces
// live in their own units: the objective with doubles (fit_objective.h), the linear colours
// solved exactly (variable_projection.h), the subset the early stages run on
// (importance_subset.h), Ceres' residuals (fit_residual.h) and the metrics (metrics.cc).
#include "brdffit/fit.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <set>

#include "brdffit/error.h"
#include "brdffit/fit_objective.h"
#include "brdffit/fit_residual.h"
#include "brdffit/held_model.h"
#include "brdffit/importance_subset.h"
#include "brdffit/parallel.h"
#include "brdffit/registry.h"
#include "brdffit/variable_projection.h"

namespace brdffit {

namespace {

// Where each flattened value comes from: its parameter and its channel (0 for scalars).
struct ValueSlot {
  const ParamSpec* param;
  int channel;
};

// FitOptions::cancel is looked at before and after every grid, coordinate-search pass and solve,
// and by Ceres at each iteration (AtEachIteration).
void stop_if_cancelled(const FitOptions& options) {
  if (options.cancel && options.cancel->load()) throw Cancelled();
}

// FitOptions::on_iteration, then FitOptions::cancel, after each of Ceres' iterations.
class AtEachIteration : public ceres::IterationCallback {
 public:
  AtEachIteration(const std::string& model, const FitOptions& options) : model_(model), options_(options) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    if (options_.on_iteration) options_.on_iteration(model_, summary.iteration);
    return options_.cancel && options_.cancel->load() ? ceres::SOLVER_ABORT : ceres::SOLVER_CONTINUE;
  }

 private:
  const std::string& model_;
  const FitOptions& options_;
};

std::vector<ValueSlot> value_slots(const Model& model) {
  std::vector<ValueSlot> slots;
  for (const ParamSpec& p : model.parameters())
    for (int c = 0; c < p.channels; ++c) slots.push_back({&p, c});
  return slots;
}

// A value is fitted in a channel-restricted fit when it is a scalar, or a colour component of
// a fitted channel.
bool is_fitted(const ValueSlot& slot, const Channels& channels) {
  return slot.param->channels == 1 || channels[slot.channel];
}

std::unique_ptr<ceres::LossFunction> make_loss(LossKind kind, double scale) {
  switch (kind) {
    case LossKind::Huber: return std::make_unique<ceres::HuberLoss>(scale);
    case LossKind::Cauchy: return std::make_unique<ceres::CauchyLoss>(scale);
    case LossKind::None: break;
  }
  return nullptr;
}

// ---------------------------------------------------------------------------------------------
// Multi-start grid over the shape parameters.

// One shape parameter's value at coordinate t ∈ (0, 1) of its range, log-spaced for
// exponents and roughness.
double at_fraction(const ParamSpec& p, double t) {
  const double value =
      p.spacing == Spacing::Log ? p.lower * std::pow(p.upper / p.lower, t) : p.lower + t * (p.upper - p.lower);
  return p.integer ? std::round(value) : value;
}

// Candidate values for one shape parameter: n points spread over its range (log-spaced for
// exponents and roughness), or every integer for integer parameters.
std::vector<double> grid_axis(const ParamSpec& p, int n) {
  std::vector<double> axis;
  if (p.integer) {
    const int lo = static_cast<int>(std::ceil(p.lower)), hi = static_cast<int>(std::floor(p.upper));
    const int step = std::max(1, (hi - lo + 1) / std::max(n, 1));
    for (int k = lo; k <= hi; k += step) axis.push_back(k);
    return axis;
  }
  for (int k = 0; k < n; ++k) axis.push_back(at_fraction(p, (k + 0.5) / n));
  return axis;
}

struct Start {
  std::vector<double> values;
  double cost;
};

// Solves the linear parameters of `values` and returns the cost there (cost_of without a loss):
// from the solve's normal equations where they give it, which saves a pass over the samples per
// grid point and search step (a quarter of those stages for a model with two linear colours).
double solved_cost(const Model& model, std::vector<double>& values, const std::vector<Sample>& samples, Metric metric,
                   const Channels& channels) {
  const double cost = solve_linear(model, values, samples, metric, channels);
  return std::isnan(cost) ? cost_of(model, values, samples, metric, channels, nullptr) : cost;
}

// The i-th point (from 1) of the Halton sequence in base `base`: a low-discrepancy coordinate in (0, 1).
double halton(size_t i, int base) {
  double value = 0.0, digit = 1.0 / base;
  for (; i > 0; i /= base, digit /= base) value += digit * static_cast<double>(i % base);
  return value;
}

// Every grid point's values with the linear parameters solved, sorted by cost on `samples`. The
// grid spans the scalar non-linear parameters, and with `colours` the non-linear colours too, a
// colour taking the same value in every channel (a start: the refinement separates them).
std::vector<Start> grid_starts(const Model& model, const std::vector<double>& initial,
                               const std::vector<Sample>& samples, Metric metric, const Channels& channels,
                               const FitOptions& options, bool colours) {
  std::vector<const ParamSpec*> axes_params;
  for (const ParamSpec& p : model.parameters())
    if (!p.linear && (colours || p.channels == 1)) axes_params.push_back(&p);
  const int dims = static_cast<int>(axes_params.size());
  const int per_axis =
      dims == 0 ? 1 : std::clamp(static_cast<int>(std::floor(std::pow(options.grid_points, 1.0 / dims))), 2, 24);
  // A lattice with 2 points per axis only tries each parameter near a quarter and three quarters
  // of its range; with that many dimensions a Halton design spreads the same budget over more
  // distinct values of every parameter.
  const bool lattice = per_axis >= 3 || dims <= 2;
  std::vector<std::vector<double>> axes;
  size_t total = 1;
  if (lattice) {
    for (const ParamSpec* p : axes_params) {
      axes.push_back(grid_axis(*p, per_axis));
      total *= axes.back().size();
    }
  } else {
    total = static_cast<size_t>(std::max(options.grid_points, 1));
  }
  static constexpr int kPrimes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61, 67, 71};
  auto set = [&](std::vector<double>& values, const ParamSpec& p, double value) {
    const int offset = model.offset_of(p.name);
    std::fill_n(values.begin() + offset, p.channels, value);
  };

  std::vector<Start> starts(total + 1);
  // The last entry starts from `initial` itself (the defaults), so the grid never does worse.
  parallel_for(total + 1, thread_count(options.threads), [&](size_t index) {
    std::vector<double> values = initial;
    size_t rest = index;
    if (index < total && lattice)
      for (int d = 0; d < dims; ++d) {
        set(values, *axes_params[d], axes[d][rest % axes[d].size()]);
        rest /= axes[d].size();
      }
    else if (index < total)
      for (int d = 0; d < dims; ++d)
        set(values, *axes_params[d], at_fraction(*axes_params[d], halton(index + 1, kPrimes[d % std::size(kPrimes)])));
    const double cost = solved_cost(model, values, samples, metric, channels);
    starts[index] = {std::move(values), cost};
  });
  stop_if_cancelled(options);
  std::sort(starts.begin(), starts.end(), [](const Start& a, const Start& b) { return a.cost < b.cost; });
  return starts;
}

// Coordinate search from a grid point, for models with many shape parameters: each parameter in
// turn is tried at values spread over its range (the others held, colours set in every channel,
// the linear parameters solved), keeping any improvement, until a pass changes nothing. A
// 256-point design in nine dimensions (sgd) rarely lands in the basin of a material's optimum;
// the search walks there one parameter at a time, at the cost of a few hundred evaluations on
// the subsample, before the trust region takes over. (Profiled on sgd, its evaluations with
// doubles are most of the fit's time. Searching a third of the subsample instead cost sgd 8 %
// in error on blue-acrylic: the search needs the subsample's grazing samples.)
bool has_non_linear_colour(const Model& model) {
  const auto& params = model.parameters();
  return std::any_of(params.begin(), params.end(), [](const ParamSpec& p) { return !p.linear && p.channels > 1; });
}

// Where the grid is a Halton design rather than a lattice (see grid_starts).
bool many_shape_parameters(const Model& model) {
  const auto& params = model.parameters();
  return std::count_if(params.begin(), params.end(), [](const ParamSpec& p) { return !p.linear; }) > 5;
}

Start coordinate_search(const Model& model, Start start, const std::vector<Sample>& samples, Metric metric,
                        const Channels& channels, const FitOptions& options) {
  constexpr int kValuesPerParameter = 24, kMaxPasses = 10;
  std::vector<const ParamSpec*> shape;
  for (const ParamSpec& p : model.parameters())
    if (!p.linear) shape.push_back(&p);
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    bool improved = false;
    for (const ParamSpec* p : shape) {
      stop_if_cancelled(options);
      const std::vector<double> axis = grid_axis(*p, kValuesPerParameter);
      std::vector<Start> tries(axis.size());
      parallel_for(axis.size(), thread_count(options.threads), [&](size_t k) {
        std::vector<double> values = start.values;
        std::fill_n(values.begin() + model.offset_of(p->name), p->channels, axis[k]);
        const double cost = solved_cost(model, values, samples, metric, channels);
        tries[k] = {std::move(values), cost};
      });
      for (Start& t : tries)
        if (t.cost < start.cost * (1 - 1e-9)) {
          start = std::move(t);
          improved = true;
        }
    }
    if (!improved) break;
  }
  return start;
}

// ---------------------------------------------------------------------------------------------
// Trust-region least squares with Ceres.

struct Refinement {
  std::vector<double> values;
  double cost = HUGE_VAL;  // Ceres' cost: ½ Σ r²
  int iterations = 0;
  double trust_region_radius = 0.0;  // at the last step: where a continuation starts
  bool usable = false;
  std::string termination;
  Eigen::MatrixXd covariance;      // over the free values, unscaled (JᵀJ)⁻¹; empty if not computed
  std::vector<bool> identifiable;  // per free value
  std::vector<int> free_index;
  std::vector<int> held;      // free values held on a bound (indices into values)
  bool held_checked = false;  // `held` is what the cost asks for at `values`, not only where the run started
};

class LeastSquares {
 public:
  LeastSquares(const Model& model, const std::vector<Sample>& samples, Metric metric, const Channels& channels,
               const ceres::LossFunction* loss, const FitOptions& options)
      : model_(model), samples_(samples), metric_(metric), channels_(channels), loss_(loss), options_(options) {}

  // Trust-region least squares from `start`; function_tolerance: relative cost change at which it
  // stops. A continuation of an earlier run on the same samples passes that run's last trust-region
  // radius, so that it goes on with the steps the run had reached rather than starting over from
  // Ceres' default (a converged run's radius would stop a run on other samples at once). A run
  // from an earlier run's end (`earlier`) starts with the values that run held on their bounds.
  Refinement run(const std::vector<double>& start, int max_iterations, double function_tolerance = 1e-10,
                 double trust_region_radius = 0.0, const Refinement* earlier = nullptr) const {
    stop_if_cancelled(options_);
    Refinement out;
    out.values = start;
    out.free_index = free_values();
    if (out.free_index.empty()) {
      out.cost = 0.5 * cost_of(model_, start, samples_, metric_, channels_, loss_);
      out.usable = std::isfinite(out.cost);
      out.termination = "nothing to optimise";
      return out;
    }
    // Values on a bound that the cost pushes outward are held there: Ceres projects its steps onto
    // the bounds, so a value pushed against one makes the step's quadratic model promise a decrease
    // the projected step cannot deliver, and the trust region shrinks to a crawl (openpbr on
    // blue-acrylic, metalness and diffuse roughness at 0 and the ior at 3: steps gave 2 % of their
    // promise, 24 iterations on all samples where the held problem takes 1). Where the run ends,
    // the bounds are looked at again (first-order optimality on the box): a held value the cost
    // now pulls inward is released, a value it pushes outward is held, and the run goes on.
    out.held = earlier && earlier->held_checked ? earlier->held : held_on_bounds(out);
    double radius = trust_region_radius;
    constexpr int kMaxHeldSetChanges = 3;
    for (int change = 0;; ++change) {
      solve(out, max_iterations - out.iterations, function_tolerance, radius);
      if (!out.usable || out.iterations >= max_iterations || change == kMaxHeldSetChanges) break;
      std::vector<int> held_now = held_on_bounds(out);
      if (held_now == out.held) {
        out.held_checked = true;
        break;
      }
      out.held = std::move(held_now);
      radius = out.trust_region_radius;
    }
    return out;
  }

  // Fills r.covariance and r.identifiable at r.values.
  void estimate_covariance(Refinement& r) const {
    if (r.free_index.empty() || !r.usable) return;
    std::vector<double> x;
    ceres::Problem problem;
    build_problem(r, x, problem);
    estimate_covariance(problem, x, thread_count(options_.threads), r);
  }

  // Values the solver optimises: all but integer parameters and the colour components of channels
  // this fit leaves alone.
  std::vector<int> free_values() const {
    std::vector<int> free;
    const std::vector<ValueSlot> slots = value_slots(model_);
    for (int i = 0; i < static_cast<int>(slots.size()); ++i)
      if (!slots[i].param->integer && is_fitted(slots[i], channels_)) free.push_back(i);
    return free;
  }

 private:
  // Runs Ceres from r.values with the values r.held held, and puts its result in r (its
  // iterations added to r's).
  void solve(Refinement& r, int max_iterations, double function_tolerance, double trust_region_radius) const {
    std::vector<double> x;
    ceres::Problem problem;
    build_problem(r, x, problem);
    if (!r.held.empty()) {
      std::vector<int> held_positions;
      for (size_t k = 0; k < x.size(); ++k)
        if (std::find(r.held.begin(), r.held.end(), r.free_index[k]) != r.held.end())
          held_positions.push_back(static_cast<int>(k));
      problem.SetManifold(x.data(), new ceres::SubsetManifold(static_cast<int>(x.size()), held_positions));
    }

    ceres::Solver::Options solver;
    solver.minimizer_type = ceres::TRUST_REGION;
    // Dogleg with non-monotonic steps: measured tables' cost valleys are long and curved, and
    // letting the cost rise briefly walks them in a third of the steps strict descent needs.
    solver.trust_region_strategy_type = ceres::DOGLEG;
    solver.use_nonmonotonic_steps = true;
    solver.linear_solver_type = ceres::DENSE_QR;  // a few dozen rows: the batches are compressed
    solver.max_num_iterations = max_iterations;
    if (trust_region_radius > 0.0) solver.initial_trust_region_radius = trust_region_radius;
    solver.function_tolerance = function_tolerance;
    solver.gradient_tolerance = 1e-12;
    solver.parameter_tolerance = 1e-10;
    solver.num_threads = thread_count(options_.threads);
    // With bounds, Ceres follows each trust-region step with a projected line search that
    // costs two more Jacobian evaluations per iteration; the projected trust-region step alone converges.
    solver.max_num_line_search_step_size_iterations = 0;
    solver.logging_type = ceres::SILENT;
    AtEachIteration at_each_iteration(model_.name(), options_);
    if (options_.cancel || options_.on_iteration) solver.callbacks.push_back(&at_each_iteration);
    ceres::Solver::Summary summary;
    ceres::Solve(solver, &problem, &summary);
    stop_if_cancelled(options_);

    for (size_t k = 0; k < x.size(); ++k) r.values[r.free_index[k]] = x[k];
    r.cost = summary.final_cost;
    r.iterations += static_cast<int>(summary.iterations.size()) - 1;
    if (!summary.iterations.empty()) r.trust_region_radius = summary.iterations.back().trust_region_radius;
    r.termination = std::string(ceres::TerminationTypeToString(summary.termination_type)) + ": " + summary.message;
    r.usable = summary.termination_type != ceres::FAILURE && summary.termination_type != ceres::USER_FAILURE &&
               std::isfinite(summary.final_cost) &&
               std::all_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); });
  }

  // The free values (indices into the model's values) on a bound with the cost's gradient pointing
  // out of the box at r.values; none when that would be every free value. One gradient evaluation,
  // and none when no free value is on a bound.
  std::vector<int> held_on_bounds(const Refinement& r) const {
    const std::vector<ValueSlot> slots = value_slots(model_);
    auto on_lower = [&](int i) { return r.values[i] <= slots[i].param->lower; };
    auto on_upper = [&](int i) { return r.values[i] >= slots[i].param->upper; };
    if (std::none_of(r.free_index.begin(), r.free_index.end(), [&](int i) { return on_lower(i) || on_upper(i); }))
      return {};
    Refinement at = r;
    at.held.clear();
    std::vector<double> x, gradient;
    ceres::Problem problem;
    build_problem(at, x, problem);
    double cost = 0.0;
    if (!problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, &gradient, nullptr)) return {};
    std::vector<int> held;
    for (size_t k = 0; k < x.size(); ++k) {
      const int i = at.free_index[k];
      if ((on_lower(i) && gradient[k] > 0.0) || (on_upper(i) && gradient[k] < 0.0)) held.push_back(i);
    }
    if (held.size() == x.size()) return {};
    return held;
  }

  // One residual block per batch of samples over the free values x, with the bounds.
  void build_problem(Refinement& r, std::vector<double>& x, ceres::Problem& problem) const {
    x.clear();
    for (int i : r.free_index) x.push_back(r.values[i]);
    // Enough batches to keep every thread busy, each large enough to amortise its overhead.
    const size_t batches =
        std::clamp<size_t>(samples_.size() / 2048, 1, static_cast<size_t>(thread_count(options_.threads)) * 16);
    const size_t per_batch = (samples_.size() + batches - 1) / batches;
    for (size_t begin = 0; begin < samples_.size(); begin += per_batch) {
      ResidualBatch batch;
      batch.samples = samples_.data() + begin;
      batch.count = std::min(per_batch, samples_.size() - begin);
      batch.metric = metric_;
      batch.channels = channels_;
      batch.loss = loss_;
      batch.free_index = &r.free_index;
      batch.full_values = &r.values;
      problem.AddResidualBlock(new_batch_cost(model_, batch), nullptr, x.data());
    }
    const std::vector<ValueSlot> slots = value_slots(model_);
    for (size_t k = 0; k < x.size(); ++k) {
      const ParamSpec& p = *slots[r.free_index[k]].param;
      problem.SetParameterLowerBound(x.data(), static_cast<int>(k), p.lower);
      problem.SetParameterUpperBound(x.data(), static_cast<int>(k), p.upper);
    }
  }

  // The covariance (JᵀJ)⁺ of the free values from the Jacobian Ceres evaluates at the
  // optimum. Values the data do not determine (their direction lies partly in the numerical
  // null space of the column-scaled JᵀJ, e.g. two parameters that only matter through their
  // ratio) are flagged rather than given a meaningless number; the others get theirs from the
  // pseudo-inverse, which drops that null space.
  static void estimate_covariance(ceres::Problem& problem, std::vector<double>& x, int threads, Refinement& out) {
    const int n = static_cast<int>(x.size());
    ceres::CRSMatrix crs;
    ceres::Problem::EvaluateOptions evaluate;
    evaluate.num_threads = threads;  // one thread unless asked
    problem.Evaluate(evaluate, nullptr, nullptr, nullptr, &crs);
    Eigen::MatrixXd jtj = Eigen::MatrixXd::Zero(n, n);
    for (int row = 0; row < crs.num_rows; ++row)
      for (int a = crs.rows[row]; a < crs.rows[row + 1]; ++a)
        for (int b = crs.rows[row]; b < crs.rows[row + 1]; ++b)
          jtj(crs.cols[a], crs.cols[b]) += crs.values[a] * crs.values[b];
    // Scaling to unit diagonal makes "small" mean the same for an albedo and an exponent.
    const Eigen::VectorXd scale = jtj.diagonal().cwiseSqrt();
    Eigen::VectorXd inverse_scale(n);
    for (int i = 0; i < n; ++i) inverse_scale[i] = scale[i] > 0 ? 1.0 / scale[i] : 0.0;
    const Eigen::MatrixXd scaled = inverse_scale.asDiagonal() * jtj * inverse_scale.asDiagonal();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(scaled);
    const double largest = std::max(eig.eigenvalues().maxCoeff(), 1e-300);
    Eigen::MatrixXd pseudo_inverse = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd null_weight = Eigen::VectorXd::Zero(n);
    for (int k = 0; k < n; ++k) {
      const Eigen::VectorXd u = eig.eigenvectors().col(k);
      if (eig.eigenvalues()[k] > 1e-9 * largest)
        pseudo_inverse += u * u.transpose() / eig.eigenvalues()[k];
      else
        null_weight += u.cwiseAbs2();
    }
    out.covariance = inverse_scale.asDiagonal() * pseudo_inverse * inverse_scale.asDiagonal();
    out.identifiable.resize(n);
    // A pair of interchangeable values puts half of each in the null space, a triple a third.
    for (int i = 0; i < n; ++i) out.identifiable[i] = scale[i] > 0 && null_weight[i] < 0.1;
  }

  const Model& model_;
  const std::vector<Sample>& samples_;
  Metric metric_;
  Channels channels_;
  const ceres::LossFunction* loss_;
  const FitOptions& options_;
};

// One fit of the given channels: multi-start on the subsample, refinement on larger subsets and
// on every sample, and the final choice among every candidate met on the way by the objective
// on ALL samples.
struct ChannelFit {
  Refinement final;
  int iterations = 0;
  size_t residuals = 0;
};

ChannelFit fit_channels(const Model& model, const SampleSet& data, const FitOptions& options, const Channels& channels,
                        const std::vector<double>& initial, const std::vector<std::vector<double>>& nested_starts) {
  ChannelFit fit;
  const int threads = thread_count(options.threads);
  const std::vector<Sample> small = importance_subset(data.samples, options.subsample, options.seed);
  const bool small_is_all = small.size() == data.samples.size();

  std::vector<Start> starts;
  if (options.single_start) {
    starts.push_back({initial, 0.0});
  } else {
    // The best points of two grids: over the scalar shape parameters with the colours at their
    // start, and over the colours as well. Neither contains the other's best basin on every
    // material: the first misses it when the shape is in the colours (sgd's are all colours),
    // the second, with fewer points per parameter, misses it on some tables (openpbr on
    // paper_white, 0.0471 against 0.0313).
    const size_t keep_best = static_cast<size_t>(std::max(1, options.starts));
    for (bool colours : {false, true}) {
      if (colours && !has_non_linear_colour(model)) break;
      std::vector<Start> grid = grid_starts(model, initial, small, options.metric, channels, options, colours);
      grid.resize(std::min(grid.size(), keep_best));
      // Both grids hold the defaults; a model whose shape is all colours (sgd) has nothing else
      // in the first. The same point searched twice cost sgd a fifth of its fit.
      for (Start& point : grid)
        if (std::none_of(starts.begin(), starts.end(), [&](const Start& s) { return s.values == point.values; }))
          starts.push_back(std::move(point));
    }
    // Searched from, besides the grid points themselves: the search does not always end in the
    // better basin.
    if (many_shape_parameters(model))
      for (size_t i = 0, n = starts.size(); i < n; ++i)
        starts.push_back(coordinate_search(model, starts[i], small, options.metric, channels, options));
    // The contained models' optima are refined too: the multi-start grid may not come near them.
    for (std::vector<double> nested : nested_starts) {
      const double cost = solved_cost(model, nested, small, options.metric, channels);
      starts.push_back({std::move(nested), cost});
    }
  }

  double loss_scale = options.loss_scale;
  if (options.loss != LossKind::None && loss_scale <= 0.0) {
    // 1.4826·MAD estimates σ; Huber's and Cauchy's usual tuning constants for 95% efficiency.
    const double sigma = 1.4826 * median_abs_residual(model, starts[0].values, small, options.metric, channels);
    loss_scale = std::max(sigma, 1e-12) * (options.loss == LossKind::Huber ? 1.345 : 2.385);
  }
  const std::unique_ptr<ceres::LossFunction> loss = make_loss(options.loss, loss_scale);
  const LeastSquares on_all(model, data.samples, options.metric, channels, loss.get(), options);
  auto full_cost = [&](const std::vector<double>& values) {
    return 0.5 * cost_of(model, values, data.samples, options.metric, channels, loss.get(), threads);
  };

  // Every candidate met on the way, with its objective on all samples (½Σ, as Ceres counts).
  // Stages work on subsets whose optimum can be worse on all samples than where they started;
  // choosing on all samples discards such a stage, and keeping the contained models' optima
  // among the candidates means the result is never worse than theirs.
  std::vector<Refinement> candidates;
  auto keep = [&](Refinement r) {
    if (!r.usable) return;
    r.cost = full_cost(r.values);
    if (std::isfinite(r.cost)) candidates.push_back(std::move(r));
  };
  for (const std::vector<double>& nested : nested_starts) {
    Refinement r;
    r.values = nested;
    r.usable = true;
    r.termination = "the optimum of a contained model";
    r.free_index = on_all.free_values();
    keep(std::move(r));
  }

  Refinement best;
  if (!options.single_start) {
    const LeastSquares on_subsample(model, small, options.metric, channels, loss.get(), options);
    // Every start is screened with a few iterations, and only the best 2·options.starts
    // continue. On the heavy models every start used to run its 50 iterations, most of their fit;
    // on the MERL proxies the start that finishes best was the first after 8 iterations for sgd
    // and among the six first elsewhere but twice, where one ranked lower finished 0.3 %
    // (principled, red-fabric) and 0.08 % (openpbr, gold-metallic-paint) better (docs/performance.md).
    constexpr int kScreenIterations = 8;
    const int refine_iterations = small_is_all ? options.max_iterations : 50;
    std::vector<Refinement> screened;
    std::set<std::vector<double>> refined;
    for (const Start& start : starts) {
      // A search that found nothing better returns its grid point: the same refinement twice.
      if (!refined.insert(start.values).second) continue;
      Refinement r = on_subsample.run(start.values, std::min(kScreenIterations, refine_iterations));
      fit.iterations += r.iterations;
      if (r.usable) screened.push_back(std::move(r));
    }
    std::sort(screened.begin(), screened.end(),
              [](const Refinement& a, const Refinement& b) { return a.cost < b.cost; });
    screened.resize(std::min(screened.size(), 2 * static_cast<size_t>(std::max(1, options.starts))));
    // Every continued start's refinement is a candidate: the best on the subsample is not always
    // the best on all samples (a many-parameter model can fit the subsample's few grazing samples
    // in a way all samples do not confirm).
    for (Refinement& r : screened) {
      if (r.iterations >= kScreenIterations) {  // stopped by the screen, not converged
        Refinement more =
            on_subsample.run(r.values, refine_iterations - r.iterations, 1e-10, r.trust_region_radius, &r);
        fit.iterations += more.iterations;
        if (more.usable) r = std::move(more);
      }
      if (!small_is_all) keep(r);
      if (r.cost < best.cost) best = r;
    }
    if (!best.usable) {
      best.values = starts[0].values;
      best.termination = "no start converged on the subsample";
    }
  }
  // Refine on ever larger subsets (×10 each) before all samples: a large table's cost valley
  // can be long, and walking it on a tenth of the data costs a tenth as much per step. Each
  // subset is drawn where the data or the current fit's errors are large.
  size_t largest_draws = small.size();
  std::vector<Sample> largest_subset;
  if (!options.single_start)
    for (size_t draws = small.size() * 10; draws < data.size(); draws *= 10) {
      std::vector<Sample> subset = importance_subset(
          data.samples, draws, options.seed, absolute_errors(model, best.values, data.samples, channels, threads));
      const LeastSquares on_subset(model, subset, options.metric, channels, loss.get(), options);
      Refinement r = on_subset.run(best.values, options.max_iterations, 1e-6, 0.0, best.usable ? &best : nullptr);
      fit.iterations += r.iterations;
      if (r.usable) {
        best = r;
        keep(std::move(r));
      }
      largest_draws = draws;
      largest_subset = std::move(subset);
    }
  bool polish = !options.single_start && largest_draws >= options.polish_after;
  if (options.single_start || !small_is_all) {
    // From the best candidate so far on all samples: to a relative cost change of 1e-6, far
    // below any metric's reported precision, or only a few polishing steps after a large
    // subset whose optimum is also the best candidate on all samples (FitOptions).
    const Refinement* from = nullptr;
    for (const Refinement& c : candidates)
      if (!from || c.cost < from->cost) from = &c;
    const std::vector<double> start = options.single_start ? initial : from ? from->values : best.values;
    polish = polish && from && from->values == best.values;
    // A candidate that came from a run starts with the values that run held on their bounds.
    const Refinement* earlier = !options.single_start && from && from->iterations > 0 ? from : nullptr;
    Refinement r =
        on_all.run(start, polish ? std::min(options.polish_iterations, options.max_iterations) : options.max_iterations,
                   1e-6, 0.0, earlier);
    fit.iterations += r.iterations;
    if (polish && r.usable && r.iterations >= options.polish_iterations)
      r.termination =
          fmt::format("polished: {} steps on all samples after converging on an importance subset of {} draws",
                      r.iterations, largest_draws);
    keep(r);
    if (!r.usable && candidates.empty()) best = std::move(r);  // reported as the failure it is
  } else {
    keep(best);
  }
  const auto cheapest = [&] {
    return *std::min_element(candidates.begin(), candidates.end(),
                             [](const Refinement& a, const Refinement& b) { return a.cost < b.cost; });
  };
  if (!candidates.empty()) {
    // The linear parameters solved exactly on all samples for the best shape: the stopping rule
    // (a relative cost change of 1e-6) leaves them wherever the cost is flat enough, which under
    // a bright peak can be a diffuse albedo a percent off its least-squares value.
    Refinement exact = cheapest();
    solve_linear(model, exact.values, data.samples, options.metric, channels);
    keep(std::move(exact));
    best = cheapest();
  }
  // JᵀJ at the optimum: over all samples, or estimated from the large importance subset (its
  // weights make sums over it unbiased estimates of sums over all samples; with 100k draws the
  // standard deviations come out within about a percent, for a tenth of the time).
  if (polish && !largest_subset.empty())
    LeastSquares(model, largest_subset, options.metric, channels, loss.get(), options).estimate_covariance(best);
  else
    on_all.estimate_covariance(best);
  fit.residuals = data.size() * static_cast<size_t>(std::count(channels.begin(), channels.end(), true));
  fit.final = std::move(best);
  return fit;
}

// On a bound to within a millionth of the parameter's range, measured as the grid spaces it: in
// log space for log-spaced parameters (c of sgd spans 1e-8 to 1e4; a linear millionth, 0.01,
// would call 0.006 a value at its lower bound).
bool at_upper_bound(const ParamSpec& p, double value) {
  return p.spacing == Spacing::Log ? value >= p.upper * std::pow(p.lower / p.upper, 1e-6)
                                   : value >= p.upper - 1e-6 * (p.upper - p.lower);
}
bool at_bound(const ParamSpec& p, double value) {
  const bool at_lower = p.spacing == Spacing::Log ? value <= p.lower * std::pow(p.upper / p.lower, 1e-6)
                                                  : value <= p.lower + 1e-6 * (p.upper - p.lower);
  return at_lower || at_upper_bound(p, value);
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

}  // namespace

const char* verdict_name(Verdict verdict) {
  switch (verdict) {
    case Verdict::Good: return "good";
    case Verdict::Poor: return "poor";
    case Verdict::Failed: break;
  }
  return "failed";
}

namespace {

// A contained model's optimum in the outer model's values, one vector per channel (the three
// are equal unless the contained model was fitted per channel).
using ChannelVectors = std::array<std::vector<double>, 3>;

void check_fit_input(const SampleSet& data) {
  if (data.empty()) fail("{}: no samples to fit", data.source.empty() ? "input" : data.source);
  check_sample_magnitudes(data);  // before any solver: values that would overflow its cost are refused
}

// Fits one model from its grid and from the contained models' optima `nested`. A per-channel
// fit first fits the shared model and starts each channel from it, so it contains the shared
// fit as well.
FitResult fit_one(const Model& model, const SampleSet& data, const FitOptions& options,
                  const std::vector<ChannelVectors>& nested) {
  const auto started = std::chrono::steady_clock::now();
  FitResult result;
  result.model = model.name();
  result.samples = data.size();
  if (!options.initial_values.empty() && static_cast<int>(options.initial_values.size()) != model.num_values())
    fail("{}: {} initial values given, the model has {}", model.name(), options.initial_values.size(),
         model.num_values());
  const std::vector<double> initial = options.initial_values.empty() ? model.default_values() : options.initial_values;
  auto nested_for = [&](int channel) {
    std::vector<std::vector<double>> starts;
    if (!options.single_start)
      for (const ChannelVectors& n : nested) starts.push_back(n[channel]);
    return starts;
  };

  std::vector<ChannelFit> fits;
  std::string failure;
  auto record = [&](ChannelFit fit) {
    if (!fit.final.usable && failure.empty()) failure = fit.final.termination;
    result.iterations += fit.iterations;
    fits.push_back(std::move(fit));
  };
  if (!options.per_channel) {
    record(fit_channels(model, data, options, kAllChannels, initial, nested_for(0)));
  } else {
    std::vector<std::vector<double>> shared_starts;
    for (int c = 0; c < 3; ++c)
      for (std::vector<double>& s : nested_for(c)) shared_starts.push_back(std::move(s));
    const ChannelFit shared = fit_channels(model, data, options, kAllChannels, initial, shared_starts);
    result.iterations += shared.iterations;
    for (int c = 0; c < 3; ++c) {
      Channels mask{false, false, false};
      mask[c] = true;
      std::vector<std::vector<double>> starts = nested_for(c);
      if (shared.final.usable) starts.push_back(shared.final.values);
      record(fit_channels(model, data, options, mask, shared.final.usable ? shared.final.values : initial, starts));
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
  result.metrics = evaluate_metrics(model, result.values, data, result.channel_values);

  const bool finite =
      std::all_of(result.values.begin(), result.values.end(), [](double v) { return std::isfinite(v); }) &&
      std::isfinite(result.metrics.get(options.metric));
  result.ok = failure.empty() && finite;
  if (!result.ok)
    result.error = !failure.empty() ? "the fit diverged (" + failure + ")" : "the fit produced non-finite values";
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

std::string format_value(const std::vector<double>& v) {
  if (v.size() == 1) return fmt::format("{:.4g}", v[0]);
  return fmt::format("[{:.4g}, {:.4g}, {:.4g}]", v[0], v[1], v[2]);
}

// The verdict and the warning lines of a fitted result (see Verdict in fit.h). A fit is poor
// when any of these holds:
//   - its error in any judged metric (kJudgedMetrics: cosine, log, relative and l2, whichever was
//     minimised) is more than kPoorRatio times that of the baseline, Lambert fitted to the same
//     samples: every reflectance model should do at least as well as a diffuse term alone, and
//     models with a Lambert base contain it. Judging the fitted metric alone let a mirror-like
//     gltf fit of white paper (log minimised; cosine error 1960 against Lambert's 0.047) and
//     glossy fits 2-14x Lambert's relative error on acrylics pass as good. `max` is one sample's
//     error and is reported, not judged;
//   - it removes less than 1 - kPoorUnexplained of the data's own scale in that metric (the
//     error of predicting zero): it misses what dominates the data, e.g. a diffuse model on a
//     glossy coating;
//   - its typical sample is off by more than kPoorTypical times its own value (Metrics::typical):
//     it misses the body of the data, e.g. a lobe with no diffuse term on a coloured paint;
//   - a colour or scale it solves linearly sits at its upper bound in every channel while it
//     leaves more than kPoorClampedUnexplained of the data's scale: the data are brighter than
//     the model can be (a stylised shader's output in place of a reflectance), and the values
//     it reports are its limits, not the material's.
// The thresholds were set on the shared RGL and MERL tables, where they flag the diffuse models
// on glossy materials, toon on measured ones and single lobes that capture < 15% of a
// mirror-like peak, and leave every model on white paper and red fabric good.
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
    if (spec && spec->trades_off_with && (p.at_bound || !p.identifiable)) {
      const ParamSpec* other = model.find_parameter(spec->trades_off_with);
      const auto partner = std::find_if(r.parameters.begin(), r.parameters.end(),
                                        [&](const ParameterEstimate& e) { return e.name == spec->trades_off_with; });
      if (other && partner != r.parameters.end()) {
        std::vector<double> product;
        for (size_t i = 0; i < std::max(partner->value.size(), p.value.size()); ++i)
          product.push_back(partner->value[std::min(i, partner->value.size() - 1)] *
                            p.value[std::min(i, p.value.size() - 1)]);
        r.warnings.push_back(
            fmt::format("{}·{} = {} is what the data determine (the lobe's reflectance at normal "
                        "incidence); {} was left where the least-squares optimum put it",
                        other->name, p.name, format_value(product), p.name));
      }
    }
    if (!p.identifiable)
      r.warnings.push_back(
          fmt::format("{} is not identifiable: the data do not determine it (it trades off with "
                      "other parameters); its value is one of many equally good ones",
                      p.name));
  }
}

}  // namespace

FitResult fit_model(const Model& model, const SampleSet& data, const FitOptions& options) {
  return fit_models({&model}, data, options).front();
}

namespace {

// fit_one, with a fit that goes wrong reported as failed rather than thrown.
FitResult fit_or_failure(const Model& model, const SampleSet& data, const FitOptions& options,
                         const std::vector<ChannelVectors>& nested) {
  FitResult result;
  try {
    result = fit_one(model, data, options, nested);
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

FitResult fit_held(const HeldModel& held, const SampleSet& data, const FitOptions& options) {
  FitOptions own = options;
  const int full_count = held.num_values() + held.held_count();
  if (!own.initial_values.empty() && static_cast<int>(own.initial_values.size()) != full_count)
    fail("{}: {} initial values given, the model has {}", held.name(), own.initial_values.size(), full_count);
  if (!own.initial_values.empty()) own.initial_values = held.free_values(own.initial_values);
  return held.full_result(fit_or_failure(held, data, own, {}));
}

}  // namespace

std::vector<FitResult> fit_models(const std::vector<const Model*>& models, const SampleSet& data,
                                  const FitOptions& options) {
  check_fit_input(data);
  check_held(models, options.fixed);
  // Every model fitted in this run, the requested ones and those they contain, by name.
  std::map<std::string, FitResult> fitted;
  std::set<std::string> in_progress;
  auto requested = [&](const std::string& name) {
    return std::any_of(models.begin(), models.end(), [&](const Model* m) { return m->name() == name; });
  };
  // Fits `model` after the models it contains: exact nestings always (they carry the guarantee),
  // approximate ones only when that model is fitted in this run anyway.
  std::function<const FitResult&(const Model&)> fit = [&](const Model& model) -> const FitResult& {
    if (auto it = fitted.find(model.name()); it != fitted.end()) return it->second;
    in_progress.insert(model.name());
    std::vector<ChannelVectors> nested;
    for (const Nesting& nesting : model.nestings()) {
      const Model* inner = find_model(nesting.inner);
      if (!inner || in_progress.count(inner->name())) continue;
      if (!nesting.exact && !requested(inner->name()) && !fitted.count(inner->name())) continue;
      const FitResult& r = fit(*inner);
      if (!r.ok) continue;
      ChannelVectors embedded;
      for (int c = 0; c < 3; ++c)
        embedded[c] = embed_values(model, nesting, *inner, r.channel_values.empty() ? r.values : r.channel_values[c]);
      nested.push_back(std::move(embedded));
    }
    // A start given in the options is the requested models'; contained models fitted on the
    // way (and the baseline) start from their own grids.
    FitOptions own = options;
    if (!requested(model.name())) {
      own.initial_values.clear();
      own.single_start = false;
    }
    const Nesting* form = data.isotropic ? isotropic_form(model) : nullptr;
    const auto form_fit = form ? fitted.find(form->inner) : fitted.end();
    FitResult result = form_fit != fitted.end()
                           ? in_isotropic_form(model, *form, *find_model(form->inner), form_fit->second, data)
                           : fit_or_failure(model, data, own, nested);
    in_progress.erase(model.name());
    return fitted.emplace(model.name(), std::move(result)).first->second;
  };

  const Model* lambert = find_model("lambert");
  const FitResult* baseline = lambert ? &fit(*lambert) : nullptr;
  const double zero_error = zero_prediction_error(data, options.metric);
  std::vector<FitResult> results;
  for (const Model* model : models) {
    if (options.on_model_start) options.on_model_start(results.size(), models.size(), model->name());
    // Held parameters (FitOptions::fixed): the model of the others, fitted on its own.
    const HeldModel held(*model, options.fixed);
    FitResult r = held.holds_any() ? fit_held(held, data, options) : fit(*model);
    judge(*model, baseline, zero_error, options.metric, data.isotropic, r);
    results.push_back(std::move(r));
  }
  return results;
}

}  // namespace brdffit
