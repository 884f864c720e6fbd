// The generic fitter (see fit.h for the strategy).
#include "brdffit/fit.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numeric>
#include <random>

#include "brdffit/error.h"
#include "brdffit/fit_residual.h"
#include "brdffit/parallel.h"

namespace brdffit {

namespace {

using Channels = std::array<bool, 3>;
constexpr Channels kAllChannels{true, true, true};

// Where each flattened value comes from: its parameter and its channel (0 for scalars).
struct ValueSlot {
  const ParamSpec* param;
  int channel;
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
// Plain evaluation: cost and residuals with doubles.

// Σ over samples and fitted channels of the squared (robustified, weighted) residual.
double cost_of(const Model& model, const std::vector<double>& values, const std::vector<Sample>& samples,
               Metric metric, const Channels& channels, const ceres::LossFunction* loss) {
  double sum = 0.0;
  for (const Sample& s : samples) {
    const Rgb<double> shade = model.shade(values.data(), s.l, s.v);
    const double sqrt_w = std::sqrt(metric_weight(metric, s.weight));
    for (int c = 0; c < 3; ++c) {
      if (!channels[c]) continue;
      double r, scale;
      detail::robustify(loss, metric_residual(metric, shade[c], s.value[c]) * sqrt_w, r, scale);
      sum += r * r;
    }
  }
  return std::isfinite(sum) ? sum : HUGE_VAL;
}

// Median absolute residual (unweighted by the loss) on the fitted channels, for the robust
// loss's automatic scale.
double median_abs_residual(const Model& model, const std::vector<double>& values,
                           const std::vector<Sample>& samples, Metric metric, const Channels& channels) {
  std::vector<double> abs_residuals;
  for (const Sample& s : samples) {
    const Rgb<double> shade = model.shade(values.data(), s.l, s.v);
    for (int c = 0; c < 3; ++c)
      if (channels[c])
        abs_residuals.push_back(std::fabs(metric_residual(metric, shade[c], s.value[c])) *
                                std::sqrt(metric_weight(metric, s.weight)));
  }
  if (abs_residuals.empty()) return 0.0;
  auto middle = abs_residuals.begin() + abs_residuals.size() / 2;
  std::nth_element(abs_residuals.begin(), middle, abs_residuals.end());
  return *middle;
}

// ---------------------------------------------------------------------------------------------
// Variable projection: the linear colour parameters solved exactly for fixed shape parameters.

// Minimises xᵀAx - 2bᵀx over the box lower <= x <= upper for small n (at most a few colour
// parameters) by trying every active set: each variable free, at its lower or at its upper bound.
Eigen::VectorXd solve_box_quadratic(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, const Eigen::VectorXd& lower,
                                    const Eigen::VectorXd& upper) {
  const int n = static_cast<int>(b.size());
  int combinations = 1;
  for (int i = 0; i < n; ++i) combinations *= 3;
  Eigen::VectorXd best = lower;
  double best_value = HUGE_VAL;
  for (int code = 0; code < combinations; ++code) {
    Eigen::VectorXd x(n);
    std::vector<int> free;
    int rest = code;
    for (int i = 0; i < n; ++i, rest /= 3) {
      if (rest % 3 == 0) free.push_back(i);
      x[i] = rest % 3 == 1 ? lower[i] : upper[i];
    }
    if (!free.empty()) {
      const int f = static_cast<int>(free.size());
      Eigen::MatrixXd a_free(f, f);
      Eigen::VectorXd rhs(f);
      for (int i = 0; i < f; ++i) {
        rhs[i] = b[free[i]];
        for (int j = 0; j < n; ++j)
          if (std::find(free.begin(), free.end(), j) == free.end()) rhs[i] -= a(free[i], j) * x[j];
        for (int j = 0; j < f; ++j) a_free(i, j) = a(free[i], free[j]);
      }
      const Eigen::VectorXd x_free = a_free.completeOrthogonalDecomposition().solve(rhs);
      bool feasible = x_free.allFinite();
      for (int i = 0; i < f && feasible; ++i) {
        feasible = x_free[i] >= lower[free[i]] - 1e-12 && x_free[i] <= upper[free[i]] + 1e-12;
        x[free[i]] = std::clamp(x_free[i], lower[free[i]], upper[free[i]]);
      }
      if (!feasible) continue;
    }
    const double value = x.dot(a * x) - 2.0 * b.dot(x);
    if (value < best_value) {
      best_value = value;
      best = x;
    }
  }
  return best;
}

// Sets the model's linear parameters (fitted channels only) to their weighted least-squares
// optimum within bounds, for the current shape parameters. The prediction is affine in them:
// shade_c = base_c + Σ_j x_jc · basis_jc. For the relative and log metrics the residual is
// weighted by its first-order sensitivity so the solve matches the metric near the data.
void solve_linear(const Model& model, std::vector<double>& values, const std::vector<Sample>& samples, Metric metric,
                  const Channels& channels) {
  std::vector<const ParamSpec*> linear;
  for (const ParamSpec& p : model.parameters())
    if (p.linear) linear.push_back(&p);
  if (linear.empty()) return;
  const int m = static_cast<int>(linear.size());

  std::vector<double> probe = values;
  for (const ParamSpec* p : linear) std::fill_n(probe.begin() + model.offset_of(p->name), 3, 0.0);
  std::array<Eigen::MatrixXd, 3> a;
  std::array<Eigen::VectorXd, 3> b;
  for (int c = 0; c < 3; ++c) {
    a[c] = Eigen::MatrixXd::Zero(m, m);
    b[c] = Eigen::VectorXd::Zero(m);
  }
  std::vector<Rgb<double>> basis(m);
  for (const Sample& s : samples) {
    const Rgb<double> base = model.shade(probe.data(), s.l, s.v);
    for (int j = 0; j < m; ++j) {
      const int offset = model.offset_of(linear[j]->name);
      std::fill_n(probe.begin() + offset, 3, 1.0);
      basis[j] = model.shade(probe.data(), s.l, s.v) - base;
      std::fill_n(probe.begin() + offset, 3, 0.0);
    }
    for (int c = 0; c < 3; ++c) {
      if (!channels[c]) continue;
      double w = metric_weight(metric, s.weight);
      if (metric == Metric::Relative) w /= std::pow(std::fabs(s.value[c]) + kRelativeEpsilon, 2);
      if (metric == Metric::Log) w /= std::pow(1.0 + std::max(s.value[c], 0.0), 2);
      const double target = s.value[c] - base[c];
      for (int i = 0; i < m; ++i) {
        b[c][i] += w * basis[i][c] * target;
        for (int j = 0; j < m; ++j) a[c](i, j) += w * basis[i][c] * basis[j][c];
      }
    }
  }
  Eigen::VectorXd lower(m), upper(m);
  for (int j = 0; j < m; ++j) {
    lower[j] = linear[j]->lower;
    upper[j] = linear[j]->upper;
  }
  for (int c = 0; c < 3; ++c) {
    if (!channels[c]) continue;
    const Eigen::VectorXd x = solve_box_quadratic(a[c], b[c], lower, upper);
    for (int j = 0; j < m; ++j) values[model.offset_of(linear[j]->name) + c] = x[j];
  }
}

// ---------------------------------------------------------------------------------------------
// Multi-start grid over the shape parameters.

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
  for (int k = 0; k < n; ++k) {
    const double t = (k + 0.5) / n;
    axis.push_back(p.spacing == Spacing::Log ? p.lower * std::pow(p.upper / p.lower, t)
                                             : p.lower + t * (p.upper - p.lower));
  }
  return axis;
}

struct Start {
  std::vector<double> values;
  double cost;
};

// Every grid point's values with the linear parameters solved, sorted by cost on `samples`.
std::vector<Start> grid_starts(const Model& model, const std::vector<double>& initial,
                               const std::vector<Sample>& samples, Metric metric, const Channels& channels,
                               const FitOptions& options) {
  // Grid over the scalar, non-linear parameters. Non-linear colours stay at their start.
  std::vector<const ParamSpec*> axes_params;
  for (const ParamSpec& p : model.parameters())
    if (!p.linear && p.channels == 1) axes_params.push_back(&p);
  const int dims = static_cast<int>(axes_params.size());
  const int per_axis =
      dims == 0 ? 1 : std::clamp(static_cast<int>(std::floor(std::pow(options.grid_points, 1.0 / dims))), 2, 24);
  std::vector<std::vector<double>> axes;
  size_t total = 1;
  for (const ParamSpec* p : axes_params) {
    axes.push_back(grid_axis(*p, per_axis));
    total *= axes.back().size();
  }

  std::vector<Start> starts(total + 1);
  // The last entry starts from `initial` itself (the defaults), so the grid never does worse.
  parallel_for(total + 1, thread_count(options.threads), [&](size_t index) {
    std::vector<double> values = initial;
    size_t rest = index;
    if (index < total)
      for (int d = 0; d < dims; ++d) {
        values[model.offset_of(axes_params[d]->name)] = axes[d][rest % axes[d].size()];
        rest /= axes[d].size();
      }
    solve_linear(model, values, samples, metric, channels);
    starts[index] = {values, cost_of(model, values, samples, metric, channels, nullptr)};
  });
  std::sort(starts.begin(), starts.end(), [](const Start& a, const Start& b) { return a.cost < b.cost; });
  return starts;
}

// ---------------------------------------------------------------------------------------------
// Trust-region least squares with Ceres.

struct Refinement {
  std::vector<double> values;
  double cost = HUGE_VAL;  // Ceres' cost: ½ Σ r²
  int iterations = 0;
  bool usable = false;
  std::string termination;
  Eigen::MatrixXd covariance;  // over the free values, unscaled (JᵀJ)⁻¹; empty if not computed
  std::vector<bool> identifiable;  // per free value
  std::vector<int> free_index;
};

class LeastSquares {
 public:
  LeastSquares(const Model& model, const std::vector<Sample>& samples, Metric metric, const Channels& channels,
               const ceres::LossFunction* loss, const FitOptions& options)
      : model_(model), samples_(samples), metric_(metric), channels_(channels), loss_(loss), options_(options) {}

  // Trust-region least squares from `start`; function_tolerance: relative cost change at which it stops.
  Refinement run(const std::vector<double>& start, int max_iterations, double function_tolerance = 1e-10) const {
    Refinement out;
    out.values = start;
    out.free_index = free_values();
    if (out.free_index.empty()) {
      out.cost = 0.5 * cost_of(model_, start, samples_, metric_, channels_, loss_);
      out.usable = std::isfinite(out.cost);
      out.termination = "nothing to optimise";
      return out;
    }
    std::vector<double> x;
    ceres::Problem problem;
    build_problem(out, x, problem);

    ceres::Solver::Options solver;
    solver.minimizer_type = ceres::TRUST_REGION;
    // Dogleg with non-monotonic steps: measured tables' cost valleys are long and curved, and
    // letting the cost rise briefly walks them in a third of the steps strict descent needs.
    solver.trust_region_strategy_type = ceres::DOGLEG;
    solver.use_nonmonotonic_steps = true;
    solver.linear_solver_type = ceres::DENSE_QR;  // a few dozen rows: the batches are compressed
    solver.max_num_iterations = max_iterations;
    solver.function_tolerance = function_tolerance;
    solver.gradient_tolerance = 1e-12;
    solver.parameter_tolerance = 1e-10;
    solver.num_threads = thread_count(options_.threads);
    // With bounds, Ceres follows each trust-region step with a projected line search that
    // costs two more Jacobian evaluations per iteration; the projected trust-region step alone converges.
    solver.max_num_line_search_step_size_iterations = 0;
    solver.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(solver, &problem, &summary);

    for (size_t k = 0; k < x.size(); ++k) out.values[out.free_index[k]] = x[k];
    out.cost = summary.final_cost;
    out.iterations = static_cast<int>(summary.iterations.size()) - 1;
    out.termination = std::string(ceres::TerminationTypeToString(summary.termination_type)) + ": " + summary.message;
    out.usable = summary.termination_type != ceres::FAILURE && summary.termination_type != ceres::USER_FAILURE &&
                 std::isfinite(summary.final_cost) &&
                 std::all_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); });
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

 private:
  // Values the solver optimises: all but integer parameters and the colour components of channels
  // this fit leaves alone.
  std::vector<int> free_values() const {
    std::vector<int> free;
    const std::vector<ValueSlot> slots = value_slots(model_);
    for (int i = 0; i < static_cast<int>(slots.size()); ++i)
      if (!slots[i].param->integer && is_fitted(slots[i], channels_)) free.push_back(i);
    return free;
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
      problem.AddResidualBlock(model_.new_batch_cost(batch), nullptr, x.data());
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

// A deterministic subset of about `count` samples standing in for all of them in the early,
// cheap stages. A measured table's error is dominated by few samples (a specular peak covers
// few bins with large values), which a uniform subset would mostly miss; so samples are drawn
// with probability ∝ weight·(value + mean value)² by systematic sampling, and each kept sample's
// weight is divided by its expected count so sums over the subset estimate sums over all.
std::vector<Sample> subsample(const std::vector<Sample>& samples, size_t count, uint64_t seed) {
  if (samples.size() <= count) return samples;
  double mean = 0.0, weight_sum = 0.0;
  for (const Sample& s : samples) {
    mean += s.weight * s.value.cwiseAbs().mean();
    weight_sum += s.weight;
  }
  mean /= std::max(weight_sum, 1e-300);
  std::vector<double> score(samples.size());
  double total = 0.0;
  for (size_t i = 0; i < samples.size(); ++i) {
    const double m = samples[i].value.cwiseAbs().mean() + mean;
    score[i] = samples[i].weight * m * m;
    total += score[i];
  }
  if (!(total > 0.0)) return std::vector<Sample>(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(count));
  std::vector<Sample> subset;
  subset.reserve(count);
  const double step = total / count;
  std::mt19937_64 rng(seed);
  double next = std::uniform_real_distribution<double>(0.0, step)(rng);
  double cumulative = 0.0;
  for (size_t i = 0; i < samples.size(); ++i) {
    cumulative += score[i];
    int hits = 0;
    while (next < cumulative) {
      ++hits;
      next += step;
    }
    if (hits == 0) continue;
    Sample s = samples[i];
    s.weight *= hits * step / score[i];
    subset.push_back(s);
  }
  return subset;
}

// One fit of the given channels: multi-start on the subsample, then refinement on every sample.
struct ChannelFit {
  Refinement final;
  int iterations = 0;
  size_t residuals = 0;
};

ChannelFit fit_channels(const Model& model, const SampleSet& data, const FitOptions& options,
                        const Channels& channels, const std::vector<double>& initial) {
  ChannelFit fit;
  const std::vector<Sample> small = subsample(data.samples, options.subsample, options.seed);
  const bool small_is_all = small.size() == data.samples.size();

  std::vector<Start> starts;
  if (options.single_start) {
    starts.push_back({initial, 0.0});
  } else {
    starts = grid_starts(model, initial, small, options.metric, channels, options);
    starts.resize(std::min<size_t>(starts.size(), std::max(1, options.starts)));
  }

  double loss_scale = options.loss_scale;
  if (options.loss != LossKind::None && loss_scale <= 0.0) {
    // 1.4826·MAD estimates σ; Huber's and Cauchy's usual tuning constants for 95% efficiency.
    const double sigma = 1.4826 * median_abs_residual(model, starts[0].values, small, options.metric, channels);
    loss_scale = std::max(sigma, 1e-12) * (options.loss == LossKind::Huber ? 1.345 : 2.385);
  }
  const std::unique_ptr<ceres::LossFunction> loss = make_loss(options.loss, loss_scale);

  Refinement best;
  if (!options.single_start) {
    const LeastSquares on_subsample(model, small, options.metric, channels, loss.get(), options);
    for (const Start& start : starts) {
      Refinement r = on_subsample.run(start.values, small_is_all ? options.max_iterations : 50);
      fit.iterations += r.iterations;
      if (r.usable && r.cost < best.cost) best = std::move(r);
    }
    if (!best.usable) {
      best.values = starts[0].values;
      best.termination = "no start converged on the subsample";
    }
  }
  // Refine on ever larger subsets (×10 each) before all samples: a large table's cost valley
  // can be long, and walking it on a tenth of the data costs a tenth as much per step.
  size_t largest_draws = small.size();
  std::vector<Sample> largest_subset;
  if (!options.single_start)
    for (size_t draws = small.size() * 10; draws < data.size(); draws *= 10) {
      // Heavy samples drawn more than once are kept once, with the weight of all their draws.
      std::vector<Sample> subset = subsample(data.samples, draws, options.seed);
      const LeastSquares on_subset(model, subset, options.metric, channels, loss.get(), options);
      Refinement r = on_subset.run(best.values, options.max_iterations, 1e-6);
      fit.iterations += r.iterations;
      if (r.usable) best = std::move(r);
      largest_draws = draws;
      largest_subset = std::move(subset);
    }
  const bool polish = !options.single_start && largest_draws >= options.polish_after;
  const LeastSquares on_all(model, data.samples, options.metric, channels, loss.get(), options);
  if (options.single_start || !small_is_all) {
    // From the subsets' optimum: to a relative cost change of 1e-6, far below any metric's
    // reported precision, or only a few polishing steps after a large subset (FitOptions).
    best = on_all.run(options.single_start ? initial : best.values,
                      polish ? std::min(options.polish_iterations, options.max_iterations) : options.max_iterations, 1e-6);
    if (polish && best.usable && best.iterations >= options.polish_iterations)
      best.termination = fmt::format("polished: {} steps on all samples after converging on an importance subset of {} draws",
                                     best.iterations, largest_draws);
    fit.iterations += best.iterations;
  }
  // JᵀJ at the optimum: over all samples, or estimated from the large importance subset (its
  // weights make sums over it unbiased estimates of sums over all samples; with 100k draws the
  // standard deviations come out within about a percent, for a tenth of the time).
  if (polish)
    LeastSquares(model, largest_subset, options.metric, channels, loss.get(), options).estimate_covariance(best);
  else
    on_all.estimate_covariance(best);
  fit.residuals = data.size() * static_cast<size_t>(std::count(channels.begin(), channels.end(), true));
  fit.final = std::move(best);
  return fit;
}

bool at_bound(const ParamSpec& p, double value) {
  const double tolerance = 1e-6 * (p.upper - p.lower);
  return value <= p.lower + tolerance || value >= p.upper - tolerance;
}

// Fills result.parameters from one or three channel fits. stddev = √(σ² (JᵀJ)⁻¹), with
// σ² = 2·cost/(residuals − free values) the residual variance (Ceres' cost is ½Σr²).
void report_parameters(const Model& model, const std::vector<ChannelFit>& fits, bool per_channel,
                       FitResult& result) {
  const std::vector<ValueSlot> slots = value_slots(model);
  // stddev per flattened value per fit (NaN unless estimated).
  std::vector<std::vector<double>> stddev(fits.size(), std::vector<double>(slots.size(), NAN));
  std::vector<std::vector<bool>> identifiable(fits.size(), std::vector<bool>(slots.size(), true));
  for (size_t f = 0; f < fits.size(); ++f) {
    const Refinement& r = fits[f].final;
    const double dof = std::max<double>(1.0, static_cast<double>(fits[f].residuals) - r.free_index.size());
    const double variance = 2.0 * r.cost / dof;
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

FitResult fit_model(const Model& model, const SampleSet& data, const FitOptions& options) {
  if (data.empty()) fail("{}: no samples to fit", data.source.empty() ? "input" : data.source);
  check_sample_magnitudes(data);  // before any solver: values that would overflow its cost are refused

  const auto started = std::chrono::steady_clock::now();
  FitResult result;
  result.model = model.name();
  result.samples = data.size();
  if (!options.initial_values.empty() && static_cast<int>(options.initial_values.size()) != model.num_values())
    fail("{}: {} initial values given, the model has {}", model.name(), options.initial_values.size(), model.num_values());
  const std::vector<double> initial = options.initial_values.empty() ? model.default_values() : options.initial_values;

  std::vector<Channels> masks;
  if (options.per_channel)
    masks = {Channels{true, false, false}, Channels{false, true, false}, Channels{false, false, true}};
  else
    masks = {kAllChannels};

  std::vector<ChannelFit> fits;
  std::string failure;
  for (const Channels& mask : masks) {
    // Each channel fit starts from the previous one's values so its other channels are sane.
    fits.push_back(fit_channels(model, data, options, mask, fits.empty() ? initial : fits.back().final.values));
    if (!fits.back().final.usable && failure.empty()) failure = fits.back().final.termination;
    result.iterations += fits.back().iterations;
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
  result.metrics = evaluate_metrics(model, result.values, data, result.channel_values);

  const bool finite = std::all_of(result.values.begin(), result.values.end(), [](double v) { return std::isfinite(v); }) &&
                      std::isfinite(result.metrics.get(options.metric));
  result.ok = failure.empty() && finite;
  if (!result.ok) result.error = !failure.empty() ? "the fit diverged (" + failure + ")" : "the fit produced non-finite values";
  result.verdict = result.ok ? Verdict::Good : Verdict::Failed;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

std::vector<FitResult> fit_models(const std::vector<const Model*>& models, const SampleSet& data,
                                  const FitOptions& options) {
  std::vector<FitResult> results;
  for (const Model* model : models) {
    try {
      results.push_back(fit_model(*model, data, options));
    } catch (const Error&) {
      throw;  // bad input or options: the same for every model
    } catch (const std::exception& e) {
      FitResult failed;
      failed.model = model->name();
      failed.error = e.what();
      failed.samples = data.size();
      results.push_back(failed);
    }
  }
  return results;
}

Metrics evaluate_metrics(const Model& model, const std::vector<double>& values, const SampleSet& data,
                         const std::vector<std::vector<double>>& per_channel_values) {
  struct Sums {
    double weight = 0, cosine = 0, log = 0, relative = 0, plain = 0, max = 0;
    size_t count = 0;
  };
  const size_t chunks = 64;
  std::vector<Sums> partial(chunks);
  const size_t per_chunk = (data.size() + chunks - 1) / chunks;
  parallel_for(chunks, thread_count(0), [&](size_t chunk) {
    Sums& sums = partial[chunk];
    const size_t end = std::min(data.size(), (chunk + 1) * per_chunk);
    for (size_t i = chunk * per_chunk; i < end; ++i) {
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
  }
  Metrics metrics;
  if (total.count == 0) return metrics;
  metrics.cosine = std::sqrt(total.cosine / total.weight);
  metrics.log = std::sqrt(total.log / total.weight);
  metrics.relative = std::sqrt(total.relative / total.weight);
  metrics.l2 = std::sqrt(total.plain / total.count);
  metrics.max = total.max;
  return metrics;
}

}  // namespace brdffit
