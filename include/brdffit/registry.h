// The registry: every model brdffit knows, and the lookup of models by the names users type.
// It sits above the models (model.h) and the two-lobe composite: adding a model is a header in
// models/ and one line in src/registry.cc.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "brdffit/model.h"

namespace brdffit {

// Every model brdffit knows, in a stable order.
const std::vector<std::unique_ptr<Model>>& all_models();
// The model with this CLI name, or nullptr. A registered name is taken first (gltf+clearcoat,
// gltf+sheen and gltf+clearcoat+sheen are models; "gltf+" followed by glTF extensions in any order
// names the one that has them, and the former name gltf-clearcoat is gltf+clearcoat). Otherwise
// "FIRST+SECOND" names two lobes over one Lambert base (two_lobes.h), built on first use; throws
// Error when a component is not such a lobe, or for gltf+ with an extension brdffit does not fit.
const Model* find_model(const std::string& name);
// The names of all models, comma separated (for messages).
std::string model_names();

// Parses "a,b,c" or "all" into models; throws UsageError naming an unknown model (with the list
// respelled when every name is near a known one: names.h).
std::vector<const Model*> parse_model_list(const std::string& list);

}  // namespace brdffit
