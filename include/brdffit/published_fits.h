// Published per-material fits in the BBM benchmark's text format (bsdfbenchmark/bbm, fits/):
//   material = Aggregate(Lambertian(albedo = [r, g, b]), NganWard(albedo = [..], roughness = 0.1))
// mapped onto brdffit's models, so published parameters can be scored on the same tables.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "brdffit/model.h"

namespace brdffit {

// One model term of a published fit: its BBM name and its parameters (scalars have one value).
struct PublishedTerm {
  std::string model;
  std::map<std::string, std::vector<double>> parameters;
};

// Every material of a .fit file with its terms. Throws Error naming the file and line when a
// line is malformed.
std::map<std::string, std::vector<PublishedTerm>> read_published_fits(const std::string& path);

// The flattened values of `model` for a published fit (a Lambertian term plus one of Ngan's
// NganCookTorrance, NganWard, NganAshikhminShirley, NganLafortune), or nullopt when the terms
// are not that model's. The mapping is written in each model's header.
std::optional<std::vector<double>> to_model_values(const Model& model, const std::vector<PublishedTerm>& terms);

}  // namespace brdffit
