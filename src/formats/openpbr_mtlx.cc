// OpenPBR Surface as a MaterialX document (.mtlx): the openpbr model and its layered forms
// (openpbr+coat, openpbr+fuzz, openpbr+coat+fuzz) as an open_pbr_surface, written and read back
// (material_export.h).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/material_convert.h"
#include "brdffit/material_export.h"
#include "brdffit/material_formats.h"
#include "brdffit/registry.h"
#include "brdffit/text.h"
#include "brdffit/xml_reader.h"

namespace brdffit {

std::string materialx_document(const Material& material, const std::string& comment) {
  if (!is_openpbr_model(material.model))
    fail("MaterialX holds an {} material, not {}", join_words(openpbr_models(), "or"), material.model);
  const Model& model = *find_model(material.model);
  const bool coated = model.find_parameter("coat_weight") != nullptr;
  const std::string name = xml_name(material.name);
  std::string xml = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n";
  xml += "<!-- " + xml_comment_text(comment) + "\n     base_weight, specular_weight and specular_roughness_anisotropy" +
         (coated ? ", coat_roughness_anisotropy and coat_darkening" : "") + ": as brdffit's " + material.model +
         " model holds them. -->\n";
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
  if (coated) {
    xml += "    <input name=\"coat_roughness_anisotropy\" type=\"float\" value=\"0\" />\n";
    xml += "    <input name=\"coat_darkening\" type=\"float\" value=\"1\" />\n";
  }
  xml += "  </open_pbr_surface>\n";
  xml += fmt::format("  <surfacematerial name=\"{}\" type=\"material\">\n", name);
  xml += fmt::format("    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"{}_shader\" />\n", name);
  xml += "  </surfacematerial>\n</materialx>\n";
  return xml;
}

namespace {

// OpenPBR's base_weight w (MaterialX's open_pbr_surface graph): the metal's F0 is w·base_color and
// the diffuse is w·EON(base_color, σ). Folded into base_color, the metal and EON's single
// scattering (linear in ρ) are exact, but EON's multiple scattering ρ_ms = ρ²Ē/(1 - ρ(1-Ē)) is not
// linear in ρ: exact only for σ = 0 (Lambert), w = 0 or 1, or metalness 1. Otherwise the warning
// gives the error in the diffuse's mean albedo, ρĒ/(1 - ρ(1-Ē)) for EON (single and multiple
// scattering), hence folded/true = (1 - ρ(1-Ē))/(1 - wρ(1-Ē)), Ē the mean albedo of EON's
// single scattering (models/openpbr.h).
void fold_base_weight(const Model& model, Material& material, double w, const std::string& path,
                      std::vector<std::string>& warnings) {
  const int base = model.offset_of("base_color");
  const double sigma = material.values[model.offset_of("base_diffuse_roughness")],
               metalness = material.values[model.offset_of("base_metalness")];
  double worst = 0.0;  // relative error of the folded diffuse's mean albedo, the largest channel's
  if (sigma > 0.0 && w > 0.0 && w < 1.0 && metalness < 1.0) {
    const double on_a = 1.0 / (1.0 + (0.5 - 2.0 / (3.0 * kPi)) * sigma);
    const double mean_single = on_a * (1.0 + (2.0 / 3.0 - 28.0 / (15.0 * kPi)) * sigma);
    for (int c = 0; c < 3; ++c) {
      const double rho = material.values[base + c], loss = rho * (1.0 - mean_single);
      const double error = (1.0 - loss) / (1.0 - w * loss) - 1.0;
      if (std::abs(error) > std::abs(worst)) worst = error;
    }
  }
  for (int c = 0; c < 3; ++c) material.values[base + c] *= w;
  if (worst != 0.0)
    warnings.push_back(fmt::format(
        "{}: base_weight {} of '{}' is folded into base_color, which is not exact with base_diffuse_roughness {} "
        "(EON's multiple scattering is not linear in the colour): the diffuse's mean albedo is {:+.3g} % off",
        path, w, material.name, sigma, 100.0 * worst));
}

// The inputs of one open_pbr_surface that hold a value: name → numbers. One connected to a node is
// reported and left out.
std::map<std::string, std::vector<double>> shader_inputs(const std::vector<XmlElement>& elements, int shader,
                                                         const std::string& material, const std::string& path,
                                                         std::vector<std::string>& warnings) {
  std::map<std::string, std::vector<double>> inputs;
  for (const int k : elements[shader].children) {
    if (elements[k].tag != "input") continue;
    const std::string name = attribute(elements[k], "name");
    if (!attribute(elements[k], "nodename").empty() || !attribute(elements[k], "nodegraph").empty()) {
      warnings.push_back(
          fmt::format("{}: {} of '{}' is connected to a node: left at its default", path, name, material));
      continue;
    }
    inputs[name] = parse_numbers(attribute(elements[k], "value"), name, path);
  }
  return inputs;
}

// The smallest of openpbr, openpbr+coat, openpbr+fuzz and openpbr+coat+fuzz that holds a shader's
// layers: those whose weight is given and not 0 (OpenPBR's default weights are 0).
const Model& model_holding(const std::map<std::string, std::vector<double>>& inputs) {
  const auto present = [&](const char* weight) {
    const auto it = inputs.find(weight);
    return it != inputs.end() && it->second[0] != 0.0;
  };
  std::string name = "openpbr";
  if (present("coat_weight")) name += "+coat";
  if (present("fuzz_weight")) name += "+fuzz";
  return *find_model(name);
}

std::vector<Material> read_materialx(const std::string& path, std::vector<std::string>& warnings) {
  const std::vector<XmlElement> elements = parse_xml(read_material_file(path), path);
  if (elements.empty() || elements[0].tag != "materialx") fail("{}: not a MaterialX document (<materialx>)", path);
  // Materials are named by the surfacematerial that uses a shader, or by the shader itself.
  std::map<std::string, std::string> material_of_shader;
  for (size_t i = 0; i < elements.size(); ++i)
    if (elements[i].tag == "input" && attribute(elements[i], "name") == "surfaceshader" && elements[i].parent >= 0 &&
        elements[elements[i].parent].tag == "surfacematerial")
      material_of_shader[attribute(elements[i], "nodename")] = attribute(elements[elements[i].parent], "name");
  std::vector<Material> materials;
  for (size_t i = 0; i < elements.size(); ++i) {
    if (elements[i].tag != "open_pbr_surface") continue;
    const std::string shader = attribute(elements[i], "name");
    const auto named = material_of_shader.find(shader);
    const std::string material_name = named != material_of_shader.end() ? named->second : shader;
    const std::map<std::string, std::vector<double>> inputs =
        shader_inputs(elements, static_cast<int>(i), material_name, path, warnings);
    const Model& model = model_holding(inputs);
    Material material{material_name, model.name(), model.default_values()};
    // The specification's defaults where an input is absent (they differ from the fit's starts).
    // coat_roughness's, 0, is below the model's bound: clamped, with a warning when the coat is on.
    set_parameter(model, material, "base_color", {0.8}, path, warnings);
    set_parameter(model, material, "specular_roughness", {0.3}, path, warnings);
    if (model.find_parameter("coat_roughness") && !inputs.count("coat_roughness"))
      set_parameter(model, material, "coat_roughness", {0.0}, path, warnings);
    double base_weight = 1.0, specular_weight = 1.0;
    for (const auto& [name, value] : inputs) {
      if (name == "base_weight")
        base_weight = value[0];
      else if (name == "specular_weight")
        specular_weight = value[0];
      else if (model.find_parameter(name))
        set_parameter(model, material, name, value, path, warnings);
      else if ((name == "specular_roughness_anisotropy" || name == "coat_roughness_anisotropy") && value[0] != 0.0)
        warnings.push_back(fmt::format("{}: {} {} of '{}' is held at 0 by the {} model", path, name, value[0],
                                       material.name, model.name()));
      else if (name == "coat_darkening" && value[0] != 1.0 && model.find_parameter("coat_weight"))
        warnings.push_back(fmt::format("{}: coat_darkening {} of '{}' is held at 1 by the {} model", path, value[0],
                                       material.name, model.name()));
      else if (value.size() == 1 && value[0] != 0.0 && name.find("weight") != std::string::npos &&
               name != "coat_weight" && name != "fuzz_weight")
        warnings.push_back(
            fmt::format("{}: {} = {} of '{}' is outside the opaque base, coat and fuzz brdffit's "
                        "OpenPBR models have",
                        path, name, value[0], material.name));
    }
    fold_base_weight(model, material, std::clamp(base_weight, 0.0, 1.0), path, warnings);
    if (model.find_parameter("coat_weight") && base_weight != 1.0)
      warnings.push_back(
          fmt::format("{}: base_weight {} of '{}' is folded into base_color, which the coat's darkening "
                      "reads too (MaterialX's darkening reads base_color alone)",
                      path, base_weight, material.name));
    if (specular_weight != 1.0)
      warnings.push_back(fmt::format("{}: specular_weight {} of '{}' is held at 1 by the {} model: not scored", path,
                                     specular_weight, material.name, model.name()));
    materials.push_back(std::move(material));
  }
  return materials;
}

// A fit of another model becomes the OpenPBR model with the layers its core has (material_convert.h):
// gltf+clearcoat's coat, gltf+sheen's sheen as the fuzz.
std::string openpbr_conversion_target(const std::string& source_model, const std::vector<double>& values) {
  const Core core = core_of(source_model, values);
  return std::string("openpbr") + (core.coat.weight > 0.0 ? "+coat" : "") + (core.sheen.weight > 0.0 ? "+fuzz" : "");
}

std::string write_materialx(const Material& material, const MaterialProvenance& provenance) {
  return materialx_document(material, provenance.comment);
}

}  // namespace

MaterialFormatInfo openpbr_format() {
  return {MaterialFormat::OpenPbr, "openpbr",        "OpenPBR (MaterialX)",     ".mtlx",         ".mtlx (OpenPBR)",
          "open_pbr_surface",      openpbr_models(), openpbr_conversion_target, write_materialx, read_materialx};
}

}  // namespace brdffit
