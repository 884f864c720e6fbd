#include "brdffit/two_lobes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>

#include "brdffit/error.h"
#include "brdffit/fit_residual.h"

namespace brdffit {

namespace {

// Components with more values than this are refused (sgd, with 33; the next largest lobe has 10).
constexpr int kMaxComponentValues = 32;
constexpr const char* kSuffix = "_2";

// Direction pairs at which a component's switching scale is checked.
const std::array<std::pair<Vec3, Vec3>, 4>& probe_pairs() {
  static const std::array<std::pair<Vec3, Vec3>, 4> pairs = {
      std::pair{Vec3(0, 0, 1), Vec3(0, 0, 1)},
      {Vec3(0.6, 0, 0.8), Vec3(-0.6, 0, 0.8)},
      {Vec3(0.3, -0.2, 0.93).normalized(), Vec3(-0.5, 0.4, 0.6).normalized()},
      {Vec3(0.9, 0.1, 0.3).normalized(), Vec3(0.1, 0.8, 0.5).normalized()}};
  return pairs;
}

// The model's linear specular colour if setting it to 0 (with albedo 0) leaves nothing at the
// probe pairs, for its defaults and for every other value at its upper bound; else nullptr.
const ParamSpec* switching_scale(const Model& model) {
  for (const ParamSpec& p : model.parameters()) {
    if (p.role != Role::SpecularColour || !p.linear) continue;
    bool vanishes = true;
    for (bool at_upper : {false, true}) {
      std::vector<double> values = model.default_values();
      if (at_upper) {
        int offset = 0;
        for (const ParamSpec& q : model.parameters()) {
          std::fill_n(values.begin() + offset, q.channels, q.upper);
          offset += q.channels;
        }
      }
      std::fill_n(values.begin(), 3, 0.0);  // albedo
      std::fill_n(values.begin() + model.offset_of(p.name), p.channels, 0.0);
      for (const auto& [l, v] : probe_pairs()) vanishes = vanishes && model.shade(values.data(), l, v).isZero(0.0);
    }
    if (vanishes) return &p;
  }
  return nullptr;
}

class TwoLobes final : public Model, public BatchCostSource {
 public:
  TwoLobes(const Model& first, const Model& second) : lobes_{&first, &second} {
    name_ = first.name() + kLobeSeparator + second.name();
    for (const Model* lobe : lobes_) {
      if (!lobe->is_lobe_over_lambert())
        fail("model {}: {} is not a specular lobe over the Lambert base albedo/π, so it cannot be one of two lobes",
             name_, lobe->name());
      if (lobe->num_values() > kMaxComponentValues)
        fail("model {}: {} has {} values, more than the {} a lobe of two may have", name_, lobe->name(),
             lobe->num_values(), kMaxComponentValues);
    }
    const ParamSpec* second_scale = switching_scale(second);
    weighted_ = second_scale == nullptr;
    summary_ = "albedo/π + " + first.name() + " lobe + " + (weighted_ ? "weight_2 · " : "") + second.name() +
               " lobe: two specular lobes over one Lambert base";

    params_.push_back(first.parameters().front());  // albedo
    int linear_index = 1;                           // albedo's is 0
    for (int k = 0; k < 2; ++k) {
      const Model& lobe = *lobes_[k];
      lobe_offset_[k] = num_flattened_;
      for (auto it = std::next(lobe.parameters().begin()); it != lobe.parameters().end(); ++it) {
        const ParamSpec& p = *it;
        if (p.linear) linear_of_component_[k].push_back(linear_index++);
        ParamSpec renamed = p;
        if (k == 1) {
          renamed.name += kSuffix;
          renamed.meaning = "second lobe: " + p.meaning;
          if (weighted_ && p.linear) {
            if (p.channels != 3)  // the fitter solves linear values per channel: every one is a colour
              fail("model {}: {}'s linear parameter {} is not a colour", name_, lobe.name(), p.name);
            renamed.meaning += std::string(", times weight") + kSuffix;
            scaled_linear_.push_back({lobe.offset_of(p.name), num_flattened_});
          }
        }
        params_.push_back(renamed);
        num_flattened_ += p.channels;
      }
    }
    if (weighted_) {
      weight_offset_ = num_flattened_;
      // A colour: the fitter solves linear values per channel.
      params_.push_back({std::string("weight") + kSuffix, 3, 0.0, 1.0, 0.5,
                         "second lobe's scale where its linear values are 0 (ggx: Schlick's reflectance at grazing "
                         "incidence); 0 with them switches it off",
                         Role::SpecularColour, /*linear=*/true});
    }
    declare_nestings(switching_scale(first), second_scale);
    values_ = flattened_size(params_);
    for (int k = 0; k < 2; ++k) lobe_values_[k] = lobes_[k]->num_values();
  }

  const std::string& name() const override { return name_; }
  const std::string& summary() const override { return summary_; }
  const std::vector<ParamSpec>& parameters() const override { return params_; }
  bool has_brdf() const override { return true; }
  bool energy_conserving() const override { return false; }  // two lobes may reflect more than one
  const std::vector<Nesting>& nestings() const override { return nestings_; }

  Rgb<double> shade(const double* values, const Vec3& l, const Vec3& v) const override {
    if (l.z() <= 0.0) return Rgb<double>::Zero();
    return lobes(values, nullptr, [&](const Model& m, const double* p, double*) { return m.shade(p, l, v); }) +
           colour_of(values) * (kInvPi * l.z());
  }

  std::optional<Rgb<double>> brdf(const double* values, const Vec3& l, const Vec3& v) const override {
    return lobes(values, nullptr, [&](const Model& m, const double* p, double*) { return *m.brdf(p, l, v); }) +
           colour_of(values) * kInvPi;
  }

  Rgb<double> shade_with_jacobian(const double* values, const Vec3& l, const Vec3& v, double* jacobian) const override {
    const int n = values_;
    std::fill_n(jacobian, 3 * n, 0.0);
    if (l.z() <= 0.0) return Rgb<double>::Zero();
    for (int c = 0; c < 3; ++c) jacobian[c * n + c] = kInvPi * l.z();  // albedo occupies values 0..2
    return lobes(values, jacobian,
                 [&](const Model& m, const double* p, double* j) { return m.shade_with_jacobian(p, l, v, j); }) +
           colour_of(values) * (kInvPi * l.z());
  }

  // From the components' own splits, one evaluation of each lobe: the albedo's part is n·l/π; the
  // weighted second lobe contributes w·L(0) (weight_2's part) and (w·x_j)·(L(e_j) − L(0)) (lobes()).
  Rgb<double> shade_linear_parts(const double* values, const Vec3& l, const Vec3& v,
                                 Rgb<double>* basis) const override {
    const int composite_linear =
        static_cast<int>(linear_of_component_[0].size() + linear_of_component_[1].size()) + (weighted_ ? 2 : 1);
    std::fill_n(basis, composite_linear, Rgb<double>::Zero());
    if (l.z() <= 0.0) return Rgb<double>::Zero();
    basis[0] = Rgb<double>::Constant(kInvPi * l.z());
    std::array<Rgb<double>, kMaxComponentValues> parts;  // a component's albedo's, then its other linear ones'
    Rgb<double> base = Rgb<double>::Zero();
    for (int k = 0; k < 2; ++k) {
      const Values p = component_values(k, values);
      const Rgb<double> lobe_base = lobes_[k]->shade_linear_parts(p.data(), l, v, parts.data());
      for (size_t j = 0; j < linear_of_component_[k].size(); ++j) basis[linear_of_component_[k][j]] = parts[j + 1];
      if (k == 1 && weighted_)
        basis[composite_linear - 1] = lobe_base;  // weight_2, the last parameter
      else
        base += lobe_base;
    }
    return base;
  }

  ceres::CostFunction* new_batch_cost(const ResidualBatch& batch) const override {
    return new JacobianBatchCost(*this, batch);
  }

 private:
  using Values = std::array<double, kMaxComponentValues>;
  using Jacobian = std::array<double, 3 * kMaxComponentValues>;

  // The colour stored at values[0..2] (albedo is the composite's first parameter, as every lobe's).
  static Rgb<double> colour_of(const double* values) { return Rgb<double>(values[0], values[1], values[2]); }

  // The composite's index of component k's value i (i >= 3: after the component's albedo).
  int composite_index(int k, int i) const { return lobe_offset_[k] + i - 3; }

  // Component k's values taken from the composite's, with its albedo at 0 (the lobe alone).
  Values component_values(int k, const double* values) const {
    Values p;  // only the values the component reads are set: this runs per sample
    std::fill_n(p.begin(), 3, 0.0);
    std::copy_n(values + composite_index(k, 3), lobe_values_[k] - 3, p.begin() + 3);
    return p;
  }

  // Adds scale_c · (component jacobian) to the composite's, for component k's values other than
  // albedo and, for the weighted lobe, its linear ones (the composite's own values there).
  void add_jacobian(int k, const Jacobian& component, const Rgb<double>& scale, double* jacobian) const {
    const int n = values_, m = lobe_values_[k];
    for (int c = 0; c < 3; ++c)
      for (int i = 3; i < m; ++i)
        if (!(k == 1 && is_scaled_linear(i)))
          jacobian[c * n + composite_index(k, i)] += scale[c] * component[c * m + i];
  }

  bool is_scaled_linear(int component_index) const {
    for (const auto& [from, to] : scaled_linear_)
      if (component_index >= from && component_index < from + 3) return true;
    return false;
  }

  // The sum of both lobes; `eval(model, component values, component jacobian or null)`; adds
  // the derivatives to `jacobian` (3 x num_values()) when it is not null.
  //
  // The weighted second lobe is affine in its linear values x (colours): L(x) = L(0) + Σ_j x_j
  // (L(e_j) - L(0)), e_j = 1 in x_j, 0 elsewhere. Scaled by w it is w·L(0) + Σ_j (w x_j)(L(e_j) - L(0)),
  // and the composite stores p_j = w x_j: affine in w and every p_j jointly, so the fitter solves
  // them all exactly, and w = p = 0 switches the lobe off.
  template <class Eval>
  Rgb<double> lobes(const double* values, double* jacobian, Eval&& eval) const {
    Jacobian component_jacobian, base_jacobian;
    double* j = jacobian ? component_jacobian.data() : nullptr;
    Values p = component_values(0, values);
    Rgb<double> sum = eval(*lobes_[0], p.data(), j);
    if (jacobian) add_jacobian(0, component_jacobian, Rgb<double>::Ones(), jacobian);
    p = component_values(1, values);
    if (!weighted_) {
      sum += eval(*lobes_[1], p.data(), j);
      if (jacobian) add_jacobian(1, component_jacobian, Rgb<double>::Ones(), jacobian);
      return sum;
    }
    const int n = values_, m = lobe_values_[1];
    for (const auto& [from, to] : scaled_linear_) std::fill_n(p.begin() + from, 3, 0.0);
    const Rgb<double> w = colour_of(values + weight_offset_);
    const Rgb<double> base = eval(*lobes_[1], p.data(), jacobian ? base_jacobian.data() : nullptr);
    sum += w.cwiseProduct(base);
    if (jacobian) {
      add_jacobian(1, base_jacobian, w, jacobian);
      for (int c = 0; c < 3; ++c) jacobian[c * n + weight_offset_ + c] = base[c];
    }
    for (const auto& [from, to] : scaled_linear_) {
      std::fill_n(p.begin() + from, 3, 1.0);
      const Rgb<double> difference = eval(*lobes_[1], p.data(), j) - base;
      std::fill_n(p.begin() + from, 3, 0.0);
      const Rgb<double> scaled = colour_of(values + to);
      sum += scaled.cwiseProduct(difference);
      if (!jacobian) continue;
      for (int i = 0; i < 3 * m; ++i) component_jacobian[i] -= base_jacobian[i];
      add_jacobian(1, component_jacobian, scaled, jacobian);
      for (int c = 0; c < 3; ++c) jacobian[c * n + to + c] = difference[c];
    }
    return sum;
  }

  void declare_nestings(const ParamSpec* first_scale, const ParamSpec* second_scale) {
    // What switches the second lobe off: its specular scale, or the weight with the values it scales.
    std::vector<std::pair<std::string, double>> second_off;
    if (weighted_) {
      second_off.push_back({std::string("weight") + kSuffix, 0.0});
      for (const auto& [from, to] : scaled_linear_)
        for (const ParamSpec& p : params_)
          if (offset_of(p.name) == to) second_off.push_back({p.name, 0.0});
    } else {
      second_off.push_back({second_scale->name + kSuffix, 0.0});
    }
    std::string off_names;
    for (const auto& [name, value] : second_off) off_names += (off_names.empty() ? "" : ", ") + name;
    Nesting first{lobes_[0]->name(), {}, second_off, true, "the second lobe switched off (" + off_names + " = 0)"};
    for (const ParamSpec& p : lobes_[0]->parameters()) first.copies.push_back({p.name, p.name});
    nestings_.push_back(first);
    Nesting lambert{"lambert", {{"albedo", "albedo"}}, second_off, first_scale != nullptr, "both lobes switched off"};
    if (first_scale) {
      lambert.fixed.push_back({first_scale->name, 0.0});
    } else {
      // No scale of the first lobe removes it: its linear values at 0 are the nearest start.
      for (const ParamSpec& p : lobes_[0]->parameters())
        if (p.linear && p.name != "albedo") lambert.fixed.push_back({p.name, 0.0});
      lambert.why = "second lobe switched off, the first's linear values at 0 (" + lobes_[0]->name() +
                    "'s lobe does not vanish with them)";
    }
    nestings_.push_back(lambert);
  }

  std::array<const Model*, 2> lobes_;
  std::array<int, 2> lobe_offset_{};  // where each component's values after its albedo start in the composite's
  // The composite's linear index (Model::shade_linear_parts) of each component's linear parameters but albedo.
  std::array<std::vector<int>, 2> linear_of_component_;
  // Weighted second lobe: its linear colours, as (offset in the component, offset in the composite).
  std::vector<std::pair<int, int>> scaled_linear_;
  std::string name_, summary_;
  std::vector<ParamSpec> params_;
  std::vector<Nesting> nestings_;
  int num_flattened_ = 3;  // albedo's
  // num_values() of the composite and of its lobes, which the evaluations per sample need (Model
  // counts them over the parameters at each call).
  int values_ = 0;
  std::array<int, 2> lobe_values_{};
  bool weighted_ = false;
  int weight_offset_ = -1;
};

}  // namespace

std::unique_ptr<Model> make_two_lobes(const Model& first, const Model& second) {
  return std::make_unique<TwoLobes>(first, second);
}

}  // namespace brdffit
