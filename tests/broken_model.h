// A model whose evaluation fails everywhere, for tests of what happens when a fit fails.
#pragma once

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>

#include "brdffit/fit_residual.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"

namespace brdffit::test {

// Lambert's parameters, NaN shading, and a cost function that cannot be evaluated: its fit
// must fail cleanly (ok = false with a reason).
class BrokenModel final : public Model, public BatchCostSource {
 public:
  const std::string& name() const override { return name_; }
  const std::string& summary() const override { return name_; }
  const std::vector<ParamSpec>& parameters() const override { return lambert().parameters(); }
  bool has_brdf() const override { return false; }
  bool energy_conserving() const override { return false; }
  Rgb<double> shade(const double*, const Vec3&, const Vec3&) const override { return Rgb<double>::Constant(NAN); }
  std::optional<Rgb<double>> brdf(const double*, const Vec3&, const Vec3&) const override { return std::nullopt; }
  Rgb<double> shade_with_jacobian(const double* values, const Vec3& l, const Vec3& v, double* jacobian) const override {
    std::fill_n(jacobian, 9, NAN);
    return shade(values, l, v);
  }
  ceres::CostFunction* new_batch_cost(const ResidualBatch& batch) const override {
    struct Nan final : ceres::CostFunction {
      explicit Nan(int n) {
        set_num_residuals(n + 1);
        mutable_parameter_block_sizes()->push_back(n);
      }
      bool Evaluate(double const* const*, double*, double**) const override { return false; }
    };
    return new Nan(static_cast<int>(batch.free_index->size()));
  }

 private:
  static const Model& lambert() { return *find_model("lambert"); }
  std::string name_ = "broken";
};

}  // namespace brdffit::test
