// The fitter's Ceres hook, kept off the public Model interface (model.h names no Ceres or
// fitter type). The model adapters implement it: ModelAdapter<M> with its templated BatchCost,
// the two-lobe composite and HeldModel with their own; the fitter asks a model for its cost
// through new_batch_cost(model, batch) (fit_residual.h), which gives any other Model the cost
// derived from its shade_with_jacobian.
#pragma once

namespace ceres {
class CostFunction;
}

namespace brdffit {

struct ResidualBatch;  // fit_residual.h

class BatchCostSource {
 public:
  // A Ceres cost function covering a batch of samples (see fit_residual.h); owned by caller.
  virtual ceres::CostFunction* new_batch_cost(const ResidualBatch& batch) const = 0;

 protected:
  ~BatchCostSource() = default;
};

}  // namespace brdffit
