// The models' scalar helpers (brdffit/math.h) against derivatives written out by hand.
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <thread>
#include <type_traits>

#include "brdffit/math.h"

namespace brdffit {
namespace {

using Jet5 = ceres::Jet<double, 5>;

// A term of three parameters with every partial derivative non-zero at the point below.
auto term = [](const auto& x, const auto& y, const auto& z) {
  using std::exp;
  using std::sin;
  return x * x * sin(y) * exp(z);
};

TEST(OfParameters, IsTheTermItselfForDoubles) {
  EXPECT_DOUBLE_EQ(of_parameters(term, 0.7, 1.3, -0.4), 0.49 * std::sin(1.3) * std::exp(-0.4));
  EXPECT_DOUBLE_EQ(of_one_parameter(0.7, [](double x) { return x * x; }), 0.49);
}

// Each argument a Jet of five derivatives that depends on several of them: the result's
// derivatives are the chain rule's Σ ∂f/∂xᵢ · ∂xᵢ/∂slot.
TEST(OfParameters, PutsTheChainRuleBackOnTheWideJet) {
  Jet5 x(0.7), y(1.3), z(-0.4);
  x.v << 1.0, 0.0, 2.0, 0.0, 0.5;
  y.v << 0.0, 1.0, -1.0, 0.0, 0.0;
  z.v << 0.0, 0.0, 0.0, 1.0, 3.0;
  const Jet5 narrow = of_parameters(term, x, y, z);
  const Jet5 wide = term(x, y, z);
  const double f = 0.49 * std::sin(1.3) * std::exp(-0.4);
  const double df_dx = 2.0 * 0.7 * std::sin(1.3) * std::exp(-0.4), df_dy = 0.49 * std::cos(1.3) * std::exp(-0.4),
               df_dz = f;
  EXPECT_DOUBLE_EQ(narrow.a, f);
  for (int slot = 0; slot < 5; ++slot) {
    const double expected = df_dx * x.v[slot] + df_dy * y.v[slot] + df_dz * z.v[slot];
    EXPECT_NEAR(narrow.v[slot], expected, 1e-14) << "slot " << slot;
    EXPECT_NEAR(wide.v[slot], expected, 1e-14) << "slot " << slot;
  }
  // Two parameters, and one.
  const Jet5 two = of_two_parameters(x, y, [](const auto& a, const auto& b) { return a / b; });
  EXPECT_NEAR(two.v[2], 2.0 / 1.3 - 0.7 / (1.3 * 1.3) * -1.0, 1e-14);
  const Jet5 one = of_one_parameter(z, [](const auto& a) { return a * a * a; });
  EXPECT_NEAR(one.v[4], 3.0 * 0.16 * 3.0, 1e-14);
  EXPECT_EQ(one.v[0], 0.0);
}

// A function returning several values (terms sharing their steps): each comes back as the one-value
// form would give it, for Jets and for doubles.
TEST(OfParameters, CarriesEachOfSeveralValuesThroughTheChainRule) {
  Jet5 x(0.7), y(1.3);
  x.v << 1.0, 0.0, 2.0, 0.0, 0.5;
  y.v << 0.0, 1.0, -1.0, 4.0, 0.0;
  const auto ratio_and_product = [](const auto& a, const auto& b) {
    using R = std::decay_t<decltype(a)>;
    return std::array<R, 2>{a / b, a * b};
  };
  const auto [ratio, product] = of_parameters(ratio_and_product, x, y);
  const Jet5 wide_ratio = x / y, wide_product = x * y;
  EXPECT_DOUBLE_EQ(ratio.a, 0.7 / 1.3);
  EXPECT_DOUBLE_EQ(product.a, 0.7 * 1.3);
  for (int slot = 0; slot < 5; ++slot) {
    // ∂(a/b) = ∂a/b − a·∂b/b², ∂(ab) = b·∂a + a·∂b, by hand at a = 0.7, b = 1.3.
    EXPECT_NEAR(ratio.v[slot], x.v[slot] / 1.3 - 0.7 * y.v[slot] / (1.3 * 1.3), 1e-14) << "slot " << slot;
    EXPECT_NEAR(product.v[slot], 1.3 * x.v[slot] + 0.7 * y.v[slot], 1e-14) << "slot " << slot;
    EXPECT_NEAR(ratio.v[slot], wide_ratio.v[slot], 1e-14);
    EXPECT_NEAR(product.v[slot], wide_product.v[slot], 1e-14);
  }
  const auto [plain_ratio, plain_product] = of_parameters(ratio_and_product, 0.7, 1.3);
  EXPECT_DOUBLE_EQ(plain_ratio, 0.7 / 1.3);
  EXPECT_DOUBLE_EQ(plain_product, 0.7 * 1.3);
}

// The base under a layer, on Jets of the base's slots only: three values that differentiate by the
// first two of five slots give the same numbers as on the five, to the bit, and the layer's slots
// come back 0; a value that also differentiates by a later slot makes it run on all five.
TEST(OnLeadingSlots, RunsOnTheSlotsTheValuesUseAndGivesTheSameNumbers) {
  std::array<Jet5, 3> values{Jet5(0.7), Jet5(1.3), Jet5(-0.4)};
  values[0].v << 1.0, 0.0, 0.0, 0.0, 0.0;
  values[1].v << 0.0, 1.0, 0.0, 0.0, 0.0;
  values[2].v << 0.5, -2.0, 0.0, 0.0, 0.0;
  int narrow_calls = 0, wide_calls = 0;
  const auto base = [&](const auto* q) {
    using J = std::decay_t<decltype(q[0])>;
    if constexpr (!std::is_same_v<J, double>) (J::DIMENSION == 2 ? narrow_calls : wide_calls) += 1;
    return Rgb<J>(term(q[0], q[1], q[2]), q[0] / q[1], q[2] * q[2] * q[0]);
  };
  const Rgb<Jet5> narrow = on_leading_slots<2, 3>(base, values.data());
  const Rgb<Jet5> wide = base(values.data());
  EXPECT_EQ(narrow_calls, 1);
  for (int c = 0; c < 3; ++c) EXPECT_TRUE(same_bits(narrow[c], wide[c])) << "channel " << c;
  // By hand: ∂(a/b)/∂slot 1 = −a/b² (b is slot 1's value).
  EXPECT_DOUBLE_EQ(narrow[1].v[1], -0.7 / (1.3 * 1.3));
  EXPECT_EQ(narrow[0].v[4], 0.0);

  values[2].v[3] = 1.0;  // the third value now differentiates by slot 3 too
  narrow_calls = wide_calls = 0;
  const Rgb<Jet5> all_slots = on_leading_slots<2, 3>(base, values.data());
  EXPECT_EQ(narrow_calls, 0);
  EXPECT_EQ(wide_calls, 1);
  EXPECT_NEAR(all_slots[2].v[3], 2.0 * -0.4 * 0.7, 1e-15);  // ∂(c²a)/∂c · 1
  // Doubles: the term itself.
  const double plain[3] = {0.7, 1.3, -0.4};
  const Rgb<double> plain_terms = on_leading_slots<2, 3>(base, plain);
  EXPECT_DOUBLE_EQ(plain_terms[1], 0.7 / 1.3);
}

// A term of the parameters alone is computed once for as long as its keys stay the same, to the
// bit and derivatives included, and again as soon as one changes.
// A layer's weight that is 0 with no derivative: a double 0, or a Jet that is a constant 0. A Jet
// that differentiates by it, or whose value is tiny but not 0, is not.
TEST(ConstantZero, IsZeroWithNoDerivative) {
  EXPECT_TRUE(constant_zero(0.0));
  EXPECT_TRUE(constant_zero(-0.0));
  EXPECT_FALSE(constant_zero(1e-300));
  EXPECT_TRUE(constant_zero(Jet5(0.0)));
  EXPECT_FALSE(constant_zero(Jet5(0.0, 4)));  // the weight itself, differentiated by
  EXPECT_FALSE(constant_zero(Jet5(1e-300)));
  Jet5 through_another = Jet5(0.0);
  through_another.v[2] = -1e-300;  // 0 here, but it moves with another value
  EXPECT_FALSE(constant_zero(through_another));
}

TEST(OncePerParameters, ComputesAgainOnlyWhenAKeyChanges) {
  int computed = 0;
  const auto scaled = [&computed](double a, double b) {
    ++computed;
    return std::array<double, 2>{a * b, a + b};
  };
  auto read = [&](double a, double b) { return once_per_parameters(scaled, a, b); };
  EXPECT_EQ(read(0.3, 1.7)[0], 0.3 * 1.7);
  EXPECT_EQ(read(0.3, 1.7)[1], 0.3 + 1.7);
  EXPECT_EQ(computed, 1);
  EXPECT_EQ(read(0.3, 1.8)[0], 0.3 * 1.8);  // the second key changed
  EXPECT_EQ(computed, 2);
  EXPECT_EQ(read(0.0, 1.8)[1], 1.8);
  EXPECT_EQ(read(-0.0, 1.8)[1], 1.8);  // -0.0 == 0.0, but 1/x tells them apart: computed again
  EXPECT_EQ(computed, 4);

  // Jets: the same value with other derivatives is another key.
  int jets_computed = 0;
  const auto square = [&jets_computed](const Jet5& x) {
    ++jets_computed;
    return Jet5(x * x);
  };
  Jet5 x(0.7, 1), y(0.7, 3);
  EXPECT_EQ(once_per_parameters(square, x).v[1], 1.4);
  EXPECT_EQ(once_per_parameters(square, x).v[1], 1.4);
  EXPECT_EQ(jets_computed, 1);
  EXPECT_EQ(once_per_parameters(square, y).v[3], 1.4);
  EXPECT_EQ(once_per_parameters(square, y).v[1], 0.0);
  EXPECT_EQ(jets_computed, 2);
}

// Each thread keeps its own: a pass on another thread at other parameters does not change what
// this one reads.
TEST(OncePerParameters, KeepsOneTermPerThread) {
  const auto doubled = [](double a) { return 2.0 * a; };
  auto read = [&](double a) -> const double& { return once_per_parameters(doubled, a); };
  const double* here = &read(1.5);
  double there = 0.0;
  std::thread other([&] { there = read(4.0); });
  other.join();
  EXPECT_EQ(there, 8.0);
  EXPECT_EQ(*here, 3.0);
  EXPECT_EQ(&read(1.5), here);
}

}  // namespace
}  // namespace brdffit
