// The importance subset: a few thousand samples standing in for a table's million in the
// fitter's early, cheap stages (grid, coordinate search, first refinement).
//
// A measured table's error is dominated by few samples (a specular peak covers few bins with
// large values), which a uniform subset would mostly miss. So samples are drawn with probability
// ∝ weight·(value + error + mean value)² by systematic sampling, and each kept sample's weight
// is divided by its expected count, so that sums over the subset estimate sums over all samples.
// `error` is the current fit's absolute residual per sample where one is known: without it a
// subset drawn where the data are bright never sees where the model is bright and the data are
// not (a narrow grazing spike of a sharp lobe on a matte material), and a stage on it walks into
// that spike.
#pragma once

#include <cstdint>
#include <vector>

#include "brdffit/samples.h"

namespace brdffit {

// About `count` samples (all of them when there are no more), the same for the same seed. A
// sample drawn k times is kept once with k times the weight.
std::vector<Sample> importance_subset(const std::vector<Sample>& samples, size_t count, uint64_t seed,
                                      const std::vector<double>& error = {});

}  // namespace brdffit
