// A cost function that answers again for the values it was last given, from a memo that outlives
// it: Ceres asks again for points it has evaluated, and the fitter's runs over the same samples
// each build a new problem.
//
// Where the fitter's batches (fit_residual.h) are asked again for the same values:
// - the same trial point, cost only, while Ceres' dogleg radius shrinks from its initial 1e4
//   down to the Gauss-Newton step's length, which does not change meanwhile (a dozen times);
// - the Jacobian where a run ends at its last step: the bounds are looked at there
//   (LeastSquares::held_on_bounds' gradient) and the next run starts there (its iteration 0).
// The same values give the same answer: a fit is unchanged, bit for bit, and costs a sixth less
// for openpbr+coat+fuzz (docs/performance.md, eleventh round).
#pragma once

#include <ceres/ceres.h>

#include <algorithm>
#include <atomic>
#include <limits>
#include <memory>
#include <vector>

namespace brdffit::fitting {

// Watches one Ceres run (its EvaluationCallback; its batches report their costs) for the
// evaluations whose result cannot change where the run goes:
//
// - The Jacobian after the run's last allowed step. Ceres evaluates the Jacobian at every accepted
//   point before it checks the iteration limit, so a run that ends on its limit (the polish on all
//   samples, a walk at its cap) would end with a pass over its samples with derivatives for no
//   step. Each iteration costs at most one trial point; once `max_iterations` have been costed,
//   the Jacobian asked for next is that one. It is answered with zeros, which only Ceres' summary
//   reads.
// - The rest of a trial point's cost once the part summed passes twice the run's starting cost.
//   Every point a run accepts costs less than its start (the non-monotonic steps too: less than
//   an earlier point), so Ceres rejects such a trial point, and its dogleg halves the radius
//   whatever the cost; a trial point whose evaluation fails is one of infinite cost, rejected the
//   same way. Twice the start and not once: Ceres also ends a run where a trial point costs within
//   function_tolerance of the current point, which a sum cut just past the start could feign.
//   Trial points rejected at 10 to 10⁴ times the cost are common in the heavy models' walks.
class RunWatch final : public ceres::EvaluationCallback {
 public:
  // end_jacobian_read: the Jacobian after the last allowed step is read afterwards (a covariance
  // estimated there finds it in the memo), and is computed.
  RunWatch(int max_iterations, bool end_jacobian_read)
      : max_iterations_(end_jacobian_read ? std::numeric_limits<int>::max() : max_iterations) {}

  void PrepareForEvaluation(bool evaluate_jacobians, bool new_evaluation_point) override {
    // The run's first evaluation, at its start and with the Jacobian, has ended.
    if (start_cost_ < 0.0 && evaluations_ > 0) start_cost_ = cost_.load();
    ++evaluations_;
    if (!evaluate_jacobians) ++trial_points_;
    costing_trial_ = !evaluate_jacobians;
    jacobian_unread_ = evaluate_jacobians && !new_evaluation_point && trial_points_ >= max_iterations_;
    cost_ = 0.0;
  }
  // Whether the Jacobian about to be asked for is the one after the last allowed step.
  bool jacobian_unread() const { return jacobian_unread_; }
  // Whether the evaluation is a trial point whose cost summed so far passes twice the start's:
  // Ceres will reject it.
  bool trial_rejected() const { return costing_trial_ && start_cost_ >= 0.0 && cost_.load() > 2.0 * start_cost_; }
  // Adds one batch's cost (½Σr²) to the evaluation's (batches may end on several threads).
  void add(double batch_cost) {
    double sum = cost_.load();
    while (!cost_.compare_exchange_weak(sum, sum + batch_cost)) {
    }
  }

 private:
  const int max_iterations_;
  int evaluations_ = 0, trial_points_ = 0;
  bool costing_trial_ = false, jacobian_unread_ = false;
  double start_cost_ = -1.0;       // the first evaluation's cost, once it has ended
  std::atomic<double> cost_{0.0};  // the current evaluation's, summed over the batches that ended
};

// The last evaluation, cost only and with the Jacobian, of one cost function over one parameter
// block of free values.
struct CostMemo {
  struct Evaluation {
    std::vector<double> values;  // every value of the model, the free ones as evaluated
    std::vector<double> residuals, jacobian;
  };
  Evaluation cost_only, with_jacobian;
};

class MemoizedCost final : public ceres::CostFunction {
 public:
  // Takes `cost` (one parameter block: the free values, values[free_index[k]] = x[k]). `values`
  // holds the others, which the memo's key includes; it, `memo` and `watch` (if any) must outlive
  // this. With a watch, a Jacobian it tells is unread is answered with zeros, and a trial point it
  // tells Ceres will reject fails (RunWatch).
  MemoizedCost(ceres::CostFunction* cost, const std::vector<double>& values, const std::vector<int>& free_index,
               CostMemo& memo, RunWatch* watch = nullptr)
      : cost_(cost), values_(values), free_index_(free_index), memo_(memo), watch_(watch) {
    set_num_residuals(cost->num_residuals());
    *mutable_parameter_block_sizes() = cost->parameter_block_sizes();
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    if (!watch_) return answer(parameters, residuals, jacobians);
    if (jacobians && jacobians[0] && watch_->jacobian_unread()) {
      std::fill_n(jacobians[0], num_residuals() * free_index_.size(), 0.0);
      return answer(parameters, residuals, nullptr);  // the trial point's cost, from the memo
    }
    if (watch_->trial_rejected()) return false;  // a step of infinite cost: rejected all the same
    if (!answer(parameters, residuals, jacobians)) return false;
    double squares = 0.0;
    for (int i = 0; i < num_residuals(); ++i) squares += residuals[i] * residuals[i];
    watch_->add(0.5 * squares);
    return true;
  }

 private:
  // The evaluation, from the memo where it holds these values.
  bool answer(double const* const* parameters, double* residuals, double** jacobians) const {
    const bool with_jacobian = jacobians && jacobians[0];
    CostMemo::Evaluation& last = with_jacobian ? memo_.with_jacobian : memo_.cost_only;
    std::vector<double> values = values_;
    for (size_t k = 0; k < free_index_.size(); ++k) values[free_index_[k]] = parameters[0][k];
    if (values == last.values && last.residuals.size() == static_cast<size_t>(num_residuals())) {
      std::copy(last.residuals.begin(), last.residuals.end(), residuals);
      if (with_jacobian) std::copy(last.jacobian.begin(), last.jacobian.end(), jacobians[0]);
      return true;
    }
    last.values.clear();
    if (!cost_->Evaluate(parameters, residuals, jacobians)) return false;
    last.residuals.assign(residuals, residuals + num_residuals());
    if (with_jacobian) last.jacobian.assign(jacobians[0], jacobians[0] + num_residuals() * free_index_.size());
    last.values = std::move(values);
    return true;
  }

  std::unique_ptr<ceres::CostFunction> cost_;
  const std::vector<double>& values_;
  const std::vector<int>& free_index_;
  CostMemo& memo_;
  RunWatch* watch_;
};

}  // namespace brdffit::fitting
