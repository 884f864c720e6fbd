// Small math shared by every model: directions in the local shading frame, where the surface
// normal is n = (0,0,1), and scalar helpers that work for double and ceres::Jet alike.
//
// Directions (light l, view v) are always plain doubles: only model parameters are
// differentiated, so geometry never pays for automatic differentiation.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <tuple>
#include <type_traits>
#include <utility>

namespace brdffit {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInvPi = 1.0 / kPi;

using Vec3 = Eigen::Vector3d;
template <class T>
using Rgb = Eigen::Matrix<T, 3, 1>;

// Unit half vector of two unit directions; +z when they are opposite.
inline Vec3 half_vector(const Vec3& l, const Vec3& v) {
  Vec3 h = l + v;
  const double len = h.norm();
  return len > 0.0 ? Vec3(h / len) : Vec3(0.0, 0.0, 1.0);
}

// Mirror direction of l about the normal (0,0,1): reflect(-l, n) in shader notation.
inline Vec3 reflect_about_normal(const Vec3& l) { return Vec3(-l.x(), -l.y(), l.z()); }

// The plain value of a scalar: itself for double, the value part of a ceres::Jet. For
// quantities that are piecewise constant in a parameter (band indices), whose derivative is 0.
inline double value_of(double x) { return x; }
template <class J>
auto value_of(const J& j) -> decltype(j.a) {
  return j.a;
}

// f(x…) for a function f of a few parameters x…, doubles or ceres::Jets: f runs on Jets of one
// derivative per parameter and the chain rule puts Σ ∂f/∂xᵢ·∂xᵢ back. An expensive term of one or
// two parameters (a lobe of its roughness, a table read at it, a Fresnel of its ior) then costs
// one or two derivatives instead of one per fitted value: a Jet of nine derivatives does nine
// times the work in every step of f. f is called with doubles or with Jets of sizeof…(x)
// derivatives (a generic lambda), and returns one value or a std::array of values (terms that
// share their steps), which come back as the same.
template <class F, class... X, std::enable_if_t<(std::is_same_v<X, double> && ...), int> = 0>
auto of_parameters(F&& f, const X&... x) {
  return f(x...);
}
namespace detail {
template <template <class, int> class Jet, int N, class Narrow, class... X, size_t... I>
Jet<double, N> widened(const Narrow& y, std::index_sequence<I...>, const X&... x) {
  Jet<double, N> out;
  out.a = y.a;
  out.v.setZero();
  ((out.v += y.v[I] * x.v), ...);
  return out;
}
template <template <class, int> class Jet, int N, class F, class... X, size_t... I>
auto on_narrow_jets(F&& f, std::index_sequence<I...> slots, const X&... x) {
  using Narrow = Jet<double, static_cast<int>(sizeof...(X))>;
  const auto y = f(Narrow(x.a, static_cast<int>(I))...);
  if constexpr (std::is_same_v<std::decay_t<decltype(y)>, Narrow>) {
    return widened<Jet, N>(y, slots, x...);
  } else {
    std::array<Jet<double, N>, std::tuple_size_v<std::decay_t<decltype(y)>>> out;
    for (size_t k = 0; k < out.size(); ++k) out[k] = widened<Jet, N>(y[k], slots, x...);
    return out;
  }
}
}  // namespace detail
template <class F, template <class, int> class Jet, int N, class... X>
auto of_parameters(F&& f, const Jet<double, N>& x, const X&... more) {
  return detail::on_narrow_jets<Jet, N>(f, std::index_sequence_for<Jet<double, N>, X...>(), x, more...);
}
template <class T, class F>
T of_one_parameter(const T& x, F&& f) {
  return of_parameters(f, x);
}
template <class T, class F>
T of_two_parameters(const T& x, const T& y, F&& f) {
  return of_parameters(f, x, y);
}

// f(values) for a term of the first `Count` values that a model computes on Jets wider than the
// derivatives those values carry: the base under a layer (openpbr's under its fuzz), whose values
// differentiate by the base's own parameters, the first K slots of a model that declares
// kSeparateChannels (the layers' parameters take the slots after them). Where none of the values
// has a derivative past slot K, f runs on Jets of K derivatives and its Rgb comes back with 0 in
// the other slots: the same numbers to the bit, since a Jet's derivatives are computed slot by
// slot. Otherwise, and on doubles or Jets of K derivatives or fewer, f runs on the values as they
// are. f takes a pointer to the values.
template <int K, int Count, class F>
auto on_leading_slots(F&& f, const double* values) {
  return f(values);
}
template <int K, int Count, class F, template <class, int> class Jet, int N>
Rgb<Jet<double, N>> on_leading_slots(F&& f, const Jet<double, N>* values) {
  if constexpr (N <= K) {
    return f(values);
  } else {
    for (int i = 0; i < Count; ++i)
      if (!values[i].v.template tail<N - K>().isZero(0.0)) return f(values);
    std::array<Jet<double, K>, Count> narrow;
    for (int i = 0; i < Count; ++i) {
      narrow[i].a = values[i].a;
      narrow[i].v = values[i].v.template head<K>();
    }
    const Rgb<Jet<double, K>> y = f(narrow.data());
    Rgb<Jet<double, N>> out;
    for (int c = 0; c < 3; ++c) {
      out[c].a = y[c].a;
      out[c].v.template head<K>() = y[c].v;
      out[c].v.template tail<N - K>().setZero();
    }
    return out;
  }
}

// Whether a and b are the same number with the same derivatives, to the bit (ceres::Jet's ==
// compares the numbers only, and 0.0 == -0.0).
inline bool same_bits(double a, double b) {
  std::uint64_t bits_a, bits_b;  // memcpy, not memcmp: GCC inlines the one, calls libc for the other
  std::memcpy(&bits_a, &a, sizeof a);
  std::memcpy(&bits_b, &b, sizeof b);
  return bits_a == bits_b;
}
template <class J>
bool same_bits(const J& a, const J& b) {
  if (!same_bits(a.a, b.a)) return false;
  for (int i = 0; i < a.v.size(); ++i)
    if (!same_bits(a.v[i], b.v[i])) return false;
  return true;
}

// compute(keys) for a term of the parameters alone (a table's row at a roughness, a lobe's
// normalisation) that a model would otherwise compute again for every sample of a pass over the
// samples, all at the same parameters; or for a term of the parameters and of a direction that
// runs of samples share (sgd's D at one n·h: a MERL table's samples, and its subsets', come in runs
// of one θh), the direction among the keys. Kept per thread and per call site (each `compute` lambda
// is a type of its own), for the keys it was last computed for; the keys compare to the bit, so
// what comes back is what computing would give. `compute` must depend on nothing but its keys;
// the reference holds until the same call site is next reached on this thread.
template <class F, class K, size_t N>
const auto& once_per_parameters(F&& compute, const std::array<K, N>& keys) {
  using Value = std::decay_t<decltype(compute(keys))>;
  struct Memo {
    std::array<K, N> keys;
    std::optional<Value> value;
  };
  thread_local Memo memo;
  bool hit = memo.value.has_value();
  for (size_t i = 0; hit && i < N; ++i) hit = same_bits(memo.keys[i], keys[i]);
  if (!hit) {
    memo.value.emplace(compute(keys));
    memo.keys = keys;
  }
  return *memo.value;
}
// compute(key, more…), the same for a few keys of one type.
template <class F, class K, class... More>
const auto& once_per_parameters(F&& compute, const K& key, const More&... more) {
  static_assert((std::is_same_v<K, More> && ...), "keys of one type");
  using Keys = std::array<K, 1 + sizeof...(More)>;
  return once_per_parameters([&compute](const Keys& keys) { return std::apply(compute, keys); }, Keys{key, more...});
}

// Whether x is 0 and carries no derivative: a double equal to 0, or a Jet whose value and
// derivatives are all 0 (a constant). A layer of such a weight leaves what is under it exactly as it
// is, derivatives included (what it adds is the weight times a finite term, what it multiplies by
// is 1 plus such a term), so it need not be computed: on doubles, and on Jets that differentiate
// by other values only (the linear parts' Jets, which differentiate by a colour). Where the Jets
// differentiate by the weight, its derivatives there are not 0 and the layer is computed.
template <class T>
bool constant_zero(const T& x) {
  if constexpr (std::is_same_v<T, double>) {
    return x == 0.0;
  } else {
    if (x.a != 0.0) return false;
    for (int i = 0; i < x.v.size(); ++i)
      if (x.v[i] != 0.0) return false;
    return true;
  }
}

template <class T>
T abs_value(const T& x) {
  return x < T(0.0) ? T(-x) : x;
}

// Value-type clamps that only compare (Jet comparisons use the value part).
template <class T>
T max0(const T& x) {
  return x > T(0.0) ? x : T(0.0);
}
template <class T>
T saturate(const T& x) {
  return x < T(0.0) ? T(0.0) : (x > T(1.0) ? T(1.0) : x);
}

// x^e for x >= 0: zero for x <= 0 so that neither pow(0, e) nor its derivative
// (log 0 for a differentiated exponent) ever produces NaN.
template <class X, class E>
X pow_pos(const X& x, const E& e) {
  using std::exp;
  using std::log;
  if (!(x > X(0.0))) return X(0.0);
  return exp(e * log(x));
}

// base^e for a base that depends only on the directions (a plain double) and an exponent that
// may be a Jet: the log is taken in double, so a tiny (subnormal) base cannot give the Jet a
// 0·∞ derivative. Zero for base <= 0.
template <class E>
E pow_of_direction_term(double base, const E& e) {
  using std::exp;
  return base > 0.0 ? E(exp(e * std::log(base))) : E(0.0);
}

// Hermite smoothstep as in GLSL/HLSL: 0 below e0, 1 above e1, 3t²-2t³ between.
template <class T, class E>
T smoothstep(const E& e0, const E& e1, const T& x) {
  const T t = saturate(T((x - e0) / (e1 - e0)));
  return t * t * (T(3.0) - T(2.0) * t);
}

// Schlick's approximation of Fresnel reflectance for a cosine between light and half vector.
template <class T>
T schlick_fresnel(const T& f0, double cos_theta) {
  const double m = 1.0 - cos_theta;
  const double m5 = m * m * m * m * m;
  return f0 + (T(1.0) - f0) * m5;
}

inline Vec3 normalized_or_zero(const Vec3& d) {
  const double len = d.norm();
  return len > 0.0 ? Vec3(d / len) : Vec3::Zero();
}

// Luminance of linear RGB with Rec. 709 / sRGB primaries (ITU-R BT.709 weights).
inline double rec709_luminance(const Rgb<double>& rgb) { return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]; }

}  // namespace brdffit
