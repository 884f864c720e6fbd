// Renderer materials from fits: choosing the fit, converting through the metallic-roughness
// core, and writing glTF, MaterialX (OpenPBR) and Mitsuba 3 files (see material_export.h).
#include "brdffit/material_export.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>

#include "brdffit/base64.h"
#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/io.h"
#include "brdffit/measured.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"
#include "brdffit/text.h"

namespace brdffit {

namespace {

constexpr double kDielectricF0 = 0.04;                   // glTF's (IOR 1.5)
constexpr double kDiffuseThrough = 1.0 - kDielectricF0;  // the light the dielectric coat lets through
constexpr int kFixedDirectionPairs = 20000;              // MaterialExport::converted_vs_fit
constexpr uint64_t kFixedDirectionsSeed = 1;

// The models glTF holds unchanged: the core, and the core with KHR extensions (gltf-specular's
// KHR_materials_ior and _specular, the layers of KHR_materials_clearcoat and _sheen).
const std::vector<std::string>& gltf_models() {
  static const std::vector<std::string> models = {"gltf", "gltf-specular", "gltf+clearcoat", "gltf+sheen",
                                                  "gltf+clearcoat+sheen"};
  return models;
}
bool is_gltf_model(const std::string& name) {
  return std::find(gltf_models().begin(), gltf_models().end(), name) != gltf_models().end();
}

// The metallic value that matches a single (luminance) albedo a and f0 f; see the header.
double solve_metallic(double a, double f) {
  const double qa = kDielectricF0 * kDiffuseThrough, qb = -(a + kDiffuseThrough * f), qc = a;
  const double discriminant = qb * qb - 4.0 * qa * qc;
  if (discriminant < 0.0) return 0.0;  // f0 darker than any dielectric's: the closest is m = 0
  const double smaller = (-qb - std::sqrt(discriminant)) / (2.0 * qa),
               larger = (-qb + std::sqrt(discriminant)) / (2.0 * qa);
  const double t = larger <= 1.0 + 1e-12 ? larger : smaller;
  return std::clamp(1.0 - t, 0.0, 1.0);
}

// The metallic-roughness core every renderer material shares, with the dielectric's reflection:
// F0 = specular_weight·((ior-1)/(ior+1))² (tinted by specular_color where the model has one).
// Each target keeps what it can hold of it: gltf-specular all three; openpbr the ior, folding the
// weight into it (same F0) and the tint; principled and mitsuba-principled F0 as specular = F0/0.08;
// gltf and its extension models none (ior 1.5). A source without them has weight 1 and tint 1. A
// gltf+clearcoat, gltf+sheen or gltf+clearcoat+sheen source's core is its base: the coat and the
// sheen are what a conversion leaves out (and its error shows).
struct Core {
  Rgb<double> base_color = Rgb<double>::Constant(0.5);
  double metallic = 0.0, roughness = 0.5, ior = 1.5;
  double specular_weight = 1.0;
  Rgb<double> specular_color = Rgb<double>::Ones();
};

double ior_from_f0(double f0) {
  const double r = std::sqrt(std::clamp(f0, 0.0, 0.99));
  return (1.0 + r) / (1.0 - r);
}
double f0_from_ior(double ior) { return std::pow((ior - 1.0) / (ior + 1.0), 2); }
// The dielectric F0 (untinted) of a core: its weight times the ior's.
double dielectric_f0(const Core& core) { return core.specular_weight * f0_from_ior(core.ior); }

Rgb<double> colour_at(const Model& model, const std::vector<double>& values, const char* name) {
  const int offset = model.offset_of(name);
  return Rgb<double>(values[offset], values[offset + 1], values[offset + 2]);
}
double value_at(const Model& model, const std::vector<double>& values, const char* name) {
  return values[model.offset_of(name)];
}
void set_colour(const Model& model, std::vector<double>& values, const char* name, const Rgb<double>& colour) {
  const int offset = model.offset_of(name);
  for (int c = 0; c < 3; ++c) values[offset + c] = colour[c];
}
void set_value(const Model& model, std::vector<double>& values, const char* name, double value) {
  values[model.offset_of(name)] = value;
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
  } else if (model_name == "openpbr") {
    core.base_color = colour_at(model, values, "base_color");
    core.metallic = value_at(model, values, "base_metalness");
    core.roughness = value_at(model, values, "specular_roughness");
    core.ior = value_at(model, values, "specular_ior");
    core.specular_color = colour_at(model, values, "specular_color");
  } else if (model_name == "principled") {
    core.base_color = colour_at(model, values, "baseColor");
    core.metallic = value_at(model, values, "metallic");
    core.roughness = value_at(model, values, "roughness");
    core.ior = ior_from_f0(0.08 * value_at(model, values, "specular"));
  } else if (model_name == "mitsuba-principled") {  // its η is exactly ior_from_f0(0.08·specular)
    core.base_color = colour_at(model, values, "base_color");
    core.metallic = value_at(model, values, "metallic");
    core.roughness = value_at(model, values, "roughness");
    core.ior = ior_from_f0(0.08 * value_at(model, values, "specular"));
  } else {
    fail(
        "no conversion from the {} model: export converts ggx, gltf, gltf-specular, gltf+clearcoat, gltf+sheen, "
        "gltf+clearcoat+sheen, openpbr, "
        "principled and mitsuba-principled fits",
        model_name);
  }
  return core;
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
  if (is_gltf_model(name)) {  // the core holds no coat or sheen: gltf+clearcoat's and gltf+sheen's layers off
    set_colour(model, values, "baseColor", base);
    if (model.find_parameter("clearcoatFactor")) set_value(model, values, "clearcoatFactor", 0.0);
    if (model.find_parameter("sheenColorFactor")) set_colour(model, values, "sheenColorFactor", Rgb<double>::Zero());
    set_value(model, values, "metallic", clamp_to("metallic", core.metallic));
    set_value(model, values, "roughness", clamp_to("roughness", core.roughness));
    if (name == "gltf-specular") {
      set_value(model, values, "ior", clamp_to("ior", core.ior));
      set_value(model, values, "specular", clamp_to("specular", core.specular_weight));
      set_colour(model, values, "specularColor", tint);
    }
  } else if (name == "openpbr") {  // its specular_weight is held at 1: the weight goes into the ior
    set_colour(model, values, "base_color", base);
    set_value(model, values, "base_metalness", clamp_to("base_metalness", core.metallic));
    set_value(model, values, "specular_roughness", clamp_to("specular_roughness", core.roughness));
    set_value(model, values, "specular_ior", clamp_to("specular_ior", ior_from_f0(dielectric_f0(core))));
    set_colour(model, values, "specular_color", tint);
  } else if (name == "principled") {
    set_colour(model, values, "baseColor", base);
    set_value(model, values, "metallic", clamp_to("metallic", core.metallic));
    set_value(model, values, "roughness", clamp_to("roughness", core.roughness));
    set_value(model, values, "specular", clamp_to("specular", dielectric_f0(core) / 0.08));
  } else if (name == "mitsuba-principled") {
    set_colour(model, values, "base_color", base);
    set_value(model, values, "metallic", clamp_to("metallic", core.metallic));
    set_value(model, values, "roughness", clamp_to("roughness", core.roughness));
    set_value(model, values, "specular", clamp_to("specular", dielectric_f0(core) / 0.08));
  } else {
    fail(
        "{} is not a renderer material (gltf, gltf-specular, gltf+clearcoat, gltf+sheen, gltf+clearcoat+sheen, "
        "openpbr, principled, mitsuba-principled)",
        name);
  }
  return values;
}

// A fit's values for export: a per-channel fit's shape parameters are the mean of its channels'.
std::vector<double> export_values(const Model& model, const FitResult& fit, std::vector<std::string>& warnings) {
  if (static_cast<int>(fit.values.size()) != model.num_values())
    fail("the {} result has {} values, the model has {}", fit.model, fit.values.size(), model.num_values());
  std::vector<double> values = fit.values;
  if (fit.channel_values.size() == 3) {
    int offset = 0;
    for (const ParamSpec& p : model.parameters()) {
      if (p.channels == 1)
        values[offset] =
            (fit.channel_values[0][offset] + fit.channel_values[1][offset] + fit.channel_values[2][offset]) / 3;
      offset += p.channels;
    }
    warnings.push_back("a per-channel fit: its shape parameters are written as the mean of the three channels'");
  }
  return values;
}

template <class T>
void append_bytes(std::vector<uint8_t>& bytes, const T& value) {
  const auto* p = reinterpret_cast<const uint8_t*>(&value);
  bytes.insert(bytes.end(), p, p + sizeof(T));
}

// A unit UV sphere: positions (= normals), and triangles with a fan at each pole (no degenerate
// triangle), counter-clockwise seen from outside as glTF requires.
struct SphereMesh {
  std::vector<float> positions;  // x, y, z per vertex
  std::vector<uint16_t> indices;
};

SphereMesh sphere_mesh(int rings = 16, int segments = 32) {
  SphereMesh mesh;
  const auto add = [&](double theta, double phi) {
    mesh.positions.push_back(static_cast<float>(std::sin(theta) * std::cos(phi)));
    mesh.positions.push_back(static_cast<float>(std::cos(theta)));
    mesh.positions.push_back(static_cast<float>(-std::sin(theta) * std::sin(phi)));
  };
  add(0.0, 0.0);  // north pole (+y), vertex 0
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < segments; ++s) add(kPi * r / rings, 2 * kPi * s / segments);
  add(kPi, 0.0);  // south pole
  const auto ring_vertex = [&](int r, int s) { return static_cast<uint16_t>(1 + (r - 1) * segments + s % segments); };
  const uint16_t south = static_cast<uint16_t>(mesh.positions.size() / 3 - 1);
  for (int s = 0; s < segments; ++s) {
    mesh.indices.insert(mesh.indices.end(), {0, ring_vertex(1, s), ring_vertex(1, s + 1)});
    for (int r = 1; r + 1 < rings; ++r) {
      const uint16_t a = ring_vertex(r, s), b = ring_vertex(r + 1, s), c = ring_vertex(r + 1, s + 1),
                     d = ring_vertex(r, s + 1);
      mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
    }
    mesh.indices.insert(mesh.indices.end(), {south, ring_vertex(rings - 1, s + 1), ring_vertex(rings - 1, s)});
  }
  return mesh;
}

nlohmann::json number_array(const Rgb<double>& c) { return {c[0], c[1], c[2]}; }

}  // namespace

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

const char* material_format_name(MaterialFormat format) {
  switch (format) {
    case MaterialFormat::Gltf: return "gltf";
    case MaterialFormat::OpenPbr: return "openpbr";
    case MaterialFormat::Mitsuba: return "mitsuba";
  }
  return "?";
}

MaterialFormat material_format(const std::string& name, const std::string& path) {
  const std::string extension = std::filesystem::path(path).extension().string();
  std::optional<MaterialFormat> implied;
  if (extension == ".gltf") implied = MaterialFormat::Gltf;
  if (extension == ".mtlx") implied = MaterialFormat::OpenPbr;
  if (extension == ".xml") implied = MaterialFormat::Mitsuba;
  if (name.empty()) {
    if (implied) return *implied;
    fail("--format: gltf, openpbr or mitsuba (not implied by the name {}: .gltf, .mtlx or .xml)", path);
  }
  for (const MaterialFormat f : {MaterialFormat::Gltf, MaterialFormat::OpenPbr, MaterialFormat::Mitsuba}) {
    if (name != material_format_name(f)) continue;
    // A file named for one format holding another would be misread by every tool that opens it.
    if (implied && *implied != f)
      fail(
          "--format {} conflicts with the output {}, whose extension {} is the {} format's: leave out --format, or "
          "name the output for {}",
          name, path, extension, material_format_name(*implied), name);
    return f;
  }
  fail("--format: gltf, openpbr or mitsuba, not '{}'", name);
}

std::vector<std::string> native_models(MaterialFormat format) {
  switch (format) {
    case MaterialFormat::Gltf: return gltf_models();
    case MaterialFormat::OpenPbr: return {"openpbr"};
    case MaterialFormat::Mitsuba: return {"mitsuba-principled"};
  }
  return {};
}

namespace {

// The target's nesting of the source when both are renderer materials: the conversion then maps
// every parameter by name (principled → mitsuba-principled) instead of through the
// metallic-roughness core. (A nesting of lambert or ggx is a fitting start, not a material.)
const Nesting* nesting_of(const Model& target, const std::string& source_model) {
  static const std::vector<std::string> kRendererMaterials = {"gltf",       "gltf-specular",        "gltf+clearcoat",
                                                              "gltf+sheen", "gltf+clearcoat+sheen", "openpbr",
                                                              "principled", "mitsuba-principled"};
  if (std::find(kRendererMaterials.begin(), kRendererMaterials.end(), source_model) == kRendererMaterials.end())
    return nullptr;
  for (const Nesting& nesting : target.nestings())
    if (nesting.inner == source_model) return &nesting;
  return nullptr;
}

}  // namespace

Material convert_material(const std::string& source_model, const std::vector<double>& values,
                          const std::string& model) {
  const Model* target = find_model(model);
  if (!target) fail("unknown model '{}'", model);
  if (const Nesting* nesting = nesting_of(*target, source_model))
    return {"", model, embed_values(*target, *nesting, *find_model(source_model), values)};
  return {"", model, values_from_core(*target, core_of(source_model, values))};
}

namespace {

// The fit's shaded values on the fixed directions of MaterialExport::converted_vs_fit: pairs
// uniform in solid angle (cosθ uniform in [0, 1), φ uniform) from a fixed seed, so that the
// metric estimates the same hemisphere integrals as on a densely measured table.
SampleSet fixed_directions(const Model& model, const std::vector<double>& values,
                           const std::vector<std::vector<double>>& per_channel_values) {
  SampleSet set;
  set.source = "fixed directions";
  set.weighting = "solid-angle";
  std::mt19937_64 rng(kFixedDirectionsSeed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto direction = [&] {
    const double z = unit(rng), phi = 2 * kPi * unit(rng), r = std::sqrt(1.0 - z * z);
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
  };
  for (int i = 0; i < kFixedDirectionPairs; ++i) {
    Sample s;
    s.l = direction();
    s.v = direction();
    s.value = shade_fitted(model, values, per_channel_values, s.l, s.v);
    set.samples.push_back(s);
  }
  return set;
}

}  // namespace

namespace {

// The model of `format` a fit of another model becomes: the format's first, except for glTF when
// the fit's dielectric is not the core's (IOR 1.5, weight 1, no tint), which only gltf-specular's
// KHR_materials_ior and KHR_materials_specular hold.
std::string conversion_target(MaterialFormat format, const std::string& source_model,
                              const std::vector<double>& values) {
  const std::vector<std::string> natives = native_models(format);
  if (format != MaterialFormat::Gltf) return natives.front();
  const Core core = core_of(source_model, values);
  const bool core_dielectric =
      std::abs(core.ior - 1.5) < 1e-9 && core.specular_weight == 1.0 && core.specular_color == Rgb<double>::Ones();
  return core_dielectric ? "gltf" : "gltf-specular";
}

}  // namespace

MaterialExport export_material(const FitDocument& document, const ExportRequest& request) {
  const std::vector<std::string> natives = native_models(request.format);
  const FitResult* fit = nullptr;
  if (request.model.empty()) {
    for (const std::string& model : natives)
      if (!fit) fit = find_result(document.results, model);
    if (!fit)
      fail(
          "{}: has no {} fit; fit with -m {} to export it unchanged, or convert another fit with -m "
          "(ggx, gltf, gltf-specular, gltf+clearcoat, gltf+sheen, gltf+clearcoat+sheen, openpbr, principled, "
          "mitsuba-principled)",
          document.path, natives.front(), natives.front());
  } else {
    fit = find_result(document.results, request.model);
    if (!fit) fail("{}: has no {} fit", document.path, request.model);
  }
  MaterialExport out;
  out.source_model = fit->model;
  if (!fit->ok) fail("{}: the {} fit failed ({}): nothing to export", document.path, fit->model, fit->error);
  if (fit->verdict != Verdict::Good) {
    const std::string why = fit->warnings.empty() ? "" : " (" + fit->warnings.front() + ")";
    if (!request.force)
      fail("{}: the {} fit's verdict is {}{}; it does not describe the measurement. Export it anyway with --force",
           document.path, fit->model, verdict_name(fit->verdict), why);
    out.warnings.push_back(fmt::format("the {} fit's verdict is {}{}: exported because of --force", fit->model,
                                       verdict_name(fit->verdict), why));
  }
  const Model& source = *find_model(fit->model);
  const std::vector<double> values = export_values(source, *fit, out.warnings);
  const std::string metric_name = document.json.value("metric", "cosine");
  const Metric metric = parse_metric(metric_name).value_or(Metric::Cosine);
  out.metric = metric_name;
  out.fit_error = fit->metrics.get(metric);

  out.converted = std::find(natives.begin(), natives.end(), fit->model) == natives.end();
  out.material = out.converted
                     ? convert_material(fit->model, values, conversion_target(request.format, fit->model, values))
                     : Material{"", fit->model, values};
  out.material.name = material_name(document);
  if (out.converted) {
    out.converted_vs_fit = evaluate_metrics(*find_model(out.material.model), out.material.values,
                                            fixed_directions(source, fit->values, fit->channel_values))
                               .get(metric);
    try {
      const SampleSet data = load_samples(document.input_path, SamplingOptions{});
      out.converted_error = evaluate_metrics(*find_model(out.material.model), out.material.values, data).get(metric);
      out.source_error_on_data = evaluate_metrics(source, fit->values, data, fit->channel_values).get(metric);
    } catch (const Error& e) {
      out.warnings.push_back(
          fmt::format("the converted material could not be scored on the original data: {}", e.what()));
    }
  }

  const Nesting* by_name = nesting_of(*find_model(out.material.model), fit->model);
  out.conversion = !out.converted ? "unchanged"
                   : by_name      ? fmt::format("parameter by parameter ({})", by_name->why)
                                  : "through the metallic-roughness core";
  const std::string conversion = out.converted ? fmt::format("converted from the {} fit {}", fit->model, out.conversion)
                                               : fmt::format("the {} fit, unchanged", fit->model);
  nlohmann::json provenance = {{"result", document.path},     {"input", document.input_path},
                               {"model", out.material.model}, {"source_model", fit->model},
                               {"converted", out.converted},  {"verdict", verdict_name(fit->verdict)},
                               {"metric", metric_name},       {"metrics", fit_result_json(*fit)["metrics"]}};
  if (out.converted) {
    provenance["converted_error_on_input"] = out.converted_error;
    provenance["converted_vs_fit"] = out.converted_vs_fit;
  }
  const std::string comment = fmt::format(
      "brdffit {}: fitted to {}: {} ({} error {:.4g}{}).", BRDFFIT_VERSION, document.input_path, conversion,
      metric_name, out.fit_error,
      out.converted ? fmt::format("; this converted material's error on the same data {:.4g}, against the fit on fixed "
                                  "directions {:.4g}",
                                  out.converted_error, out.converted_vs_fit)
                    : "");
  switch (request.format) {
    case MaterialFormat::Gltf: out.text = gltf_document(out.material, provenance); break;
    case MaterialFormat::OpenPbr: out.text = materialx_document(out.material, comment); break;
    case MaterialFormat::Mitsuba: out.text = mitsuba_document(out.material, comment); break;
  }
  return out;
}

std::string gltf_document(const Material& material, const nlohmann::json& provenance) {
  const Model& model = *find_model(material.model);
  if (!is_gltf_model(material.model))
    fail("glTF holds a gltf, gltf-specular, gltf+clearcoat, gltf+sheen or gltf+clearcoat+sheen material, not {}",
         material.model);
  const std::vector<double>& v = material.values;
  const Rgb<double> base = colour_at(model, v, "baseColor");
  nlohmann::json gltf_material = {{"name", material.name},
                                  {"pbrMetallicRoughness",
                                   {{"baseColorFactor", {base[0], base[1], base[2], 1.0}},
                                    {"metallicFactor", value_at(model, v, "metallic")},
                                    {"roughnessFactor", value_at(model, v, "roughness")}}},
                                  {"extras", {{"brdffit", provenance}}}};
  nlohmann::json extensions_used = nlohmann::json::array();
  if (material.model == "gltf-specular") {
    gltf_material["extensions"] = {{"KHR_materials_ior", {{"ior", value_at(model, v, "ior")}}},
                                   {"KHR_materials_specular",
                                    {{"specularFactor", value_at(model, v, "specular")},
                                     {"specularColorFactor", number_array(colour_at(model, v, "specularColor"))}}}};
    extensions_used = {"KHR_materials_ior", "KHR_materials_specular"};
  }
  // The layers' parameters carry their extensions' names.
  if (model.find_parameter("clearcoatFactor")) {
    gltf_material["extensions"]["KHR_materials_clearcoat"] = {
        {"clearcoatFactor", value_at(model, v, "clearcoatFactor")},
        {"clearcoatRoughnessFactor", value_at(model, v, "clearcoatRoughnessFactor")}};
    extensions_used.push_back("KHR_materials_clearcoat");
  }
  if (model.find_parameter("sheenColorFactor")) {
    gltf_material["extensions"]["KHR_materials_sheen"] = {
        {"sheenColorFactor", number_array(colour_at(model, v, "sheenColorFactor"))},
        {"sheenRoughnessFactor", value_at(model, v, "sheenRoughnessFactor")}};
    extensions_used.push_back("KHR_materials_sheen");
  }

  // One buffer: positions, normals (the same unit vectors), then 16-bit indices.
  const SphereMesh mesh = sphere_mesh();
  std::vector<uint8_t> bytes;
  for (int copy = 0; copy < 2; ++copy)
    for (float x : mesh.positions) append_bytes(bytes, x);
  for (uint16_t i : mesh.indices) append_bytes(bytes, i);
  while (bytes.size() % 4) bytes.push_back(0);
  const size_t vertices = mesh.positions.size() / 3, vertex_bytes = vertices * 12;
  nlohmann::json gltf = {
      {"asset", {{"version", "2.0"}, {"generator", "brdffit " BRDFFIT_VERSION}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}, {"name", material.name}}}},
      {"meshes",
       {{{"name", "sphere"},
         {"primitives", {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"indices", 2}, {"material", 0}}}}}}},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", 5126},
         {"count", vertices},
         {"type", "VEC3"},
         {"min", {-1.0, -1.0, -1.0}},
         {"max", {1.0, 1.0, 1.0}}},
        {{"bufferView", 1}, {"componentType", 5126}, {"count", vertices}, {"type", "VEC3"}},
        {{"bufferView", 2}, {"componentType", 5123}, {"count", mesh.indices.size()}, {"type", "SCALAR"}}}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", vertex_bytes}, {"target", 34962}},
        {{"buffer", 0}, {"byteOffset", vertex_bytes}, {"byteLength", vertex_bytes}, {"target", 34962}},
        {{"buffer", 0}, {"byteOffset", 2 * vertex_bytes}, {"byteLength", mesh.indices.size() * 2}, {"target", 34963}}}},
      {"buffers", {{{"byteLength", bytes.size()}, {"uri", "data:application/octet-stream;base64," + base64(bytes)}}}},
      {"materials", {gltf_material}}};
  // The accessor bounds must be the data's exactly (the validator checks them).
  Rgb<double> lo = Rgb<double>::Constant(1e30), hi = Rgb<double>::Constant(-1e30);
  for (size_t i = 0; i < vertices; ++i)
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min<double>(lo[c], mesh.positions[3 * i + c]);
      hi[c] = std::max<double>(hi[c], mesh.positions[3 * i + c]);
    }
  gltf["accessors"][0]["min"] = number_array(lo);
  gltf["accessors"][0]["max"] = number_array(hi);
  if (!extensions_used.empty()) gltf["extensionsUsed"] = extensions_used;
  return gltf.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

std::string materialx_document(const Material& material, const std::string& comment) {
  if (material.model != "openpbr") fail("MaterialX holds an openpbr material, not {}", material.model);
  const Model& model = *find_model(material.model);
  const std::string name = xml_name(material.name);
  std::string xml = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n";
  xml += "<!-- " + xml_comment_text(comment) +
         "\n     base_weight, specular_weight and specular_roughness_anisotropy: as brdffit's openpbr model holds "
         "them. -->\n";
  xml += "<materialx version=\"1.39\" colorspace=\"lin_rec709\">\n";
  xml += fmt::format("  <open_pbr_surface name=\"{}_shader\" type=\"surfaceshader\">\n", name);
  xml += "    <input name=\"base_weight\" type=\"float\" value=\"1\" />\n";
  int offset = 0;
  for (const ParamSpec& p : model.parameters()) {
    const std::vector<double>& v = material.values;
    if (p.channels == 3)
      xml += fmt::format("    <input name=\"{}\" type=\"color3\" value=\"{:.9g}, {:.9g}, {:.9g}\" />\n", p.name,
                         v[offset], v[offset + 1], v[offset + 2]);
    else
      xml += fmt::format("    <input name=\"{}\" type=\"float\" value=\"{:.9g}\" />\n", p.name, v[offset]);
    offset += p.channels;
  }
  xml += "    <input name=\"specular_weight\" type=\"float\" value=\"1\" />\n";
  xml += "    <input name=\"specular_roughness_anisotropy\" type=\"float\" value=\"0\" />\n";
  xml += "  </open_pbr_surface>\n";
  xml += fmt::format("  <surfacematerial name=\"{}\" type=\"material\">\n", name);
  xml += fmt::format("    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"{}_shader\" />\n", name);
  xml += "  </surfacematerial>\n</materialx>\n";
  return xml;
}

std::string mitsuba_document(const Material& material, const std::string& comment) {
  if (material.model != "mitsuba-principled")
    fail("Mitsuba's principled BSDF holds a mitsuba-principled material, not {}", material.model);
  const Model& model = *find_model(material.model);
  const std::vector<double>& v = material.values;
  const std::string id = xml_name(material.name);
  std::string xml = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n";
  xml += "<!-- " + xml_comment_text(comment) +
         "\n     anisotropic 0 and sheen_tint 0.5 as brdffit's mitsuba-principled model holds them."
         "\n     Include this file in a scene and refer to the material as <ref id=\"" +
         id + "\"/>. -->\n";
  xml += "<scene version=\"3.0.0\">\n";
  xml += fmt::format("    <bsdf type=\"principled\" id=\"{}\">\n", id);
  int offset = 0;  // the model's parameters carry the plugin's names
  for (const ParamSpec& p : model.parameters()) {
    if (p.channels == 3)
      xml += fmt::format("        <rgb name=\"{}\" value=\"{:.9g}, {:.9g}, {:.9g}\"/>\n", p.name, v[offset],
                         v[offset + 1], v[offset + 2]);
    else
      xml += fmt::format("        <float name=\"{}\" value=\"{:.9g}\"/>\n", p.name, v[offset]);
    offset += p.channels;
  }
  xml += "        <float name=\"sheen_tint\" value=\"0.5\"/>\n";
  xml += "        <float name=\"anisotropic\" value=\"0\"/>\n";
  xml += "    </bsdf>\n</scene>\n";
  return xml;
}

}  // namespace brdffit
