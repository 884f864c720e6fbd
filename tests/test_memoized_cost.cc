// MemoizedCost (memoized_cost.h): Ceres' repeated requests are answered from the memo, anything
// else reaches the wrapped cost function, and a fit is the same with the memo as without it.
#include <gtest/gtest.h>

#include <type_traits>

#include "brdffit/memoized_cost.h"

namespace brdffit::fitting {
namespace {

// r = (a·b + c, a − b) over the free values a, b and a value c it does not optimise; counts the
// evaluations it is asked for, and fails where a = 0.
class CountedCost final : public ceres::SizedCostFunction<2, 2> {
 public:
  explicit CountedCost(const std::vector<double>& values, int& calls) : values_(values), calls_(calls) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    ++calls_;
    const double a = parameters[0][0], b = parameters[0][1], c = values_[2];
    if (a == 0.0) return false;
    residuals[0] = a * b + c;
    residuals[1] = a - b;
    if (jacobians && jacobians[0]) {
      const double jacobian[4] = {b, a, 1.0, -1.0};
      std::copy(jacobian, jacobian + 4, jacobians[0]);
    }
    return true;
  }

 private:
  const std::vector<double>& values_;
  int& calls_;
};

TEST(MemoizedCost, AnswersTheSameValuesAgainAndAsksForAnyOther) {
  std::vector<double> values = {0.0, 0.0, 0.5};  // a, b free; c = 0.5
  const std::vector<int> free_index = {0, 1};
  CostMemo memo;
  int calls = 0;
  auto evaluate = [&](std::vector<double> x, bool with_jacobian) {
    MemoizedCost cost(new CountedCost(values, calls), values, free_index, memo);  // as each run builds anew
    const double* parameters[] = {x.data()};
    std::vector<double> out(2 + 4, -1.0);
    double* jacobians[] = {out.data() + 2};
    const bool ok = cost.Evaluate(parameters, out.data(), with_jacobian ? jacobians : nullptr);
    if (!ok) out.clear();
    return out;
  };
  // 2·3 + 0.5 = 6.5, 2 − 3 = −1; J = (3 2; 1 −1).
  const std::vector<double> cost_only = {6.5, -1.0, -1.0, -1.0, -1.0, -1.0};
  const std::vector<double> with_jacobian = {6.5, -1.0, 3.0, 2.0, 1.0, -1.0};
  EXPECT_EQ(evaluate({2, 3}, false), cost_only);
  EXPECT_EQ(evaluate({2, 3}, false), cost_only);
  EXPECT_EQ(calls, 1);
  // The Jacobian is not in the cost-only memo: asked once, then remembered beside it.
  EXPECT_EQ(evaluate({2, 3}, true), with_jacobian);
  EXPECT_EQ(evaluate({2, 3}, true), with_jacobian);
  EXPECT_EQ(evaluate({2, 3}, false), cost_only);
  EXPECT_EQ(calls, 2);
  // Other free values, or the same free values with another fixed one: asked again.
  EXPECT_EQ(evaluate({2, 4}, false)[0], 8.5);
  values[2] = 1.5;
  EXPECT_EQ(evaluate({2, 4}, false)[0], 9.5);
  EXPECT_EQ(calls, 4);
  // The free values' own entries in `values` are not part of what the memo compares.
  values[0] = 7.0;
  EXPECT_EQ(evaluate({2, 4}, false)[0], 9.5);
  EXPECT_EQ(calls, 4);
  // A failed evaluation fails again, and is not remembered.
  EXPECT_TRUE(evaluate({0, 4}, false).empty());
  EXPECT_TRUE(evaluate({0, 4}, false).empty());
  EXPECT_EQ(calls, 6);
}

// Rosenbrock's valley as r = (10(b − a²), 1 − a), counting its evaluations (and, if given,
// those with derivatives apart).
struct Rosenbrock {
  int* calls;
  int* jacobian_calls = nullptr;
  template <class T>
  bool operator()(const T* x, T* r) const {
    ++*calls;
    if (jacobian_calls && !std::is_same_v<T, double>) ++*jacobian_calls;
    r[0] = 10.0 * (x[1] - x[0] * x[0]);
    r[1] = 1.0 - x[0];
    return true;
  }
};

TEST(MemoizedCost, ASolveEndsWhereItDoesWithoutTheMemoWithFewerEvaluations) {
  // From (−1.2, 1) by Ceres' dogleg, from a radius the Gauss-Newton step is far inside: the
  // trial point does not change while the radius shrinks to it, and the memo answers for it.
  // The same iterations and the same end, bit for bit.
  auto solve = [](bool memoized, ceres::Solver::Summary& summary, int& calls) {
    std::vector<double> x = {-1.2, 1.0}, values = {0.0, 0.0};
    const std::vector<int> free_index = {0, 1};
    CostMemo memo;
    ceres::CostFunction* cost = new ceres::AutoDiffCostFunction<Rosenbrock, 2, 2>(new Rosenbrock{&calls});
    ceres::Problem problem;
    problem.AddResidualBlock(memoized ? new MemoizedCost(cost, values, free_index, memo) : cost, nullptr, x.data());
    ceres::Solver::Options options;
    options.trust_region_strategy_type = ceres::DOGLEG;
    options.use_nonmonotonic_steps = true;
    options.initial_trust_region_radius = 1e4;
    ceres::Solve(options, &problem, &summary);
    return x;
  };
  ceres::Solver::Summary plain, memoized;
  int plain_calls = 0, memoized_calls = 0;
  const std::vector<double> plain_end = solve(false, plain, plain_calls);
  const std::vector<double> memoized_end = solve(true, memoized, memoized_calls);
  EXPECT_EQ(memoized_end, plain_end);
  EXPECT_NEAR(plain_end[0], 1.0, 1e-6);
  EXPECT_EQ(memoized.iterations.size(), plain.iterations.size());
  EXPECT_EQ(memoized.final_cost, plain.final_cost);
  EXPECT_LT(memoized_calls, plain_calls);
}

// A run that ends on its iteration limit after an accepted step: Ceres asks for the Jacobian there
// before it looks at the limit. With FinalJacobianWatch that one is answered with zeros, uncomputed:
// the same iterations, the same end and cost, bit for bit, one Jacobian fewer. Limits of 1 to 12
// iterations from (−1.2, 1), from a radius small enough for its steps to be accepted.
TEST(FinalJacobianWatch, TheJacobianAfterARunsLastAllowedStepIsNotComputed) {
  auto solve = [](int max_iterations, bool watched, ceres::Solver::Summary& summary, int& jacobian_calls) {
    std::vector<double> x = {-1.2, 1.0}, values = {0.0, 0.0};
    const std::vector<int> free_index = {0, 1};
    CostMemo memo;
    int calls = 0;
    FinalJacobianWatch watch(max_iterations);
    ceres::Problem::Options problem_options;
    if (watched) problem_options.evaluation_callback = &watch;
    ceres::Problem problem(problem_options);
    problem.AddResidualBlock(
        new MemoizedCost(new ceres::AutoDiffCostFunction<Rosenbrock, 2, 2>(new Rosenbrock{&calls, &jacobian_calls}),
                         values, free_index, memo, watched ? &watch : nullptr),
        nullptr, x.data());
    ceres::Solver::Options options;
    options.trust_region_strategy_type = ceres::DOGLEG;
    options.use_nonmonotonic_steps = true;
    options.initial_trust_region_radius = 0.1;
    options.max_num_iterations = max_iterations;
    ceres::Solve(options, &problem, &summary);
    return x;
  };
  int ended_on_an_accepted_step = 0;
  for (int limit = 1; limit <= 12; ++limit) {
    SCOPED_TRACE(limit);
    ceres::Solver::Summary plain, watched;
    int plain_jacobians = 0, watched_jacobians = 0;
    const std::vector<double> plain_end = solve(limit, false, plain, plain_jacobians);
    const std::vector<double> watched_end = solve(limit, true, watched, watched_jacobians);
    EXPECT_EQ(watched_end, plain_end);
    EXPECT_EQ(watched.final_cost, plain.final_cost);
    ASSERT_EQ(watched.iterations.size(), plain.iterations.size());
    EXPECT_EQ(watched.termination_type, plain.termination_type);
    const bool limit_reached = static_cast<int>(plain.iterations.size()) == limit + 1;
    const bool last_accepted = plain.iterations.back().step_is_successful;
    const int unread = limit_reached && last_accepted ? 1 : 0;
    ended_on_an_accepted_step += unread;
    EXPECT_EQ(watched_jacobians, plain_jacobians - unread);
  }
  EXPECT_GE(ended_on_an_accepted_step, 8);  // else the test would show little
}

}  // namespace
}  // namespace brdffit::fitting
