// `brdffit models` lists the model library; `brdffit eval` evaluates one model at one pair of
// directions.
#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "brdffit/error.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"
#include "brdffit/result_json.h"
#include "cli_common.h"
#include "commands.h"

namespace brdffit::cli {

namespace {

nlohmann::json model_json(const Model& model) {
  nlohmann::json params = nlohmann::json::array();
  for (const ParamSpec& p : model.parameters())
    params.push_back({{"name", p.name},
                      {"channels", p.channels},
                      {"lower", p.lower},
                      {"upper", p.upper},
                      {"default", p.default_value},
                      {"meaning", p.meaning},
                      {"role", role_name(p.role)},
                      {"integer", p.integer}});
  return {{"model", model.name()},
          {"summary", model.summary()},
          {"brdf", model.has_brdf()},
          {"energy_conserving", model.energy_conserving()},
          {"parameters", params}};
}

void print_models(bool json) {
  if (json) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& m : all_models()) list.push_back(model_json(*m));
    say("{}\n", json_text(list, 2));
    return;
  }
  for (const auto& m : all_models()) {
    say("{:<18} {}\n", m->name(), m->summary());
    for (const ParamSpec& p : m->parameters())
      say("    {:<14} {:<5} [{:g}, {:g}] default {:g}  {}\n", p.name,
          p.channels == 3 ? "rgb" : (p.integer ? "int" : ""), p.lower, p.upper, p.default_value, p.meaning);
  }
  say("\nTwo specular lobes over one Lambert base: FIRST+SECOND (e.g. -m ggx+ggx, cook-torrance+cook-torrance,\n"
      "ggx+beckmann) with any two models above that are a lobe over albedo/π. The second lobe's parameters\n"
      "take the suffix _2 (roughness_2); a weight_2 scales it when its own scale cannot switch it off.\n"
      "`brdffit eval -m ggx+ggx --param roughness_2=0.1 ...` works as for any model. 'all' is the list above.\n"
      "A renderer material's layers may be named in any order: gltf+sheen+clearcoat is gltf+clearcoat+sheen,\n"
      "openpbr+fuzz+coat is openpbr+coat+fuzz.\n");
}

struct EvalArgs {
  std::string model;
  std::vector<std::string> params;
  std::string light, view;
  bool json = false;
};

void run_eval(const EvalArgs& args) {
  const Model* model = &named_model(args.model, "eval");
  const std::vector<double> values = option_value([&] { return parameter_values(*model, args.params); });
  const Vec3 l = normalized_or_zero(option_value([&] { return parse_vec3(args.light, "--light"); }));
  const Vec3 v = normalized_or_zero(option_value([&] { return parse_vec3(args.view, "--view"); }));
  if (l.isZero() || v.isZero()) fail_usage("--light and --view must be non-zero directions");
  const Rgb<double> shade = model->shade(values.data(), l, v);
  const std::optional<Rgb<double>> brdf = model->brdf(values.data(), l, v);
  if (args.json) {
    nlohmann::json out = {{"model", model->name()}, {"shade", {shade[0], shade[1], shade[2]}}, {"brdf", nullptr}};
    if (brdf) out["brdf"] = {(*brdf)[0], (*brdf)[1], (*brdf)[2]};
    say("{}\n", json_text(out));
    return;
  }
  say("shade {:.9g} {:.9g} {:.9g}\n", shade[0], shade[1], shade[2]);
  if (brdf) say("brdf  {:.9g} {:.9g} {:.9g}\n", (*brdf)[0], (*brdf)[1], (*brdf)[2]);
}

}  // namespace

void add_models_commands(CLI::App& app) {
  auto json = std::make_shared<bool>(false);
  CLI::App* models = app.add_subcommand("models", "List the models and their parameters");
  models->add_flag("--json", *json, "Print JSON");
  models->callback([json] { print_models(*json); });

  auto args = std::make_shared<EvalArgs>();
  CLI::App* eval = app.add_subcommand("eval", "Evaluate a model's shaded value f·max(n·l,0) at one light/view pair");
  add_models_option(eval, args->model, "The model");
  add_positional_model(eval, args->model);
  eval->add_option("--param", args->params, "NAME=VALUE (colours: one value or R,G,B); repeatable");
  eval->add_option("--light", args->light, "Light direction X,Y,Z (normal is +z)")->required();
  eval->add_option("--view", args->view, "View direction X,Y,Z")->required();
  eval->add_flag("--json", args->json, "Print JSON");
  eval->callback([args] { run_eval(*args); });
}

}  // namespace brdffit::cli
