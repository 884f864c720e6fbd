// Variable projection (see variable_projection.h).
#include "brdffit/variable_projection.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace brdffit {

Eigen::VectorXd solve_box_quadratic(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, const Eigen::VectorXd& lower,
                                    const Eigen::VectorXd& upper) {
  const int n = static_cast<int>(b.size());
  int combinations = 1;
  for (int i = 0; i < n; ++i) combinations *= 3;
  Eigen::VectorXd best = lower;
  double best_value = HUGE_VAL;
  for (int code = 0; code < combinations; ++code) {
    Eigen::VectorXd x(n);
    std::vector<int> free;
    int rest = code;
    for (int i = 0; i < n; ++i, rest /= 3) {
      if (rest % 3 == 0) free.push_back(i);
      x[i] = rest % 3 == 1 ? lower[i] : upper[i];
    }
    if (!free.empty()) {
      const int f = static_cast<int>(free.size());
      Eigen::MatrixXd a_free(f, f);
      Eigen::VectorXd rhs(f);
      for (int i = 0; i < f; ++i) {
        rhs[i] = b[free[i]];
        for (int j = 0; j < n; ++j)
          if (std::find(free.begin(), free.end(), j) == free.end()) rhs[i] -= a(free[i], j) * x[j];
        for (int j = 0; j < f; ++j) a_free(i, j) = a(free[i], free[j]);
      }
      const Eigen::VectorXd x_free = a_free.completeOrthogonalDecomposition().solve(rhs);
      bool feasible = x_free.allFinite();
      for (int i = 0; i < f && feasible; ++i) {
        feasible = x_free[i] >= lower[free[i]] - 1e-12 && x_free[i] <= upper[free[i]] + 1e-12;
        x[free[i]] = std::clamp(x_free[i], lower[free[i]], upper[free[i]]);
      }
      if (!feasible) continue;
    }
    const double value = x.dot(a * x) - 2.0 * b.dot(x);
    if (value < best_value) {
      best_value = value;
      best = x;
    }
  }
  return best;
}

double solve_linear(const Model& model, std::vector<double>& values, const std::vector<Sample>& samples, Metric metric,
                    const Channels& channels, double* cost_as_given, double give_up_above) {
  if (cost_as_given) *cost_as_given = NAN;
  std::vector<const ParamSpec*> linear;
  for (const ParamSpec& p : model.parameters())
    if (p.linear) linear.push_back(&p);
  if (linear.empty()) return NAN;
  const int m = static_cast<int>(linear.size());

  // The normal equations per channel, summed in plain arrays: Eigen's dynamic matrices reloaded
  // their storage at every term (the sums were a seventh of a solve for sgd).
  constexpr int kMaxLinear = 8;
  if (m > kMaxLinear) throw std::logic_error(model.name() + ": more linear parameters than solve_linear takes");
  double normal[3][kMaxLinear][kMaxLinear] = {}, projection[3][kMaxLinear] = {};
  std::array<double, 3> target_squares{0.0, 0.0, 0.0};  // Σ w·target², for the cost at the solution
  Rgb<double> basis[kMaxLinear];

  const double lo0 = linear[0]->lower, hi0 = linear[0]->upper;
  const double lo1 = m > 1 ? linear[1]->lower : 0.0, hi1 = m > 1 ? linear[1]->upper : 0.0;
  // A lower bound of the objective at the solution, from the sums so far: their minimum over the
  // box, and the sums over all samples only add terms ≥ 0. Less a millionth of Σ w·target², more
  // than the rounding of the minimum where the normal equations are as well conditioned as asked;
  // NaN where they are not, or for more than two linear parameters. (With one or two parameters
  // the minimum over the box has a closed form: inside it, or on the nearest edge.)
  auto lower_bound_so_far = [&]() -> double {
    double bound = 0.0, targets = 0.0;
    for (int c = 0; c < 3; ++c) {
      if (!channels[c]) continue;
      // xᵀAx − 2pᵀx, A = [a b; b d]
      const double a = normal[c][0][0], p0 = projection[c][0];
      double least;
      if (m == 1) {
        if (!(a > 0.0)) return NAN;
        const double x = std::clamp(p0 / a, lo0, hi0);
        least = a * x * x - 2.0 * p0 * x;
      } else if (m == 2) {
        const double b = normal[c][0][1], d = normal[c][1][1], p1 = projection[c][1], det = a * d - b * b;
        if (!(det > 1e-6 * a * d)) return NAN;
        auto q = [&](double x0, double x1) {
          return a * x0 * x0 + 2.0 * b * x0 * x1 + d * x1 * x1 - 2.0 * (p0 * x0 + p1 * x1);
        };
        const double x0 = (d * p0 - b * p1) / det, x1 = (a * p1 - b * p0) / det;
        if (x0 >= lo0 && x0 <= hi0 && x1 >= lo1 && x1 <= hi1) {
          least = q(x0, x1);
        } else {
          least = HUGE_VAL;
          for (double edge : {lo0, hi0}) least = std::min(least, q(edge, std::clamp((p1 - b * edge) / d, lo1, hi1)));
          for (double edge : {lo1, hi1}) least = std::min(least, q(std::clamp((p0 - b * edge) / a, lo0, hi0), edge));
        }
      } else {
        return NAN;
      }
      bound += target_squares[c] + least;
      targets += target_squares[c];
    }
    return bound - 1e-6 * targets;
  };
  constexpr size_t kGiveUpCheck = 256;  // samples between two looks at the bound
  const bool may_give_up = give_up_above < HUGE_VAL && metric_is_quadratic(metric);
  size_t since_check = 0;

  for (const Sample& s : samples) {
    if (may_give_up && ++since_check == kGiveUpCheck) {
      since_check = 0;
      const double bound = lower_bound_so_far();
      if (bound > give_up_above) return bound;
    }
    const Rgb<double> base = model.shade_linear_parts(values.data(), s.l, s.v, basis);
    for (int c = 0; c < 3; ++c) {
      if (!channels[c]) continue;
      const double w = metric_linear_weight(metric, s.weight, s.value[c]);
      const double target = s.value[c] - base[c];
      target_squares[c] += w * target * target;
      for (int i = 0; i < m; ++i) {
        projection[c][i] += w * basis[i][c] * target;
        for (int j = 0; j < m; ++j) normal[c][i][j] += w * basis[i][c] * basis[j][c];
      }
    }
  }
  std::array<Eigen::MatrixXd, 3> a;
  std::array<Eigen::VectorXd, 3> b;
  for (int c = 0; c < 3; ++c) {
    a[c].resize(m, m);
    b[c].resize(m);
    for (int i = 0; i < m; ++i) {
      b[c][i] = projection[c][i];
      for (int j = 0; j < m; ++j) a[c](i, j) = normal[c][i][j];
    }
  }
  Eigen::VectorXd lower(m), upper(m);
  for (int j = 0; j < m; ++j) {
    lower[j] = linear[j]->lower;
    upper[j] = linear[j]->upper;
  }
  // Σ w·(target − basis·x)² = xᵀAx − 2bᵀx + Σ w·target², summed over the fitted channels.
  auto objective = [](double cost) { return std::isfinite(cost) ? std::max(cost, 0.0) : HUGE_VAL; };
  double cost = 0.0, given_cost = 0.0;
  for (int c = 0; c < 3; ++c) {
    if (!channels[c]) continue;
    Eigen::VectorXd given(m);
    for (int j = 0; j < m; ++j) given[j] = values[model.offset_of(linear[j]->name) + c];
    given_cost += given.dot(a[c] * given) - 2.0 * b[c].dot(given) + target_squares[c];
    const Eigen::VectorXd x = solve_box_quadratic(a[c], b[c], lower, upper);
    for (int j = 0; j < m; ++j) values[model.offset_of(linear[j]->name) + c] = x[j];
    cost += x.dot(a[c] * x) - 2.0 * b[c].dot(x) + target_squares[c];
  }
  // The log metric's weights only linearise it: its cost is not this quadratic.
  if (!metric_is_quadratic(metric)) return NAN;
  if (cost_as_given) *cost_as_given = objective(given_cost);
  return objective(cost);
}

}  // namespace brdffit
