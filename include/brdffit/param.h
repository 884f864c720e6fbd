// Description of one model parameter: what users call it, where it may lie, where fits start,
// and how the fitter should treat it.
#pragma once

#include <string>
#include <vector>

namespace brdffit {

enum class Role {
  DiffuseColour,   // colour of the diffuse (body) term
  SpecularColour,  // colour/scale of the specular lobe
  F0,              // Fresnel reflectance at normal incidence
  Roughness,       // microfacet or surface roughness
  Exponent,        // lobe sharpness exponent (shininess, gloss, n)
  Wrap,            // how far lighting wraps past the terminator
  Orientation,     // rotation of an anisotropic lobe's frame about the normal (meaningless on isotropic data)
  Anisotropy,      // how much an anisotropic lobe's widths differ (0: isotropic, which isotropic data imply)
  Shape,           // any other shape parameter
};

const char* role_name(Role role);

// How multi-start spreads its starting points across the parameter's range.
enum class Spacing { Linear, Log };

struct ParamSpec {
  std::string name;
  int channels = 1;  // 3 for colours (R,G,B), 1 for shared shape parameters
  double lower = 0.0;
  double upper = 1.0;
  double default_value = 0.5;
  std::string meaning;  // one line
  Role role = Role::Shape;
  // True when the shaded value is affine in this parameter jointly with the model's other
  // linear parameters, channel by channel; the fitter then solves it exactly (variable projection).
  bool linear = false;
  bool integer = false;  // searched over its integer range rather than optimised continuously
  Spacing spacing = Spacing::Linear;
  // A parameter whose product with this one is what the data determine (Cook-Torrance's and
  // Ashikhmin-Shirley's specular scale and Schlick f0: away from grazing angles F ≈ f0 and
  // only specular·f0 shows). When this one sits at a bound or is not identifiable, results
  // report the product.
  const char* trades_off_with = nullptr;
  // The linear parameter that this one only scales: the shaded value depends on their product
  // alone (sgd's K and specular, whose published values plug in unchanged). Every point the
  // coordinate search tries has its linear parameters solved exactly, so each value of this one
  // would cost the same: the search leaves it where it starts. Results report the product.
  const char* only_scales = nullptr;
};

// Number of scalar values a parameter list occupies when flattened (colours take three).
int flattened_size(const std::vector<ParamSpec>& params);

}  // namespace brdffit
