// The model interface every part of brdffit uses (CLI, fitter, renderer); the list of models and
// their lookup by name are in registry.h.
//
// A model is written once as a small struct with a static templated evaluation (see
// models/lambert.h for the pattern); ModelAdapter<M> (model_adapter.h) turns it into a Model.
// Parameter values are passed flattened, in the order of parameters(), colours taking three
// consecutive values (R, G, B).
//
// Convention, for every model: shade() is the shaded value f(l,v)·max(n·l,0) in the local
// frame n = (0,0,1), for unit l and v; stylised models return the shader expression of their
// seed without the light colour. brdf() is f itself (1/sr) where the model has one.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "brdffit/math.h"
#include "brdffit/param.h"

namespace brdffit {

// How a simpler model sits inside a model: the values of the outer model that describe the
// inner one. The fitter fits the inner model first and starts the outer one from its optimum
// mapped this way, and selects on all samples, so an exact nesting's error is never above the
// inner model's. Values: copied from the inner model's (optionally transformed), or fixed; every
// other value at the outer model's default.
struct Nesting {
  struct Copy {
    std::string to, from;                   // outer and inner parameter names
    double (*transform)(double) = nullptr;  // inner value -> outer value; nullptr: unchanged
  };
  std::string inner;  // the contained model's name
  std::vector<Copy> copies;
  std::vector<std::pair<std::string, double>> fixed;  // outer parameter = value (every channel)
  // true: the mapped values reproduce the inner model's shaded values exactly (the guarantee
  // holds); false: only approximately (a good start, no guarantee).
  bool exact = true;
  std::string why;  // one line for users: what is switched off or mapped
};

// What a fit recovers from a table of the model's own values: facts declared with the model (its
// struct's optional recovery_facts()) and checked by the tests of parameter recovery
// (tests/test_fit.cc), so that a new model brings its own. Empty: every value is recovered from
// a material in the middle of every range.
struct RecoveryFacts {
  // "NAME=VALUE" assignments (parameter_values) for that material where the middle of a range
  // is none a fit could recover (a near-mirror that random directions rarely see).
  std::vector<std::string> material = {};
  // Parameters a table does not determine one by one: a fit flags them not identifiable.
  std::vector<std::string> not_identifiable = {};
  // Values that trade off (another basin of almost equal cost): a fit reproduces the material's
  // reflectance rather than its values. Bounds of the fit's relative error on fresh noise-free
  // directions, and of its error over the material's own on the fitted samples.
  struct TradeOff {
    double max_relative_error;
    double max_error_over_truth;
  };
  std::optional<TradeOff> trade_off = {};
};

class Model {
 public:
  virtual ~Model() = default;

  virtual const std::string& name() const = 0;
  virtual const std::string& summary() const = 0;  // one line: formula and source
  virtual const std::vector<ParamSpec>& parameters() const = 0;
  // Physically based: f exists, reciprocal unless its specification is not (gltf-clearcoat: its header).
  virtual bool has_brdf() const = 0;
  // Every lobe is normalised: inside the bounds each linear parameter's term alone (and what
  // remains with all of them at 0, e.g. Schlick's grazing Fresnel) has directional albedo <= 1.
  // The terms are not coupled, so their sum can exceed 1 (albedo 1 plus a lobe).
  virtual bool energy_conserving() const = 0;

  virtual Rgb<double> shade(const double* values, const Vec3& l, const Vec3& v) const = 0;
  virtual std::optional<Rgb<double>> brdf(const double* values, const Vec3& l, const Vec3& v) const = 0;

  // Shade with Ceres' automatic derivatives with respect to every flattened value:
  // jacobian is 3 x num_values(), row-major. Used by tests and diagnostics, and by the fitter
  // for a model that brings no batch cost of its own (fit_residual.h).
  virtual Rgb<double> shade_with_jacobian(const double* values, const Vec3& l, const Vec3& v,
                                          double* jacobian) const = 0;

  // The shaded value split along the linear parameters (ParamSpec::linear), in which it is affine
  // channel by channel: returns the value with those parameters at 0, whatever `values` holds
  // there, and writes to basis[j] its change per unit of the j-th linear parameter (in the order
  // of parameters()), so that shade = base + Σ_j x_j·basis[j]. Variable projection's pass over
  // the samples (variable_projection.h). This default evaluates shade() once per linear
  // parameter and once more; registered models do it in one evaluation (model_adapter.h).
  virtual Rgb<double> shade_linear_parts(const double* values, const Vec3& l, const Vec3& v, Rgb<double>* basis) const;

  // The simpler models this one contains (see Nesting); empty for none.
  virtual const std::vector<Nesting>& nestings() const;
  // f = albedo/π + a lobe that does not depend on albedo, albedo the first parameter (a colour):
  // the models written as models::OverLambert (models/over_lambert.h), which two-lobe composites
  // (two_lobes.h) combine.
  virtual bool is_lobe_over_lambert() const { return false; }
  virtual const RecoveryFacts& recovery_facts() const;

  int num_values() const { return flattened_size(parameters()); }
  std::vector<double> default_values() const;
  // Offset of the named parameter in the flattened values, or -1.
  int offset_of(const std::string& param_name) const;
  const ParamSpec* find_parameter(const std::string& param_name) const;
};

// The outer model's values that describe `inner` with `inner_values` under `nesting`.
std::vector<double> embed_values(const Model& outer, const Nesting& nesting, const Model& inner,
                                 const std::vector<double>& inner_values);

// The model's isotropic form: its exact nesting that holds only the lobe's orientation and
// anisotropy (Role::Orientation, Role::Anisotropy) and copies every other parameter from the
// contained isotropic model (ggx-aniso's ggx, α_x = α_y = roughness²; gltf+anisotropy's gltf,
// anisotropyStrength 0). The fitter fits that form in the model's place on isotropic data.
// nullptr when the model has no orientation or declares no such nesting.
const Nesting* isotropic_form(const Model& model);

// What holds a model's lobe isotropic where it has no isotropic form (principled, whose isotropic
// lobe is no other model): every Role::Anisotropy parameter at 0 and every Role::Orientation one
// at its default (an isotropic lobe is the same turned any way). The fitter holds them so on
// isotropic data. Empty when the model has no Role::Anisotropy parameter.
std::vector<std::pair<std::string, double>> isotropic_holds(const Model& model);

// The shaded value of a fitted model: one value vector, or one per channel (FitResult's
// channel_values) when that is non-empty.
Rgb<double> shade_fitted(const Model& model, const std::vector<double>& values,
                         const std::vector<std::vector<double>>& per_channel_values, const Vec3& l, const Vec3& v);

}  // namespace brdffit

namespace brdffit {

// Applies "NAME=VALUE" assignments (VALUE one number, or R,G,B for colours) on top of the
// model's defaults. Throws Error for an unknown parameter, a malformed or non-finite value, a
// wrong number of components or a value outside the parameter's bounds.
std::vector<double> parameter_values(const Model& model, const std::vector<std::string>& assignments);

// The one check of given parameter values, wherever they come from (--param, a published .fit
// file): throws Error starting with `where` unless x is a number within the parameter's bounds
// (NaN never is) and whole for an integer parameter. Values fitted elsewhere are checked only
// against the lower bound (AtLeastLower), below which the models are undefined (a width of 0
// or below, a negative colour): published fits lie beyond the upper bounds, which bound the
// search, not the model (Bagher's SGD f0 up to 8, Low's eta near 100). The second checks a
// model's whole vector.
enum class BoundsCheck { Both, AtLeastLower };
void check_parameter_value(const ParamSpec& spec, double x, const std::string& where,
                           BoundsCheck bounds = BoundsCheck::Both);
void check_parameter_values(const Model& model, const std::vector<double>& values, const std::string& where,
                            BoundsCheck bounds = BoundsCheck::Both);

// Parses "x,y,z" into a vector; throws Error naming `what` when malformed or non-finite.
Vec3 parse_vec3(const std::string& text, const std::string& what);

}  // namespace brdffit
