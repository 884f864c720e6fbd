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

// Rosenbrock's valley as eight residual blocks of one parameter block, each its own MemoizedCost
// watched by `watch` (if any), solved by Ceres' dogleg as the fitter solves: the end, and the
// evaluations of the blocks without and with derivatives.
struct WatchedSolve {
  std::vector<double> x;
  ceres::Solver::Summary summary;
  int calls = 0, jacobian_calls = 0;
};
WatchedSolve solve_rosenbrock(int max_iterations, double initial_radius, RunWatch* watch) {
  WatchedSolve out;
  out.x = {-1.2, 1.0};
  const std::vector<double> values = {0.0, 0.0};
  const std::vector<int> free_index = {0, 1};
  std::vector<CostMemo> memos(8);
  ceres::Problem::Options problem_options;
  problem_options.evaluation_callback = watch;
  ceres::Problem problem(problem_options);
  for (CostMemo& memo : memos)
    problem.AddResidualBlock(new MemoizedCost(new ceres::AutoDiffCostFunction<Rosenbrock, 2, 2>(
                                                  new Rosenbrock{&out.calls, &out.jacobian_calls}),
                                              values, free_index, memo, watch),
                             nullptr, out.x.data());
  ceres::Solver::Options options;
  options.trust_region_strategy_type = ceres::DOGLEG;
  options.use_nonmonotonic_steps = true;
  options.initial_trust_region_radius = initial_radius;
  options.max_num_iterations = max_iterations;
  options.max_num_line_search_step_size_iterations = 0;
  ceres::Solve(options, &problem, &out.summary);
  return out;
}

// A run that ends on its iteration limit after an accepted step: Ceres asks for the Jacobian there
// before it looks at the limit. With a RunWatch that one is answered with zeros, uncomputed: the
// same iterations, the same end and cost, bit for bit, and every block's Jacobian once fewer.
// Limits of 1 to 12 iterations from (−1.2, 1), from a radius small enough for its steps to be
// accepted; with end_jacobian_read, that Jacobian is computed.
TEST(RunWatch, TheJacobianAfterARunsLastAllowedStepIsNotComputed) {
  int ended_on_an_accepted_step = 0;
  for (int limit = 1; limit <= 12; ++limit) {
    SCOPED_TRACE(limit);
    RunWatch watch(limit, /*end_jacobian_read=*/false), reading(limit, /*end_jacobian_read=*/true);
    const WatchedSolve plain = solve_rosenbrock(limit, 0.1, nullptr);
    const WatchedSolve watched = solve_rosenbrock(limit, 0.1, &watch);
    const WatchedSolve read = solve_rosenbrock(limit, 0.1, &reading);
    EXPECT_EQ(watched.x, plain.x);
    EXPECT_EQ(watched.summary.final_cost, plain.summary.final_cost);
    ASSERT_EQ(watched.summary.iterations.size(), plain.summary.iterations.size());
    EXPECT_EQ(watched.summary.termination_type, plain.summary.termination_type);
    const bool limit_reached = static_cast<int>(plain.summary.iterations.size()) == limit + 1;
    const int unread = limit_reached && plain.summary.iterations.back().step_is_successful ? 1 : 0;
    ended_on_an_accepted_step += unread;
    EXPECT_EQ(watched.jacobian_calls, plain.jacobian_calls - 8 * unread);
    EXPECT_EQ(read.jacobian_calls, plain.jacobian_calls);
    EXPECT_EQ(read.x, plain.x);
  }
  EXPECT_GE(ended_on_an_accepted_step, 6);  // 7 of the 12: else the test would show little
}

// From Ceres' radius of 1e4, a walk down Rosenbrock's valley tries many points far above its
// start. With a RunWatch, a trial point whose blocks' costs pass twice the start's fails from the
// next block on, and Ceres rejects it as it would have: the same iterations, each step accepted or
// rejected alike, the same end and cost, bit for bit, with fewer block evaluations. A trial point
// just below twice the start is costed whole.
TEST(RunWatch, ATrialPointPastTwiceTheStartsCostIsGivenUpAndRejectedAllTheSame) {
  RunWatch watch(100, /*end_jacobian_read=*/true);
  const WatchedSolve plain = solve_rosenbrock(100, 1e4, nullptr);
  const WatchedSolve watched = solve_rosenbrock(100, 1e4, &watch);
  EXPECT_EQ(watched.x, plain.x);
  EXPECT_NEAR(plain.x[0], 1.0, 1e-6);
  EXPECT_EQ(watched.summary.final_cost, plain.summary.final_cost);
  ASSERT_EQ(watched.summary.iterations.size(), plain.summary.iterations.size());
  const double start = plain.summary.iterations[0].cost;
  int far_above = 0;
  for (size_t i = 1; i < plain.summary.iterations.size(); ++i) {
    const ceres::IterationSummary &p = plain.summary.iterations[i], &w = watched.summary.iterations[i];
    EXPECT_EQ(w.step_is_successful, p.step_is_successful) << "iteration " << i;
    EXPECT_EQ(w.trust_region_radius, p.trust_region_radius) << "iteration " << i;
    if (p.step_is_successful) EXPECT_EQ(w.cost, p.cost) << "iteration " << i;
    if (!p.step_is_successful && p.cost > 2.0 * start) ++far_above;
  }
  EXPECT_GE(far_above, 3);
  EXPECT_LT(watched.calls, plain.calls);
}

}  // namespace
}  // namespace brdffit::fitting
