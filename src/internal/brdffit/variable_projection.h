// Variable projection: a model's linear parameters (albedo, specular, ... : `ParamSpec::linear`)
// solved exactly for fixed shape parameters, so the fitter's grid and coordinate search only
// search the shape parameters and every point they try has its best colours.
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <vector>

#include "brdffit/fit_objective.h"

namespace brdffit {

// The minimiser of xᵀAx − 2bᵀx over the box lower ≤ x ≤ upper, A symmetric positive
// semi-definite, for small n (a model's few linear parameters): every active set is tried, each
// variable free, at its lower or at its upper bound (3ⁿ systems).
Eigen::VectorXd solve_box_quadratic(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, const Eigen::VectorXd& lower,
                                    const Eigen::VectorXd& upper);

// Sets the model's linear parameters in the fitted channels to their weighted least-squares
// optimum within their bounds, the other values held. The prediction is affine in them:
// shade_c = base_c + Σ_j x_jc · basis_jc. For the relative and log metrics each residual is
// weighted by its first-order sensitivity, so the solve matches the metric near the data.
// Returns the objective at the solution, Σ r² as cost_of counts it without a loss, from the
// normal equations (no second pass over the samples); NaN for the log metric (not quadratic in
// the prediction) and for a model without linear parameters. `cost_as_given`, if set, receives
// the objective at the values as they were given, from the same normal equations (NaN where the
// return is): the cost of a candidate and its linear parameters' optimum in one pass.
//
// A solve whose objective is known to pass give_up_above before the last sample is given up, as
// cost_of does: it returns a value above that bound, itself a lower bound of the objective, and
// leaves `values` as given. (Every 256 samples, the objective's minimum over the box on the
// samples summed so far is compared with the bound, for one or two linear parameters.)
double solve_linear(const Model& model, std::vector<double>& values, const std::vector<Sample>& samples, Metric metric,
                    const Channels& channels, double* cost_as_given = nullptr, double give_up_above = HUGE_VAL);

}  // namespace brdffit
