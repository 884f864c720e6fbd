// Renderer materials converted into one another: through the metallic-roughness core, or
// parameter by parameter where the target nests the source (material_export.h,
// material_convert.h).
#include "brdffit/material_convert.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/material_export.h"
#include "brdffit/registry.h"

namespace brdffit {

namespace {

constexpr double kDielectricF0 = 0.04;                   // glTF's (IOR 1.5)
constexpr double kDiffuseThrough = 1.0 - kDielectricF0;  // the light the dielectric coat lets through

// The metallic value that matches a single (luminance) albedo a and f0 f; see material_export.h.
double solve_metallic(double a, double f) {
  const double qa = kDielectricF0 * kDiffuseThrough, qb = -(a + kDiffuseThrough * f), qc = a;
  const double discriminant = qb * qb - 4.0 * qa * qc;
  if (discriminant < 0.0) return 0.0;  // f0 darker than any dielectric's: the closest is m = 0
  const double smaller = (-qb - std::sqrt(discriminant)) / (2.0 * qa),
               larger = (-qb + std::sqrt(discriminant)) / (2.0 * qa);
  const double t = larger <= 1.0 + 1e-12 ? larger : smaller;
  return std::clamp(1.0 - t, 0.0, 1.0);
}

double ior_from_f0(double f0) {
  const double r = std::sqrt(std::clamp(f0, 0.0, 0.99));
  return (1.0 + r) / (1.0 - r);
}
double f0_from_ior(double ior) { return std::pow((ior - 1.0) / (ior + 1.0), 2); }
// The dielectric F0 (untinted) of a core: its weight times the ior's.
double dielectric_f0(const Core& core) { return core.specular_weight * f0_from_ior(core.ior); }

void set_colour(const Model& model, std::vector<double>& values, const char* name, const Rgb<double>& colour) {
  const int offset = model.offset_of(name);
  for (int c = 0; c < 3; ++c) values[offset + c] = colour[c];
}
void set_value(const Model& model, std::vector<double>& values, const char* name, double value) {
  values[model.offset_of(name)] = value;
}

// The base colour's name in principled (Burley's baseColor) and mitsuba-principled (the plugin's
// base_color), which share their other core parameters' names.
const char* principled_base_color(const std::string& model_name) {
  return model_name == "principled" ? "baseColor" : "base_color";
}

std::vector<double> values_from_core(const Model& model, const Core& core) {
  std::vector<double> values = model.default_values();
  const std::string& name = model.name();
  const auto clamp_to = [&](const char* param, double value) {
    const ParamSpec& p = *model.find_parameter(param);
    return std::clamp(value, p.lower, p.upper);
  };
  const Rgb<double> base = core.base_color.cwiseMax(0.0).cwiseMin(1.0),
                    tint = core.specular_color.cwiseMax(0.0).cwiseMin(1.0);
  if (is_gltf_model(name)) {  // the core's coat and sheen where the model has them (their weight 0: off); no stretch
    set_colour(model, values, "baseColor", base);
    if (model.find_parameter("clearcoatFactor")) {
      set_value(model, values, "clearcoatFactor", clamp_to("clearcoatFactor", core.coat.weight));
      set_value(model, values, "clearcoatRoughnessFactor", clamp_to("clearcoatRoughnessFactor", core.coat.roughness));
    }
    if (model.find_parameter("sheenColorFactor")) {
      set_colour(model, values, "sheenColorFactor", (core.sheen.weight * core.sheen.color).cwiseMax(0.0).cwiseMin(1.0));
      set_value(model, values, "sheenRoughnessFactor", clamp_to("sheenRoughnessFactor", core.sheen.roughness));
    }
    if (model.find_parameter("anisotropyStrength")) set_value(model, values, "anisotropyStrength", 0.0);
    set_value(model, values, "metallic", clamp_to("metallic", core.metallic));
    set_value(model, values, "roughness", clamp_to("roughness", core.roughness));
    if (name == "gltf-specular") {
      set_value(model, values, "ior", clamp_to("ior", core.ior));
      set_value(model, values, "specular", clamp_to("specular", core.specular_weight));
      set_colour(model, values, "specularColor", tint);
    }
  } else if (is_openpbr_model(name)) {  // its specular_weight is held at 1: the weight goes into the ior
    set_colour(model, values, "base_color", base);
    set_value(model, values, "base_metalness", clamp_to("base_metalness", core.metallic));
    set_value(model, values, "specular_roughness", clamp_to("specular_roughness", core.roughness));
    set_value(model, values, "specular_ior", clamp_to("specular_ior", ior_from_f0(dielectric_f0(core))));
    set_colour(model, values, "specular_color", tint);
    if (model.find_parameter("coat_weight")) {
      set_value(model, values, "coat_weight", clamp_to("coat_weight", core.coat.weight));
      set_colour(model, values, "coat_color", core.coat.color.cwiseMax(0.0).cwiseMin(1.0));
      set_value(model, values, "coat_roughness", clamp_to("coat_roughness", core.coat.roughness));
      set_value(model, values, "coat_ior", clamp_to("coat_ior", core.coat.ior));
    }
    if (model.find_parameter("fuzz_weight")) {
      set_value(model, values, "fuzz_weight", clamp_to("fuzz_weight", core.sheen.weight));
      set_colour(model, values, "fuzz_color", core.sheen.color.cwiseMax(0.0).cwiseMin(1.0));
      set_value(model, values, "fuzz_roughness", clamp_to("fuzz_roughness", core.sheen.roughness));
    }
  } else if (name == "principled" || name == "mitsuba-principled") {
    set_colour(model, values, principled_base_color(name), base);
    set_value(model, values, "metallic", clamp_to("metallic", core.metallic));
    set_value(model, values, "roughness", clamp_to("roughness", core.roughness));
    set_value(model, values, "specular", clamp_to("specular", dielectric_f0(core) / 0.08));
  } else {
    fail("{} is not a renderer material ({})", name, fmt::join(renderer_materials(), ", "));
  }
  return values;
}

}  // namespace

const std::vector<std::string>& gltf_models() {
  static const std::vector<std::string> models = {"gltf",       "gltf-specular",        "gltf+clearcoat",
                                                  "gltf+sheen", "gltf+clearcoat+sheen", "gltf+anisotropy"};
  return models;
}
bool is_gltf_model(const std::string& name) {
  return std::find(gltf_models().begin(), gltf_models().end(), name) != gltf_models().end();
}

const std::vector<std::string>& openpbr_models() {
  static const std::vector<std::string> models = {"openpbr", "openpbr+coat", "openpbr+fuzz", "openpbr+coat+fuzz"};
  return models;
}
bool is_openpbr_model(const std::string& name) {
  return std::find(openpbr_models().begin(), openpbr_models().end(), name) != openpbr_models().end();
}

const std::vector<std::string>& renderer_materials() {
  static const std::vector<std::string> models = [] {
    std::vector<std::string> names = gltf_models();
    names.insert(names.end(), openpbr_models().begin(), openpbr_models().end());
    names.insert(names.end(), {"principled", "mitsuba-principled"});
    return names;
  }();
  return models;
}

const std::vector<std::string>& convertible_models() {
  static const std::vector<std::string> models = [] {
    std::vector<std::string> names = {"ggx"};
    names.insert(names.end(), renderer_materials().begin(), renderer_materials().end());
    return names;
  }();
  return models;
}

Rgb<double> colour_at(const Model& model, const std::vector<double>& values, const char* name) {
  const int offset = model.offset_of(name);
  return Rgb<double>(values[offset], values[offset + 1], values[offset + 2]);
}
double value_at(const Model& model, const std::vector<double>& values, const char* name) {
  return values[model.offset_of(name)];
}

Core core_of(const std::string& model_name, const std::vector<double>& values) {
  const Model& model = *find_model(model_name);
  Core core;
  if (model_name == "ggx") {
    const MetallicRoughness mr = metallic_roughness(colour_at(model, values, "albedo"), colour_at(model, values, "f0"),
                                                    value_at(model, values, "roughness"));
    core.base_color = mr.base_color;
    core.metallic = mr.metallic;
    core.roughness = mr.roughness;
  } else if (is_gltf_model(model_name)) {
    core.base_color = colour_at(model, values, "baseColor");
    core.metallic = value_at(model, values, "metallic");
    core.roughness = value_at(model, values, "roughness");
    if (model_name == "gltf-specular") {
      core.ior = value_at(model, values, "ior");
      core.specular_weight = value_at(model, values, "specular");
      core.specular_color = colour_at(model, values, "specularColor");
    }
    if (model.find_parameter("clearcoatFactor")) {
      core.coat.weight = value_at(model, values, "clearcoatFactor");
      core.coat.roughness = value_at(model, values, "clearcoatRoughnessFactor");
    }
    if (model.find_parameter("sheenColorFactor")) {
      const Rgb<double> sheen = colour_at(model, values, "sheenColorFactor");
      core.sheen.weight = sheen.maxCoeff();
      if (core.sheen.weight > 0.0) core.sheen.color = sheen / core.sheen.weight;
      core.sheen.roughness = value_at(model, values, "sheenRoughnessFactor");
    }
  } else if (is_openpbr_model(model_name)) {
    core.base_color = colour_at(model, values, "base_color");
    core.metallic = value_at(model, values, "base_metalness");
    core.roughness = value_at(model, values, "specular_roughness");
    core.ior = value_at(model, values, "specular_ior");
    core.specular_color = colour_at(model, values, "specular_color");
    if (model.find_parameter("coat_weight"))
      core.coat = {value_at(model, values, "coat_weight"), value_at(model, values, "coat_roughness"),
                   value_at(model, values, "coat_ior"), colour_at(model, values, "coat_color")};
    if (model.find_parameter("fuzz_weight"))
      core.sheen = {value_at(model, values, "fuzz_weight"), value_at(model, values, "fuzz_roughness"),
                    colour_at(model, values, "fuzz_color")};
  } else if (model_name == "principled" || model_name == "mitsuba-principled") {
    // Burley's parameters, under Mitsuba's names in mitsuba-principled (whose η is exactly
    // ior_from_f0(0.08·specular)).
    core.base_color = colour_at(model, values, principled_base_color(model_name));
    core.metallic = value_at(model, values, "metallic");
    core.roughness = value_at(model, values, "roughness");
    core.ior = ior_from_f0(0.08 * value_at(model, values, "specular"));
  } else {
    fail("no conversion from the {} model: export converts {} fits", model_name,
         join_words(convertible_models(), "and"));
  }
  return core;
}

const Nesting* nesting_of(const Model& target, const std::string& source_model) {
  const std::vector<std::string>& materials = renderer_materials();
  if (std::find(materials.begin(), materials.end(), source_model) == materials.end()) return nullptr;
  for (const Nesting& nesting : target.nestings())
    if (nesting.inner == source_model) return &nesting;
  return nullptr;
}

MetallicRoughness metallic_roughness(const Rgb<double>& albedo, const Rgb<double>& f0, double roughness) {
  MetallicRoughness out;
  out.roughness = std::clamp(roughness, 0.0, 1.0);
  out.metallic = solve_metallic(rec709_luminance(albedo), rec709_luminance(f0));
  const double m = out.metallic, diffuse = (1.0 - m) * kDiffuseThrough;
  for (int c = 0; c < 3; ++c) {
    const double b = (diffuse * albedo[c] + m * (f0[c] - kDielectricF0 * (1.0 - m))) / (diffuse * diffuse + m * m);
    out.base_color[c] = std::clamp(b, 0.0, 1.0);
  }
  out.albedo = diffuse * out.base_color;
  out.f0 = (kDielectricF0 * (1.0 - m) + m * out.base_color.array()).matrix();
  return out;
}

Material convert_material(const std::string& source_model, const std::vector<double>& values,
                          const std::string& model) {
  const Model* target = find_model(model);
  if (!target) fail("unknown model '{}'", model);
  if (const Nesting* nesting = nesting_of(*target, source_model))
    return {"", model, embed_values(*target, *nesting, *find_model(source_model), values)};
  return {"", model, values_from_core(*target, core_of(source_model, values))};
}

}  // namespace brdffit
