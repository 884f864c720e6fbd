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
#include <memory>
#include <vector>

namespace brdffit::fitting {

// Tells a run's batches when Ceres asks for a Jacobian nothing reads: at the point its last
// allowed step reached. Ceres evaluates the Jacobian at every accepted point before it checks the
// iteration limit, so a run that ends on its limit (the polish on all samples, a walk at its cap)
// ends with one pass over its samples with derivatives for no step. Each iteration costs at most
// one trial point (cost only); once `max_iterations` trial points have been costed, the Jacobian
// asked for next is that one. Ceres then sees a zero gradient there, which only its summary reads.
class FinalJacobianWatch final : public ceres::EvaluationCallback {
 public:
  explicit FinalJacobianWatch(int max_iterations) : max_iterations_(max_iterations) {}
  void PrepareForEvaluation(bool evaluate_jacobians, bool new_evaluation_point) override {
    if (!evaluate_jacobians) ++trial_points_;
    unread_ = evaluate_jacobians && !new_evaluation_point && trial_points_ >= max_iterations_;
  }
  // Whether the Jacobian about to be asked for is the one after the last allowed step.
  bool jacobian_unread() const { return unread_; }

 private:
  const int max_iterations_;
  int trial_points_ = 0;
  bool unread_ = false;
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
  // this. Where `watch` tells that the Jacobian asked for is unread, it is answered with zeros.
  MemoizedCost(ceres::CostFunction* cost, const std::vector<double>& values, const std::vector<int>& free_index,
               CostMemo& memo, const FinalJacobianWatch* watch = nullptr)
      : cost_(cost), values_(values), free_index_(free_index), memo_(memo), watch_(watch) {
    set_num_residuals(cost->num_residuals());
    *mutable_parameter_block_sizes() = cost->parameter_block_sizes();
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    if (jacobians && jacobians[0] && watch_ && watch_->jacobian_unread()) {
      std::fill_n(jacobians[0], num_residuals() * free_index_.size(), 0.0);
      return Evaluate(parameters, residuals, nullptr);  // the trial point's cost, from the memo
    }
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

 private:
  std::unique_ptr<ceres::CostFunction> cost_;
  const std::vector<double>& values_;
  const std::vector<int>& free_index_;
  CostMemo& memo_;
  const FinalJacobianWatch* watch_;
};

}  // namespace brdffit::fitting
