// Evaluation of a model struct for any scalar type (double or ceres::Jet): the one place where
// "shade = f·max(n·l,0)" is derived for models that define a BRDF.
#pragma once

#include <type_traits>

#include "brdffit/math.h"

namespace brdffit {

template <class M, class = void>
struct HasBrdf : std::false_type {};
template <class M>
struct HasBrdf<M, std::void_t<decltype(&M::template brdf<double>)>> : std::true_type {};

// The shaded value of model M for any scalar type T.
template <class M, class T>
Rgb<T> shade_of(const T* p, const Vec3& l, const Vec3& v) {
  if constexpr (HasBrdf<M>::value) {
    if (l.z() <= 0.0) return Rgb<T>(T(0.0), T(0.0), T(0.0));
    return M::brdf(p, l, v) * l.z();
  } else {
    return M::shade(p, l, v);
  }
}

}  // namespace brdffit
