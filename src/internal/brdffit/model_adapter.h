// Turns a model struct (see models/lambert.h) into a brdffit::Model. Included by the registry
// only: this is where the model's templated evaluation is instantiated for double and for
// ceres::Jet.
//
// A model struct provides kName, kSummary, kEnergyConserving, kNumValues, parameters(), and
// either brdf<T>(p, l, v) (physically based: shade = f·max(n·l,0) is derived here) or
// shade<T>(p, l, v) (stylised: the seed's shader expression without the light colour);
// optionally nestings() (model.h: the simpler models it contains), recovery_facts() (model.h:
// what fits recover from its values) and kSeparateChannels with kNumParameters
// (separate_channels.h: one derivative per parameter). A lobe over the Lambert base is a
// models::OverLambert (models/over_lambert.h). The adapter is also the model's BatchCostSource:
// the fitter's cost is a BatchCost<M> (fit_residual.h).
#pragma once

#include <ceres/jet.h>

#include <algorithm>
#include <iterator>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "brdffit/fit_residual.h"
#include "brdffit/model.h"
#include "brdffit/models/over_lambert.h"
#include "brdffit/separate_channels.h"

namespace brdffit {

template <class M>
class ModelAdapter final : public Model, public BatchCostSource {
 public:
  ModelAdapter() : name_(M::kName), summary_(M::kSummary), params_(M::parameters()) {
    static_assert(M::kNumValues > 0, "a model needs parameters");
    if constexpr (Declares<NestingsOf, M>::value) nestings_ = M::nestings();
    if constexpr (Declares<RecoveryFactsOf, M>::value) recovery_facts_ = M::recovery_facts();
    if constexpr (SeparateChannels<M>::value)
      if (parameter_slots<M>().slots() != M::kNumParameters || flattened_size(params_) != M::kNumValues)
        throw std::logic_error(name_ + ": kNumParameters or kNumValues does not match parameters()");
    // The derivative slot of each linear value in shade_linear_parts: the parameter's own with
    // separate channels (channel c's derivative there is the one by component c), else one per value.
    std::fill(std::begin(linear_slot_), std::end(linear_slot_), -1);
    int offset = 0;
    for (const ParamSpec& p : params_) {
      if (p.linear) {
        if (linear_count_ == kMaxLinearParameters)
          throw std::logic_error(name_ + ": more linear parameters than ModelAdapter::kMaxLinearParameters");
        for (int c = 0; c < p.channels; ++c)
          linear_slot_[offset + c] = SeparateChannels<M>::value ? linear_count_ : 3 * linear_count_ + c;
        linear_values_[linear_count_] = {offset, p.channels};
        ++linear_count_;
      }
      offset += p.channels;
    }
  }

  const std::string& name() const override { return name_; }
  const std::string& summary() const override { return summary_; }
  const std::vector<ParamSpec>& parameters() const override { return params_; }
  bool has_brdf() const override { return HasBrdf<M>::value; }
  bool energy_conserving() const override { return M::kEnergyConserving; }

  Rgb<double> shade(const double* values, const Vec3& l, const Vec3& v) const override {
    return shade_of<M>(values, l, v);
  }

  std::optional<Rgb<double>> brdf(const double* values, const Vec3& l, const Vec3& v) const override {
    if constexpr (HasBrdf<M>::value) {
      return M::brdf(values, l, v);
    } else {
      return std::nullopt;
    }
  }

  Rgb<double> shade_with_jacobian(const double* values, const Vec3& l, const Vec3& v, double* jacobian) const override {
    if constexpr (SeparateChannels<M>::value) {  // one derivative per parameter (separate_channels.h)
      const ParameterSlots& slots = parameter_slots<M>();
      using Jet = ceres::Jet<double, M::kNumParameters>;
      Jet p[M::kNumValues];
      for (int i = 0; i < M::kNumValues; ++i) p[i] = Jet(values[i], slots.slot_of_value[i]);
      const Rgb<Jet> s = shade_of<M>(p, l, v);
      for (int c = 0; c < 3; ++c)
        for (int i = 0; i < M::kNumValues; ++i)
          jacobian[c * M::kNumValues + i] = slots.enters(i, c) ? s[c].v[slots.slot_of_value[i]] : 0.0;
      return Rgb<double>(s[0].a, s[1].a, s[2].a);
    }
    using Jet = ceres::Jet<double, M::kNumValues>;
    Jet p[M::kNumValues];
    for (int i = 0; i < M::kNumValues; ++i) p[i] = Jet(values[i], i);
    const Rgb<Jet> s = shade_of<M>(p, l, v);
    for (int c = 0; c < 3; ++c)
      for (int i = 0; i < M::kNumValues; ++i) jacobian[c * M::kNumValues + i] = s[c].v[i];
    return Rgb<double>(s[0].a, s[1].a, s[2].a);
  }

  // One evaluation with Jets whose derivatives are those by the linear parameters, exact since the
  // value is affine in them: for sgd a third of the cost of evaluating three times. The Jets are as
  // wide as the model's linear values need (one linear parameter: half of the widest, whose unused
  // derivatives a Jet would carry through every step; gltf+sheen's grids and linear solves).
  Rgb<double> shade_linear_parts(const double* values, const Vec3& l, const Vec3& v,
                                 Rgb<double>* basis) const override {
    if constexpr (ScaledLobeOverLambert<M>::value) return scaled_lobe_linear_parts(values, l, v, basis);
    return linear_count_ <= 1 ? linear_parts_on_jets<1>(values, l, v, basis)
                              : linear_parts_on_jets<kMaxLinearParameters>(values, l, v, basis);
  }
  template <int kLinearParameters>
  Rgb<double> linear_parts_on_jets(const double* values, const Vec3& l, const Vec3& v, Rgb<double>* basis) const {
    constexpr bool kPerParameter = SeparateChannels<M>::value;
    using Jet = ceres::Jet<double, kPerParameter ? kLinearParameters : 3 * kLinearParameters>;
    // Written in place: a temporary Jet per value, its derivative stored 8 bytes at a time and
    // loaded 16 at a time, stalled the store forwarding of every linear value (a third of sgd's
    // coordinate search).
    Jet p[M::kNumValues];
    for (int i = 0; i < M::kNumValues; ++i) {
      if (linear_slot_[i] < 0)
        p[i].a = values[i];
      else
        p[i].v[linear_slot_[i]] = 1.0;
    }
    const Rgb<Jet> s = shade_of<M>(p, l, v);
    for (int j = 0; j < linear_count_; ++j)
      for (int c = 0; c < 3; ++c) basis[j][c] = s[c].v[kPerParameter ? j : 3 * j + c];
    return Rgb<double>(s[0].a, s[1].a, s[2].a);
  }

  // shade_linear_parts of a lobe over Lambert that its linear parameter scales, from one evaluation
  // on doubles: albedo's part is n·l/π, the lobe's its shade at albedo 0 and scale 1, the base 0
  // (or, for a lobe with no linear parameter, that shade). On Jets every shape term carried the
  // derivatives too: sgd's evaluation took 1.7 times as long, ggx's 2.6 times.
  Rgb<double> scaled_lobe_linear_parts(const double* values, const Vec3& l, const Vec3& v, Rgb<double>* basis) const {
    double unit[M::kNumValues];
    std::copy_n(values, M::kNumValues, unit);
    std::fill_n(unit + linear_values_[0].first, linear_values_[0].second, 0.0);  // albedo (over_lambert.h)
    if (linear_count_ == 2) std::fill_n(unit + linear_values_[1].first, linear_values_[1].second, 1.0);
    const Rgb<double> lobe = shade_of<M>(unit, l, v);
    const double lambert = l.z() > 0.0 ? kInvPi * l.z() : 0.0;
    basis[0] = Rgb<double>::Constant(lambert);
    if (linear_count_ == 1) return lobe;
    basis[1] = lobe;
    return Rgb<double>::Zero();
  }

  const std::vector<Nesting>& nestings() const override { return nestings_; }
  bool is_lobe_over_lambert() const override { return models::IsOverLambert<M>::value; }
  const RecoveryFacts& recovery_facts() const override { return recovery_facts_; }

  ceres::CostFunction* new_batch_cost(const ResidualBatch& batch) const override { return new BatchCost<M>(batch); }

 private:
  // The struct's optional members: Declares<NestingsOf, M> where M has nestings().
  template <class N>
  using NestingsOf = decltype(N::nestings());
  template <class N>
  using RecoveryFactsOf = decltype(N::recovery_facts());
  template <template <class> class Member, class N, class = void>
  struct Declares : std::false_type {};
  template <template <class> class Member, class N>
  struct Declares<Member, N, std::void_t<Member<N>>> : std::true_type {};

  template <class N, class = void>
  struct ScaledLobeOverLambert : std::false_type {};
  template <class N>
  struct ScaledLobeOverLambert<N, std::enable_if_t<models::IsOverLambert<N>::value>>
      : std::bool_constant<N::kLobeScaledByLinearParameter> {};

  static constexpr int kMaxLinearParameters = 2;  // the most any model has (albedo and specular)

  std::string name_, summary_;
  std::vector<ParamSpec> params_;
  int linear_slot_[M::kNumValues];                           // -1 for a value that is not linear
  std::pair<int, int> linear_values_[kMaxLinearParameters];  // each linear parameter's offset and channels
  int linear_count_ = 0;
  std::vector<Nesting> nestings_;
  RecoveryFacts recovery_facts_;
};

}  // namespace brdffit
