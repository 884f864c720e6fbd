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
  // holds the others, which the memo's key includes; it and `memo` must outlive this.
  MemoizedCost(ceres::CostFunction* cost, const std::vector<double>& values, const std::vector<int>& free_index,
               CostMemo& memo)
      : cost_(cost), values_(values), free_index_(free_index), memo_(memo) {
    set_num_residuals(cost->num_residuals());
    *mutable_parameter_block_sizes() = cost->parameter_block_sizes();
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
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
};

}  // namespace brdffit::fitting
