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

void LeastSquares::solve(Refinement& r, int max_iterations, double function_tolerance,
                         double trust_region_radius) const {
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

void LeastSquares::build_problem(Refinement& r, std::vector<double>& x, ceres::Problem& problem) const {
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
