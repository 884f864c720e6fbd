// Ceres' trust-region refinements of the fitter (fit_stages.h): the problem over the free values,
// values held on their bounds, and the covariance at the optimum.
#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "brdffit/fit_residual.h"
#include "brdffit/fit_stages.h"
#include "brdffit/parallel.h"

namespace brdffit::fitting {

namespace {

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

// Watches a run after each of Ceres' iterations (its state is updated every iteration):
//
// - It stops the run when a value moved freely reaches one of its bounds. Ceres projects its
//   steps onto the bounds, so a value pushed against one makes every later step's quadratic model
//   promise a decrease the projected step cannot deliver: the trust region shrinks to a crawl
//   (sgd and openpbr+coat on gold-metallic-paint: steps giving a fifth of their promise, the
//   radius halved at every step until the cost change fell below the tolerance). Stopped there,
//   the run looks at the bounds again (LeastSquares::run) and goes on with that value held or free.
// - It keeps the best point met. Non-monotonic steps let the cost rise for a while to walk a
//   curved valley faster, but on a rough cost they can wander uphill for good (sgd on
//   gold-metallic-paint's importance subset: from 8.46e-3 up to 9.02e-3 over the last 40 of its
//   100 iterations), and Ceres returns where the walk ended.
// - It stops a walk that has not improved on that best point for kMaxStepsWithoutProgress steps
//   (ten cut sgd's walk on RGL's acrylic_felt_green short of a better point it reached later:
//   cosine error 0.011432 -> 0.014188; twenty do not).
// - It stops a crawl: kMaxPoorSteps accepted steps in a row that each gave less than a quarter of
//   the decrease their model promised, so that the trust region halved at each. That is what a
//   step projected onto a bound does (the value was on it where the run started, so it is not
//   watched), and the run looks at the bounds again as above. Stopping there changed no cosine
//   error on the MERL proxies and saved 2-3 % of all 36 models' time.
class RunMonitor : public ceres::IterationCallback {
 public:
  static constexpr int kMaxStepsWithoutProgress = 20, kMaxPoorSteps = 5;

  // x: the solver's values; watched[k]: x[k] is free and off its bounds where the run starts.
  RunMonitor(const std::vector<double>& x, std::vector<bool> watched, std::vector<double> lower,
             std::vector<double> upper)
      : x_(x), watched_(std::move(watched)), lower_(std::move(lower)), upper_(std::move(upper)) {}

  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    // A rejected step's summary holds the cost of the point tried, not of x.
    const bool at_x = summary.iteration == 0 || summary.step_is_successful;
    if (summary.iteration > 0 && summary.step_is_successful) {
      ++successful_steps_;
      // Ceres' dogleg halves its radius after an accepted step below a quarter of its promise.
      poor_steps_in_a_row_ = summary.relative_decrease < 0.25 ? poor_steps_in_a_row_ + 1 : 0;
    }
    if (at_x && summary.cost < best_cost_) {
      best_cost_ = summary.cost;
      best_x_ = x_;
      steps_without_progress_ = 0;
    } else if (at_x && ++steps_without_progress_ >= kMaxStepsWithoutProgress) {
      stopped_without_progress_ = true;
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    if (poor_steps_in_a_row_ >= kMaxPoorSteps) {
      crawled_ = true;
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    for (size_t k = 0; k < x_.size(); ++k)
      if (watched_[k] && (x_[k] <= lower_[k] || x_[k] >= upper_[k])) {
        reached_bound_ = true;
        return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
      }
    return ceres::SOLVER_CONTINUE;
  }
  bool reached_bound() const { return reached_bound_; }
  bool stopped_without_progress() const { return stopped_without_progress_; }
  bool crawled() const { return crawled_; }
  int successful_steps() const { return successful_steps_; }
  double best_cost() const { return best_cost_; }
  const std::vector<double>& best_x() const { return best_x_; }

 private:
  const std::vector<double>& x_;
  std::vector<bool> watched_;
  std::vector<double> lower_, upper_;
  bool reached_bound_ = false, stopped_without_progress_ = false, crawled_ = false;
  double best_cost_ = HUGE_VAL;
  std::vector<double> best_x_;
  int steps_without_progress_ = 0;
  int successful_steps_ = 0;
  int poor_steps_in_a_row_ = 0;
};

}  // namespace

std::unique_ptr<ceres::LossFunction> make_loss(LossKind kind, double scale) {
  switch (kind) {
    case LossKind::Huber: return std::make_unique<ceres::HuberLoss>(scale);
    case LossKind::Cauchy: return std::make_unique<ceres::CauchyLoss>(scale);
    case LossKind::None: break;
  }
  return nullptr;
}

Refinement LeastSquares::run(const std::vector<double>& start, int max_iterations, double function_tolerance,
                             double trust_region_radius, const Refinement* earlier) const {
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
  // The same when the run reaches a bound on its way (RunMonitor), so that it does not crawl
  // along it until the cost change falls below the tolerance.
  out.held = earlier && earlier->held_checked ? earlier->held : held_on_bounds(out);
  double radius = trust_region_radius;
  constexpr int kMaxBoundChecks = 8;
  for (int check = 0;; ++check) {
    const SolveEnd end = solve(out, max_iterations - out.iterations, function_tolerance, radius);
    if (!out.usable || out.iterations >= max_iterations || check == kMaxBoundChecks) break;
    std::vector<int> held_now = held_on_bounds(out);
    // A value on its bound can pull inward by its derivative there and push outward at every
    // step a run can take: the cost is not smooth at that bound (openpbr+coat's coat_ior at 1,
    // where the coat's Fresnel at grazing angles grows as the square root of ior − 1). A run
    // whose every step was rejected holds every value on its bound and tries again.
    if (end.steps_tried > 0 && end.successful_steps == 0) {
      std::vector<int> all_on_bounds = on_bounds(out);
      if (all_on_bounds.size() < out.free_index.size()) held_now = std::move(all_on_bounds);
    }
    if (held_now == out.held && !end.reached_bound) {
      out.held_checked = true;
      break;
    }
    out.held = std::move(held_now);
    radius = out.trust_region_radius;
  }
  return out;
}

Refinement LeastSquares::polish(const Refinement& from, int steps) const {
  stop_if_cancelled(options_);
  Refinement out;
  out.values = from.values;
  out.free_index = free_values();
  out.held = from.held;
  if (out.free_index.empty() || steps <= 0) {
    out.cost = 0.5 * cost_of(model_, out.values, samples_, metric_, channels_, loss_);
    out.usable = std::isfinite(out.cost);
    out.termination = "nothing to optimise";
    return out;
  }
  solve(out, steps, 1e-6, 0.0);
  return out;
}

void LeastSquares::estimate_covariance(Refinement& r) const {
  if (r.free_index.empty() || !r.usable) return;
  std::vector<double> x;
  ceres::Problem problem;
  build_problem(r, x, problem);
  estimate_covariance(problem, x, thread_count(options_.threads), r);
}

std::vector<int> LeastSquares::free_values() const {
  std::vector<int> free;
  const std::vector<ValueSlot> slots = value_slots(model_);
  for (int i = 0; i < static_cast<int>(slots.size()); ++i)
    if (!slots[i].param->integer && is_fitted(slots[i], channels_)) free.push_back(i);
  return free;
}

LeastSquares::SolveEnd LeastSquares::solve(Refinement& r, int max_iterations, double function_tolerance,
                                           double trust_region_radius) const {
  std::vector<double> x;
  RunWatch watch(max_iterations, end_jacobian_read_);
  ceres::Problem::Options problem_options;
  problem_options.evaluation_callback = &watch;
  ceres::Problem problem(problem_options);
  build_problem(r, x, problem, &watch);
  const std::vector<ValueSlot> slots = value_slots(model_);
  std::vector<int> held_positions;
  std::vector<bool> watched(x.size());
  std::vector<double> lower(x.size()), upper(x.size());
  for (size_t k = 0; k < x.size(); ++k) {
    const bool held = std::find(r.held.begin(), r.held.end(), r.free_index[k]) != r.held.end();
    if (held) held_positions.push_back(static_cast<int>(k));
    lower[k] = slots[r.free_index[k]].param->lower;
    upper[k] = slots[r.free_index[k]].param->upper;
    watched[k] = !held && x[k] > lower[k] && x[k] < upper[k];
  }
  if (!held_positions.empty())
    problem.SetManifold(x.data(), new ceres::SubsetManifold(static_cast<int>(x.size()), held_positions));

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
  RunMonitor monitor(x, std::move(watched), std::move(lower), std::move(upper));
  solver.update_state_every_iteration = true;  // the monitor reads x
  solver.callbacks.push_back(&monitor);
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  stop_if_cancelled(options_);

  if (monitor.best_cost() < summary.final_cost) {
    x = monitor.best_x();
    summary.final_cost = monitor.best_cost();
  }
  for (size_t k = 0; k < x.size(); ++k) r.values[r.free_index[k]] = x[k];
  r.cost = summary.final_cost;
  r.iterations += static_cast<int>(summary.iterations.size()) - 1;
  if (!summary.iterations.empty()) r.trust_region_radius = summary.iterations.back().trust_region_radius;
  r.termination = monitor.stopped_without_progress()
                      ? fmt::format("no better point in the last {} steps", RunMonitor::kMaxStepsWithoutProgress)
                  : monitor.crawled()
                      ? fmt::format("the last {} steps gave less than a quarter of their predicted decrease",
                                    RunMonitor::kMaxPoorSteps)
                      : std::string(ceres::TerminationTypeToString(summary.termination_type)) + ": " + summary.message;
  r.usable = summary.termination_type != ceres::FAILURE && summary.termination_type != ceres::USER_FAILURE &&
             std::isfinite(summary.final_cost) &&
             std::all_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); });
  return {monitor.reached_bound(), static_cast<int>(summary.iterations.size()) - 1, monitor.successful_steps()};
}

std::vector<int> LeastSquares::on_bounds(const Refinement& r) const {
  const std::vector<ValueSlot> slots = value_slots(model_);
  std::vector<int> on;
  for (int i : r.free_index)
    if (r.values[i] <= slots[i].param->lower || r.values[i] >= slots[i].param->upper) on.push_back(i);
  return on;
}

std::vector<int> LeastSquares::held_on_bounds(const Refinement& r) const {
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

void LeastSquares::build_problem(Refinement& r, std::vector<double>& x, ceres::Problem& problem,
                                 RunWatch* watch) const {
  x.clear();
  for (int i : r.free_index) x.push_back(r.values[i]);
  // Enough batches to keep every thread busy, each large enough to amortise its overhead.
  const size_t batches =
      std::clamp<size_t>(samples_.size() / 2048, 1, static_cast<size_t>(thread_count(options_.threads)) * 16);
  const size_t per_batch = (samples_.size() + batches - 1) / batches;
  memos_.resize((samples_.size() + per_batch - 1) / per_batch);
  for (size_t begin = 0; begin < samples_.size(); begin += per_batch) {
    ResidualBatch batch;
    batch.samples = samples_.data() + begin;
    batch.count = std::min(per_batch, samples_.size() - begin);
    batch.metric = metric_;
    batch.channels = channels_;
    batch.loss = loss_;
    batch.free_index = &r.free_index;
    batch.full_values = &r.values;
    problem.AddResidualBlock(
        new MemoizedCost(new_batch_cost(model_, batch), r.values, r.free_index, memos_[begin / per_batch], watch),
        nullptr, x.data());
  }
  const std::vector<ValueSlot> slots = value_slots(model_);
  for (size_t k = 0; k < x.size(); ++k) {
    const ParamSpec& p = *slots[r.free_index[k]].param;
    problem.SetParameterLowerBound(x.data(), static_cast<int>(k), p.lower);
    problem.SetParameterUpperBound(x.data(), static_cast<int>(k), p.upper);
  }
}

void LeastSquares::estimate_covariance(ceres::Problem& problem, std::vector<double>& x, int threads, Refinement& out) {
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

}  // namespace brdffit::fitting
