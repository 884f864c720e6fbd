// Pieces shared by the model files: the standard parameters and the Lambert base.
#pragma once

#include "brdffit/math.h"
#include "brdffit/param.h"

namespace brdffit::models {

inline ParamSpec albedo_param(double default_value = 0.5) {
  return {"albedo", 3, 0.0, 1.0, default_value, "diffuse reflectance per channel (directional albedo of the Lambert term)",
          Role::DiffuseColour, /*linear=*/true};
}

inline ParamSpec specular_param(double upper, double default_value, const char* meaning) {
  return {"specular", 3, 0.0, upper, default_value, meaning, Role::SpecularColour, /*linear=*/true};
}

// Lambert BRDF albedo/π of a colour stored at p[0..2].
template <class T>
Rgb<T> lambert_term(const T* albedo) {
  return Rgb<T>(albedo[0] * kInvPi, albedo[1] * kInvPi, albedo[2] * kInvPi);
}

template <class T>
Rgb<T> colour(const T* c) {
  return Rgb<T>(c[0], c[1], c[2]);
}

}  // namespace brdffit::models
