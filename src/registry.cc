// The list of models. Adding a model: write include/brdffit/models/<name>.h and add one line here.
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
#include "brdffit/models/gltf_clearcoat.h"
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
#include "brdffit/models/oren_nayar.h"
#include "brdffit/models/phong.h"
#include "brdffit/models/principled.h"
#include "brdffit/models/sgd.h"
#include "brdffit/models/toon.h"
#include "brdffit/models/ward.h"
#include "brdffit/models/ward_aniso.h"
#include "brdffit/models/wrap.h"

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
    add<models::OpenPbr>(list);
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

}  // namespace brdffit
