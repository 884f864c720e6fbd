// The list of models. Adding a model: write include/brdffit/models/<name>.h and add one line here.
#include "brdffit/model_adapter.h"
#include "brdffit/models/ggx.h"
#include "brdffit/models/lambert.h"

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
    add<models::Ggx>(list);
    // From the literature (Ngan et al. 2005 conventions).
    return list;
  }();
  return models;
}

}  // namespace brdffit
