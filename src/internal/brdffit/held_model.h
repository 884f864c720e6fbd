// FitOptions::fixed: a model with some of its parameters held at known values (a dielectric's
// metallic 0, a known ior 1.5), seen by the fitter as a model of the remaining parameters only.
// The grid, the linear solve, the trust region and the covariance then never touch the held
// values, and the standard deviations are those of the remaining parameters with the held ones
// known exactly. A held model has no nestings: its nested starts would place the held values
// elsewhere.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "brdffit/batch_cost_source.h"
#include "brdffit/fit.h"
#include "brdffit/model.h"

namespace brdffit {

class HeldModel final : public Model, public BatchCostSource {
 public:
  // `held`: parameter name and value (every channel of a colour); names the model does not have
  // are ignored (fit_models checks them against every model of a run).
  HeldModel(const Model& full, const std::vector<std::pair<std::string, double>>& held);

  const std::string& name() const override { return full_.name(); }
  const std::string& summary() const override { return full_.summary(); }
  const std::vector<ParamSpec>& parameters() const override { return free_params_; }
  bool has_brdf() const override { return full_.has_brdf(); }
  bool energy_conserving() const override { return full_.energy_conserving(); }
  Rgb<double> shade(const double* values, const Vec3& l, const Vec3& v) const override;
  std::optional<Rgb<double>> brdf(const double* values, const Vec3& l, const Vec3& v) const override;
  Rgb<double> shade_with_jacobian(const double* values, const Vec3& l, const Vec3& v, double* jacobian) const override;
  ceres::CostFunction* new_batch_cost(const ResidualBatch& batch) const override;

  bool holds_any() const { return held_count() > 0; }
  int held_count() const { return static_cast<int>(held_values_.size() - free_slot_.size()); }
  // The full model's values from the free ones (held values inserted), and back.
  std::vector<double> full_values(const double* free_values) const;
  std::vector<double> free_values(const std::vector<double>& full_values) const;
  // A fit of this model as a fit of the full one: values expanded, the held parameters listed
  // with fixed = true and no standard deviation.
  FitResult full_result(FitResult free_fit) const;

 private:
  const Model& full_;
  std::vector<ParamSpec> free_params_;
  std::vector<int> free_slot_;       // the full model's flattened index of each free value
  std::vector<double> held_values_;  // the full model's values: held ones set, others at default
  std::vector<std::string> held_names_;
};

// Throws Error naming the parameter when a held name is given twice, belongs to none of `models`,
// or its value lies outside the bounds of a model that has it (or is not a whole number for an
// integer parameter).
void check_held(const std::vector<const Model*>& models, const std::vector<std::pair<std::string, double>>& held);

}  // namespace brdffit
