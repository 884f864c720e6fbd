// The list of models and their lookup by name (registry.h). Adding a model: write
// include/brdffit/models/<name>.h and add one line in all_models().
#include "brdffit/registry.h"

#include <algorithm>
#include <map>
#include <mutex>
#include <sstream>

#include "brdffit/error.h"
#include "brdffit/model_adapter.h"
#include "brdffit/models/ashikhmin_shirley.h"
#include "brdffit/models/ashikhmin_shirley_aniso.h"
#include "brdffit/models/banded.h"
#include "brdffit/models/beckmann.h"
#include "brdffit/models/blinn_phong.h"
#include "brdffit/models/cook_torrance.h"
#include "brdffit/models/gaussian.h"
#include "brdffit/models/ggx.h"
#include "brdffit/models/ggx_aniso.h"
#include "brdffit/models/gltf.h"
#include "brdffit/models/gltf_anisotropy.h"
#include "brdffit/models/gltf_clearcoat.h"
#include "brdffit/models/gltf_sheen.h"
#include "brdffit/models/gltf_specular.h"
#include "brdffit/models/half_lambert.h"
#include "brdffit/models/lafortune.h"
#include "brdffit/models/lambert.h"
#include "brdffit/models/low_ashikhmin_shirley.h"
#include "brdffit/models/low_cook_torrance.h"
#include "brdffit/models/low_microfacet.h"
#include "brdffit/models/low_smooth.h"
#include "brdffit/models/minnaert.h"
#include "brdffit/models/mitsuba_principled.h"
#include "brdffit/models/openpbr.h"
#include "brdffit/models/openpbr_layers.h"
#include "brdffit/models/oren_nayar.h"
#include "brdffit/models/phong.h"
#include "brdffit/models/principled.h"
#include "brdffit/models/sgd.h"
#include "brdffit/models/toon.h"
#include "brdffit/models/ward.h"
#include "brdffit/models/ward_aniso.h"
#include "brdffit/models/wrap.h"
#include "brdffit/names.h"
#include "brdffit/two_lobes.h"

namespace brdffit {

namespace {
template <class M>
void add(std::vector<std::unique_ptr<Model>>& models) {
  models.push_back(std::make_unique<ModelAdapter<M>>());
}
}  // namespace

const std::vector<std::unique_ptr<Model>>& all_models() {
  static const std::vector<std::unique_ptr<Model>> models = [] {
    std::vector<std::unique_ptr<Model>> list;
    // From the seeds (shared/seeds): one line per model, in the order users meet them.
    add<models::Lambert>(list);
    add<models::HalfLambert>(list);
    add<models::Wrap>(list);
    add<models::Phong>(list);
    add<models::BlinnPhong>(list);
    add<models::Banded>(list);
    add<models::Minnaert>(list);
    add<models::OrenNayar>(list);
    add<models::Gaussian>(list);
    add<models::Beckmann>(list);
    add<models::Ggx>(list);
    add<models::Toon>(list);
    // From the literature (Ngan et al. 2005 conventions).
    add<models::CookTorrance>(list);
    add<models::Ward>(list);
    add<models::AshikhminShirley>(list);
    add<models::Lafortune>(list);
    // Löw 2012 and Bagher 2012 (BBM conventions: published fits plug in unchanged).
    add<models::LowSmooth>(list);
    add<models::LowMicrofacet>(list);
    add<models::LowCookTorrance>(list);
    add<models::LowAshikhminShirley>(list);
    add<models::Sgd>(list);
    // Renderer materials: the BRDFs of glTF, OpenPBR and the Disney principled shader.
    add<models::Gltf>(list);
    add<models::GltfSpecular>(list);
    add<models::GltfClearcoat>(list);
    add<models::GltfSheen>(list);
    add<models::GltfClearcoatSheen>(list);
    add<models::GltfAnisotropy>(list);
    add<models::OpenPbr>(list);
    add<models::OpenPbrCoat>(list);
    add<models::OpenPbrFuzz>(list);
    add<models::OpenPbrCoatFuzz>(list);
    add<models::Principled>(list);
    add<models::MitsubaPrincipled>(list);
    // Anisotropic (brushed metals, satins): each with its tangent frame's rotation phi0.
    add<models::GgxAniso>(list);
    add<models::WardAniso>(list);
    add<models::AshikhminShirleyAniso>(list);
    return list;
  }();
  return models;
}

namespace {
const Model* find_registered(const std::string& name) {
  for (const auto& m : all_models())
    if (m->name() == name) return m.get();
  return nullptr;
}

// "FIRST+SECOND": built on first use and kept for the program's lifetime (callers hold
// pointers), so each pair is built once.
const Model* find_two_lobes(const std::string& name) {
  const size_t plus = name.find(kLobeSeparator);
  const Model* first = find_registered(name.substr(0, plus));
  const Model* second = find_registered(name.substr(plus + 1));
  if (!first || !second) return nullptr;
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<Model>> built;
  const std::lock_guard<std::mutex> lock(mutex);
  std::unique_ptr<Model>& model = built[name];
  if (!model) model = make_two_lobes(*first, *second);
  return model.get();
}

// Former names still accepted, and the model each now is.
constexpr std::pair<const char*, const char*> kAliases[] = {{"gltf-clearcoat", "gltf+clearcoat"}};

// The renderer materials whose layers (extensions) are models of their own: BASE+E1+E2... with the
// extensions in the order they are registered in (the order of `extensions` here).
struct LayeredFamily {
  const char* base;
  std::vector<const char*> extensions;
};
const std::vector<LayeredFamily>& layered_families() {
  static const std::vector<LayeredFamily> families = {{"gltf", {"clearcoat", "sheen", "anisotropy"}},
                                                      {"openpbr", {"coat", "fuzz"}}};
  return families;
}

// The family whose BASE+ begins `name`, or null.
const LayeredFamily* layered_family_of(const std::string& name) {
  for (const LayeredFamily& family : layered_families())
    if (name.rfind(std::string(family.base) + kLobeSeparator, 0) == 0) return &family;
  return nullptr;
}

// "BASE+E1+E2...": the extensions in any order (each once) name the model that registers them in
// the family's order; "" when the name is no such list.
std::string layered_name(const LayeredFamily& family, const std::string& name) {
  std::vector<std::string> given;
  std::stringstream stream(name.substr(std::string(family.base).size() + 1));
  for (std::string part; std::getline(stream, part, kLobeSeparator);) given.push_back(part);
  std::string canonical = family.base;
  size_t found = 0;
  for (const char* extension : family.extensions) {
    const auto count = std::count(given.begin(), given.end(), extension);
    if (count > 1) return "";
    if (count == 1) canonical += kLobeSeparator + std::string(extension), ++found;
  }
  return found == given.size() ? canonical : "";
}

// The family's extensions and its models for a message: "clearcoat, sheen (gltf+clearcoat, ...)".
std::string family_extensions(const LayeredFamily& family) {
  std::string extensions, models;
  for (const auto& m : all_models())
    if (layered_family_of(m->name()) == &family) models += (models.empty() ? "" : ", ") + m->name();
  for (const char* extension : family.extensions)
    extensions += (extensions.empty() ? "" : ", ") + std::string(extension);
  return extensions + " (" + models + ")";
}
}  // namespace

const Model* find_model(const std::string& name) {
  // A registered name first: gltf+clearcoat, gltf+sheen are models, not two lobes.
  if (const Model* m = find_registered(name)) return m;
  for (const auto& [alias, model] : kAliases)
    if (name == alias) return find_registered(model);
  if (const LayeredFamily* family = layered_family_of(name)) {
    // A list of the family's layers that no model combines (gltf+clearcoat+anisotropy) is refused as a bad one.
    if (const std::string canonical = layered_name(*family, name); !canonical.empty())
      if (const Model* m = find_registered(canonical)) return m;
    fail("model {}: {}'s layers are asked as {}+LAYER, each at most once, in any order, from: {}", name, family->base,
         family->base, family_extensions(*family));
  }
  if (name.find(kLobeSeparator) != std::string::npos) {
    return find_two_lobes(name);
  }
  return nullptr;
}

std::string model_names() {
  std::string names;
  for (const auto& m : all_models()) names += (names.empty() ? "" : ", ") + m->name();
  return names;
}

namespace {
// The name `typed` (one model or FIRST+SECOND) most likely meant, or "" (names.h).
std::string closest_model_name(const std::string& typed) {
  std::vector<std::string> known{"all"};
  for (const auto& m : all_models()) known.push_back(m->name());
  const size_t plus = typed.find(kLobeSeparator);
  if (plus != std::string::npos) {
    if (const std::string registered = closest_name(typed, known); !registered.empty())
      return registered;  // gltf+sheen
    const std::string first = closest_model_name(typed.substr(0, plus)),
                      second = closest_model_name(typed.substr(plus + 1));
    return first.empty() || second.empty() ? "" : first + kLobeSeparator + second;
  }
  return closest_name(typed, known);
}
}  // namespace

std::vector<const Model*> parse_model_list(const std::string& list) {
  std::vector<const Model*> models;
  if (list == "all") {
    for (const auto& m : all_models()) models.push_back(m.get());
    return models;
  }
  std::vector<std::string> names;
  std::stringstream stream(list);
  for (std::string name; std::getline(stream, name, ',');)
    if (!name.empty()) names.push_back(name);
  for (const std::string& name : names) {
    const Model* m = nullptr;
    try {
      m = find_model(name);
    } catch (const Error& e) {  // FIRST+SECOND whose parts are no lobes over Lambert
      throw UsageError(fmt::format("--models: {}", e.what()));
    }
    if (!m) {
      // The whole list respelled, so that one typo among several names is fixed in one go.
      std::string respelled;
      for (const std::string& n : names) {
        const std::string closest = closest_model_name(n);
        respelled += (respelled.empty() ? "" : ",") + (closest.empty() ? n : closest);
      }
      const bool known = closest_model_name(name).size() > 0;
      fail_usage(
          "--models: unknown model '{}'{} (known: {}; two lobes over one Lambert base: FIRST+SECOND, e.g. "
          "ggx+ggx; a renderer material's layers in any order: gltf+clearcoat+sheen, openpbr+coat+fuzz)",
          name, known ? "; did you mean -m " + respelled + "?" : "", model_names());
    }
    if (std::find(models.begin(), models.end(), m) == models.end()) models.push_back(m);
  }
  if (models.empty()) fail_usage("--models: no model named");
  return models;
}

}  // namespace brdffit
