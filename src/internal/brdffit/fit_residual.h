// The fitter's Ceres cost function: one residual block per batch of samples.
//
// One residual block per sample costs Ceres per-block bookkeeping and a Jacobian row per
// sample (about 7x the time and 3x the memory on a full MERL table). A BatchCost instead
// evaluates its samples with automatic derivatives and hands Ceres a compressed but exact
// equivalent: with r the batch's residual vector and J its Jacobian at the current point,
//
//     ‖r + Jδ‖² = ‖y + Rδ‖² + e²     for every step δ,
//
// where RᵀR = JᵀJ, Rᵀy = Jᵀr and e² = ‖r‖² − ‖y‖². The block returns the K+1 residuals
// (y, e) with Jacobian (R; 0): the cost, the gradient and the Gauss-Newton/LM model are the
// same as with every sample as its own residual, so steps, convergence and the covariance
// at the optimum are unchanged.
//
// A robust loss ρ is applied per sample-channel by replacing r with √ρ(r²) (and its
// derivative), so outliers are down-weighted sample by sample, not batch by batch.
//
// LeastSquares (least_squares.cc) hands Ceres each batch's cost wrapped in a MemoizedCost
// (memoized_cost.h), which answers again for the values the batch was last evaluated at.
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>
#include <vector>

#include "brdffit/batch_cost_source.h"
#include "brdffit/metric.h"
#include "brdffit/model.h"
#include "brdffit/model_eval.h"
#include "brdffit/samples.h"
#include "brdffit/separate_channels.h"

namespace brdffit {

struct ResidualBatch {
  const Sample* samples = nullptr;
  size_t count = 0;
  Metric metric = Metric::Cosine;
  std::array<bool, 3> channels{true, true, true};  // which measured channels are fitted
  const ceres::LossFunction* loss = nullptr;       // per sample-channel, not owned; may be null
  // The parameter block holds only the free values: full[free_index[k]] = x[k]; the others
  // keep their value in *full_values (integer parameters, channels fitted separately).
  const std::vector<int>* free_index = nullptr;
  const std::vector<double>* full_values = nullptr;
};

namespace detail {

// √ρ(r²) with its derivative scale d√ρ/dr, for a loss ρ (identity when loss is null).
inline void robustify(const ceres::LossFunction* loss, double r, double& r_out, double& scale) {
  if (!loss) {
    r_out = r;
    scale = 1.0;
    return;
  }
  double rho[3];
  loss->Evaluate(r * r, rho);
  const double root = std::sqrt(rho[0]);
  r_out = std::copysign(root, r);
  scale = root > 1e-150 ? rho[1] * std::fabs(r) / root : std::sqrt(rho[1]);
}

// The cost-only evaluation shared by the batch costs: residuals 0 but the last, √(Σ r²).
template <class Shade>
bool evaluate_cost_only(const ResidualBatch& batch, int num_free, Shade&& shade, double* residuals) {
  double rr = 0.0;
  for (size_t i = 0; i < batch.count; ++i) {
    const Sample& s = batch.samples[i];
    const Rgb<double> predicted = shade(s);
    const double sqrt_w = std::sqrt(metric_weight(batch.metric, s.weight));
    for (int c = 0; c < 3; ++c) {
      if (!batch.channels[c]) continue;
      double value, scale;
      robustify(batch.loss, metric_residual(batch.metric, predicted[c], s.value[c]) * sqrt_w, value, scale);
      rr += value * value;
    }
  }
  for (int k = 0; k < num_free; ++k) residuals[k] = 0.0;
  residuals[num_free] = std::sqrt(rr);
  return std::isfinite(rr);
}

// Writes y, e and the (F+1) x F row-major Jacobian (R; 0) for the free values' JᵀJ (F x F)
// and Jᵀr.
inline void compress(const Eigen::MatrixXd& jtj, const Eigen::VectorXd& jtr, double rr, double* residuals,
                     double* jacobian) {
  const int F = static_cast<int>(jtr.size());
  // Any square root of JᵀJ will do. With S = diag(JᵀJ)^-½ and S·JᵀJ·S = V Λ Vᵀ:
  // R = Λ^½ Vᵀ S⁻¹ and y = Λ^-½ Vᵀ S Jᵀr. The scaling keeps precision when values differ in
  // scale by orders of magnitude (albedo against a sharp lobe's F0); the eigen-decomposition
  // copes with a singular JᵀJ (a value these samples do not determine), where Jᵀr has no
  // component either.
  Eigen::VectorXd s(F);
  for (int k = 0; k < F; ++k) s[k] = jtj(k, k) > 0.0 ? 1.0 / std::sqrt(jtj(k, k)) : 1.0;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(s.asDiagonal() * jtj * s.asDiagonal());
  const Eigen::VectorXd lambda = eig.eigenvalues().cwiseMax(0.0);
  const double tiny = 1e-300 + lambda.maxCoeff() * 1e-15;
  const Eigen::VectorXd scaled_jtr = s.cwiseProduct(jtr);
  Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> jac(jacobian, F + 1, F);
  jac.setZero();
  double yy = 0.0;
  for (int k = 0; k < F; ++k) {
    const double root = std::sqrt(lambda[k]);
    const Eigen::VectorXd u = eig.eigenvectors().col(k);
    jac.row(k).head(F) = root * u.cwiseQuotient(s).transpose();
    residuals[k] = lambda[k] > tiny ? u.dot(scaled_jtr) / root : 0.0;
    yy += residuals[k] * residuals[k];
  }
  residuals[F] = std::sqrt(std::max(rr - yy, 0.0));
  // A value these samples do not move at all (its column of J is zero: sheenTint where sheen is 0)
  // gets an exactly zero column of R, as ‖R e_k‖² = (JᵀJ)_kk = 0 says. The eigen-decomposition
  // would otherwise leave round-off there wherever another value is almost undetermined too (its
  // eigenvector mixes with e_k), enough for the covariance to call the value determined.
  for (int k = 0; k < F; ++k)
    if (!(jtj(k, k) > 0.0)) jac.col(k).setZero();
}

}  // namespace detail

template <class M>
class BatchCost final : public ceres::CostFunction {
  static constexpr int K = M::kNumValues;
  using Jet = ceres::Jet<double, K>;

 public:
  explicit BatchCost(const ResidualBatch& batch) : batch_(batch) {
    num_free_ = static_cast<int>(batch.free_index->size());
    set_num_residuals(num_free_ + 1);
    mutable_parameter_block_sizes()->push_back(num_free_);
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    std::array<double, K> full;
    for (int i = 0; i < K; ++i) full[i] = (*batch_.full_values)[i];
    const std::vector<int>& free = *batch_.free_index;
    for (int k = 0; k < num_free_; ++k) full[free[k]] = parameters[0][k];

    if (!jacobians || !jacobians[0]) return evaluate_cost_only(full.data(), residuals);
    if constexpr (SeparateChannels<M>::value) return evaluate_per_parameter(full, residuals, jacobians[0]);

    // Differentiate with respect to the free values only; fixed values are constants.
    std::array<Jet, K> p;
    for (int i = 0; i < K; ++i) p[i] = Jet(full[i]);
    for (int k = 0; k < num_free_; ++k) p[free[k]].v[k] = 1.0;

    std::array<Eigen::Matrix<double, K, K>, 3> jtj;
    std::array<Eigen::Matrix<double, K, 1>, 3> jtr;
    const double rr = accumulate(p.data(), jtj, jtr);
    if (!std::isfinite(rr)) return false;
    const Eigen::Matrix<double, K, K> upper = jtj[0] + jtj[1] + jtj[2];
    compress(upper.template selfadjointView<Eigen::Upper>(), jtr[0] + jtr[1] + jtr[2], rr, residuals, jacobians[0]);
    return true;
  }

 private:
  // Shades the batch's samples with the Jets p and sums, per fitted channel, the upper triangle of
  // JᵀJ and Jᵀr over the Jets' derivative slots; returns Σ r² (robustified).
  //
  // The gradients are gathered kBlock at a time, and each channel's JᵀJ takes one rank-k update per
  // block (a matrix product) instead of a rank-1 update per sample: Eigen's rank-1 update of a small
  // fixed-size matrix is an out-of-line call per row, 8 % of an sgd fit. One derivative keeps the
  // rank-1 update: Eigen would take its 1 × k block for a vector.
  template <int N>
  double accumulate(const ceres::Jet<double, N>* p, std::array<Eigen::Matrix<double, N, N>, 3>& jtj,
                    std::array<Eigen::Matrix<double, N, 1>, 3>& jtr) const {
    using NJet = ceres::Jet<double, N>;
    constexpr int kBlock = N > 1 ? 32 : 1;
    for (int c = 0; c < 3; ++c) {
      jtj[c].setZero();
      jtr[c].setZero();
    }
    std::array<Eigen::Matrix<double, N, kBlock>, 3> grads;
    std::array<Eigen::Matrix<double, kBlock, 1>, 3> values;
    std::array<int, 3> gathered{0, 0, 0};
    auto add_block = [&](int c) {
      const int k = gathered[c];
      if constexpr (kBlock == 1) {
        jtj[c].template selfadjointView<Eigen::Upper>().rankUpdate(grads[c].col(0));
      } else {
        jtj[c].template selfadjointView<Eigen::Upper>().rankUpdate(grads[c].leftCols(k));
      }
      jtr[c] += grads[c].leftCols(k) * values[c].head(k);
      gathered[c] = 0;
    };
    double rr = 0.0;
    for (size_t i = 0; i < batch_.count; ++i) {
      const Sample& s = batch_.samples[i];
      const Rgb<NJet> shade = shade_of<M>(p, s.l, s.v);
      const double sqrt_w = std::sqrt(metric_weight(batch_.metric, s.weight));
      for (int c = 0; c < 3; ++c) {
        if (!batch_.channels[c]) continue;
        const NJet r = metric_residual(batch_.metric, shade[c], s.value[c]) * sqrt_w;
        double value, scale;
        detail::robustify(batch_.loss, r.a, value, scale);
        rr += value * value;
        grads[c].col(gathered[c]) = r.v * scale;
        values[c][gathered[c]] = value;
        if (++gathered[c] == kBlock) add_block(c);
      }
    }
    for (int c = 0; c < 3; ++c)
      if (gathered[c] > 0) add_block(c);
    return rr;
  }

  // Evaluate's derivatives for separate channels (separate_channels.h): one Jet slot per
  // parameter, JᵀJ and Jᵀr per channel in slot space, then each channel's slots scattered to the
  // free values they stand for in that channel. A fixed value gets no derivative.
  bool evaluate_per_parameter(const std::array<double, K>& full, double* residuals, double* jacobian) const {
    constexpr int W = M::kNumParameters;
    using Jet = ceres::Jet<double, W>;
    const ParameterSlots& slots = parameter_slots<M>();
    std::array<int, K> free_position;  // the value's index among the free values, or -1
    free_position.fill(-1);
    for (int k = 0; k < num_free_; ++k) free_position[(*batch_.free_index)[k]] = k;
    std::array<Jet, K> p;
    for (int i = 0; i < K; ++i) {
      p[i] = Jet(full[i]);
      if (free_position[i] >= 0) p[i].v[slots.slot_of_value[i]] = 1.0;
    }

    std::array<Eigen::Matrix<double, W, W>, 3> jtj;
    std::array<Eigen::Matrix<double, W, 1>, 3> jtr;
    const double rr = accumulate(p.data(), jtj, jtr);
    if (!std::isfinite(rr)) return false;

    Eigen::MatrixXd free_jtj = Eigen::MatrixXd::Zero(num_free_, num_free_);
    Eigen::VectorXd free_jtr = Eigen::VectorXd::Zero(num_free_);
    for (int c = 0; c < 3; ++c) {
      const Eigen::Matrix<double, W, W> full_jtj = jtj[c].template selfadjointView<Eigen::Upper>();
      for (int a = 0; a < W; ++a) {
        const int fa = free_position[slots.value(a, c)];
        if (fa < 0) continue;
        free_jtr[fa] += jtr[c][a];
        for (int b = 0; b < W; ++b)
          if (const int fb = free_position[slots.value(b, c)]; fb >= 0) free_jtj(fa, fb) += full_jtj(a, b);
      }
    }
    detail::compress(free_jtj, free_jtr, rr, residuals, jacobian);
    return true;
  }

  bool evaluate_cost_only(const double* full, double* residuals) const {
    return detail::evaluate_cost_only(
        batch_, num_free_, [full](const Sample& s) { return shade_of<M>(full, s.l, s.v); }, residuals);
  }

  // The free block of JᵀJ and Jᵀr: the Jets carry derivatives in their first F entries.
  template <class JtJ>
  void compress(const JtJ& jtj_full, const Eigen::Matrix<double, K, 1>& jtr_full, double rr, double* residuals,
                double* jacobian) const {
    const int F = num_free_;
    detail::compress(Eigen::MatrixXd(jtj_full).topLeftCorner(F, F), jtr_full.head(F), rr, residuals, jacobian);
  }

  ResidualBatch batch_;
  int num_free_ = 0;
};

}  // namespace brdffit

namespace brdffit {

// The same cost as BatchCost for a model whose number of values is known only at run time (a
// composite built from registered models, two_lobes.h): derivatives from the model's
// shade_with_jacobian, the same compressed residuals.
class JacobianBatchCost final : public ceres::CostFunction {
 public:
  // `model` must outlive the cost.
  JacobianBatchCost(const Model& model, const ResidualBatch& batch) : model_(model), batch_(batch) {
    num_free_ = static_cast<int>(batch.free_index->size());
    set_num_residuals(num_free_ + 1);
    mutable_parameter_block_sizes()->push_back(num_free_);
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const int n = model_.num_values();
    std::vector<double> full = *batch_.full_values;
    const std::vector<int>& free = *batch_.free_index;
    for (int k = 0; k < num_free_; ++k) full[free[k]] = parameters[0][k];
    if (!jacobians || !jacobians[0])
      return detail::evaluate_cost_only(
          batch_, num_free_, [&](const Sample& s) { return model_.shade(full.data(), s.l, s.v); }, residuals);

    using Scalar = ceres::Jet<double, 1>;  // differentiates the metric's residual with respect to the shade
    std::vector<double> jacobian(3 * n);
    Eigen::MatrixXd jtj = Eigen::MatrixXd::Zero(num_free_, num_free_);
    Eigen::VectorXd jtr = Eigen::VectorXd::Zero(num_free_);
    double rr = 0.0;
    // The rows of J (a sample's channel each) are gathered in blocks, and JᵀJ takes one rank-k
    // update per block, a matrix product: a rank-1 update of the dynamic-size JᵀJ per row was a
    // tenth of a two-lobe fit.
    constexpr int kBlockRows = 48;
    Eigen::Matrix<double, kBlockRows, Eigen::Dynamic, Eigen::RowMajor> rows(kBlockRows, num_free_);
    Eigen::Matrix<double, kBlockRows, 1> row_residuals;
    int filled = 0;
    auto add_rows = [&] {
      jtj.selfadjointView<Eigen::Upper>().rankUpdate(rows.topRows(filled).transpose());
      jtr += rows.topRows(filled).transpose() * row_residuals.head(filled);
      filled = 0;
    };
    for (size_t i = 0; i < batch_.count; ++i) {
      const Sample& s = batch_.samples[i];
      const Rgb<double> shade = model_.shade_with_jacobian(full.data(), s.l, s.v, jacobian.data());
      const double sqrt_w = std::sqrt(metric_weight(batch_.metric, s.weight));
      for (int c = 0; c < 3; ++c) {
        if (!batch_.channels[c]) continue;
        const Scalar r = metric_residual(batch_.metric, Scalar(shade[c], 0), s.value[c]) * sqrt_w;
        double value, scale;
        detail::robustify(batch_.loss, r.a, value, scale);
        for (int k = 0; k < num_free_; ++k) rows(filled, k) = jacobian[c * n + free[k]] * r.v[0] * scale;
        row_residuals[filled] = value;
        rr += value * value;
        if (++filled == kBlockRows) add_rows();
      }
    }
    if (filled > 0) add_rows();
    if (!std::isfinite(rr)) return false;
    detail::compress(Eigen::MatrixXd(jtj.selfadjointView<Eigen::Upper>()), jtr, rr, residuals, jacobians[0]);
    return true;
  }

 private:
  const Model& model_;
  ResidualBatch batch_;
  int num_free_ = 0;
};

// The model's batch cost: its own when it is a BatchCostSource (every model of the registry, the
// two-lobe composite, a HeldModel), else a JacobianBatchCost from its shade_with_jacobian. Owned
// by the caller; `model` must outlive it.
inline ceres::CostFunction* new_batch_cost(const Model& model, const ResidualBatch& batch) {
  if (const auto* source = dynamic_cast<const BatchCostSource*>(&model)) return source->new_batch_cost(batch);
  return new JacobianBatchCost(model, batch);
}

}  // namespace brdffit
