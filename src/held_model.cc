// The fitter's view of a model with held parameters (held_model.h).
#include "brdffit/held_model.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include "brdffit/error.h"
#include "brdffit/fit_residual.h"

namespace brdffit {

namespace {

// The full model's batch cost over the same free values: only the indices of the free values
// and the held values change, so the parameter block and residuals are the full cost's own.
class HeldBatchCost final : public ceres::CostFunction {
 public:
  HeldBatchCost(const Model& full, const ResidualBatch& batch, std::vector<int> free_index,
                std::vector<double> full_values)
      : free_index_(std::move(free_index)), full_values_(std::move(full_values)) {
    ResidualBatch inner = batch;
    inner.free_index = &free_index_;
    inner.full_values = &full_values_;
    inner_.reset(brdffit::new_batch_cost(full, inner));
    set_num_residuals(inner_->num_residuals());
    *mutable_parameter_block_sizes() = inner_->parameter_block_sizes();
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    return inner_->Evaluate(parameters, residuals, jacobians);
  }

 private:
  std::vector<int> free_index_;
  std::vector<double> full_values_;
  std::unique_ptr<ceres::CostFunction> inner_;
};

}  // namespace

HeldModel::HeldModel(const Model& full, const std::vector<std::pair<std::string, double>>& held)
    : full_(full), held_values_(full.default_values()) {
  int offset = 0;
  for (const ParamSpec& p : full.parameters()) {
    const auto it = std::find_if(held.begin(), held.end(), [&](const auto& h) { return h.first == p.name; });
    if (it != held.end()) {
      for (int c = 0; c < p.channels; ++c) held_values_[offset + c] = it->second;
      held_names_.push_back(p.name);
    } else {
      free_params_.push_back(p);
      for (int c = 0; c < p.channels; ++c) free_slot_.push_back(offset + c);
    }
    offset += p.channels;
  }
}

std::vector<double> HeldModel::full_values(const double* free_values) const {
  std::vector<double> full = held_values_;
  for (size_t k = 0; k < free_slot_.size(); ++k) full[free_slot_[k]] = free_values[k];
  return full;
}

std::vector<double> HeldModel::free_values(const std::vector<double>& full_values) const {
  std::vector<double> free;
  for (int slot : free_slot_) free.push_back(full_values[slot]);
  return free;
}

namespace {
// Calls use(full) with the full model's values in a buffer on the stack where they fit: the
// grids and costs shade sample by sample, where a vector per call is a fifth of a fit's time.
constexpr size_t kInlineValues = 64;
template <class Use>
auto with_full_values(const std::vector<double>& held_values, const std::vector<int>& free_slot,
                      const double* free_values, Use&& use) {
  std::array<double, kInlineValues> inline_values;
  std::vector<double> heap_values;
  double* full = held_values.size() <= kInlineValues ? inline_values.data()
                                                     : (heap_values.resize(held_values.size()), heap_values.data());
  std::copy(held_values.begin(), held_values.end(), full);
  for (size_t k = 0; k < free_slot.size(); ++k) full[free_slot[k]] = free_values[k];
  return use(full);
}
}  // namespace

Rgb<double> HeldModel::shade(const double* values, const Vec3& l, const Vec3& v) const {
  return with_full_values(held_values_, free_slot_, values,
                          [&](const double* full) { return full_.shade(full, l, v); });
}

std::optional<Rgb<double>> HeldModel::brdf(const double* values, const Vec3& l, const Vec3& v) const {
  return with_full_values(held_values_, free_slot_, values, [&](const double* full) { return full_.brdf(full, l, v); });
}

Rgb<double> HeldModel::shade_with_jacobian(const double* values, const Vec3& l, const Vec3& v, double* jacobian) const {
  const int n_full = full_.num_values(), n_free = static_cast<int>(free_slot_.size());
  std::vector<double> full_jacobian(3 * n_full);
  const Rgb<double> s = with_full_values(held_values_, free_slot_, values, [&](const double* full) {
    return full_.shade_with_jacobian(full, l, v, full_jacobian.data());
  });
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < n_free; ++k) jacobian[c * n_free + k] = full_jacobian[c * n_full + free_slot_[k]];
  return s;
}

ceres::CostFunction* HeldModel::new_batch_cost(const ResidualBatch& batch) const {
  std::vector<int> free_index;
  for (int k : *batch.free_index) free_index.push_back(free_slot_[k]);
  return new HeldBatchCost(full_, batch, std::move(free_index), full_values(batch.full_values->data()));
}

void check_held(const std::vector<const Model*>& models, const std::vector<std::pair<std::string, double>>& held) {
  for (size_t i = 0; i < held.size(); ++i) {
    const auto& [name, value] = held[i];
    for (size_t j = 0; j < i; ++j)
      if (held[j].first == name) fail("--fix: {} is given twice", name);
    bool found = false;
    for (const Model* model : models) {
      const ParamSpec* p = model->find_parameter(name);
      if (!p) continue;
      found = true;
      if (!(value >= p->lower && value <= p->upper))
        fail("--fix {}={}: outside the {} model's bounds [{}, {}]", name, value, model->name(), p->lower, p->upper);
      if (p->integer && value != std::round(value))
        fail("--fix {}={}: the {} model's {} is a whole number", name, value, model->name(), name);
    }
    if (!found) {
      std::string names;
      for (const Model* model : models) names += (names.empty() ? "" : ", ") + model->name();
      fail("--fix {}: none of the models fitted ({}) has a parameter {}", name, names, name);
    }
  }
}

FitResult HeldModel::full_result(FitResult free_fit) const {
  FitResult r = std::move(free_fit);
  if (r.values.size() == free_slot_.size()) r.values = full_values(r.values.data());
  for (std::vector<double>& channel : r.channel_values)
    if (channel.size() == free_slot_.size()) channel = full_values(channel.data());
  std::vector<ParameterEstimate> parameters;
  int offset = 0;
  for (const ParamSpec& p : full_.parameters()) {
    if (std::find(held_names_.begin(), held_names_.end(), p.name) != held_names_.end()) {
      ParameterEstimate e;
      e.name = p.name;
      e.value.assign(p.channels, held_values_[offset]);
      e.stddev.assign(p.channels, NAN);
      e.fixed = true;
      parameters.push_back(std::move(e));
    } else {
      const auto it = std::find_if(r.parameters.begin(), r.parameters.end(),
                                   [&](const ParameterEstimate& e) { return e.name == p.name; });
      if (it != r.parameters.end()) parameters.push_back(*it);
    }
    offset += p.channels;
  }
  r.parameters = std::move(parameters);
  return r;
}

}  // namespace brdffit
