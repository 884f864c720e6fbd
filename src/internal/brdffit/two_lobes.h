// Two specular lobes over one Lambert base, composed at run time from any two registered
// models that are a lobe over the Lambert base albedo/π (Model::is_lobe_over_lambert: ggx,
// cook-torrance, beckmann, ward, ashikhmin-shirley, the anisotropic ones, ...). Users ask for
// "FIRST+SECOND", e.g. ggx+ggx.
//
//   f = albedo/π + lobe₁(values₁) + w · lobe₂(values₂)        (per colour channel)
//
// where lobeₖ is the component's f with its albedo at 0. Parameters: the shared albedo, the
// first component's other parameters under their own names, then the second's with the
// suffix "_2" (roughness_2, f0_2, ...). The second lobe needs a scale that switches it off so
// the composite contains the first model exactly (Nesting): its own `specular` where that
// scale at 0 makes the lobe vanish (cook-torrance, ward, beckmann, ...). Otherwise (ggx, whose
// Schlick F leaves (1-l·h)^5 at f0 = 0) the composite adds w = weight_2, a colour in [0, 1],
// and stores the lobe's linear values multiplied by w, so that every one stays linear: for
// ggx, f0_2 = w·f0 and the second lobe's Schlick F runs from f0_2 at normal incidence to
// weight_2 at grazing incidence (Schlick with a separate F90), both in [0, 1]. Without
// weight_2, w = 1.
//
// Nestings: FIRST with the second lobe's scale at 0 (exact), and lambert with both lobes'
// scales at 0 (exact when the first lobe's scale switches it off).
// Derivatives come from the components' automatic differentiation (Model::shade_with_jacobian)
// and the fitter receives a JacobianBatchCost (fit_residual.h).
#pragma once

#include <memory>
#include <string>

#include "brdffit/model.h"

namespace brdffit {

// The separator of the two components in a two-lobe model's name.
constexpr char kLobeSeparator = '+';

// The composite of two lobe models. Throws Error when a component is not a lobe over the
// Lambert base albedo/π, or has more values than the composite supports (sgd's 33).
std::unique_ptr<Model> make_two_lobes(const Model& first, const Model& second);

}  // namespace brdffit
