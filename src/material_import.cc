// Renderer materials read back from .gltf, .mtlx (OpenPBR) and Mitsuba 3 .xml files, as the
// matching brdffit model (see material_export.h). The XML files are read with a small reader of
// elements and attributes: enough for these formats, which keep every value in attributes.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/material_export.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"
#include "brdffit/result_json.h"

namespace brdffit {

namespace {

struct XmlElement {
  std::string tag;
  std::map<std::string, std::string> attributes;
  int parent = -1;            // index into the element list; -1 for the root
  std::vector<int> children;  // indices, in document order
};

// A material file, read whole: far above any real one, so that reading stays bounded.
std::string read_material_file(const std::string& path) { return read_file(path, kMaxMaterialFileBytes); }

std::string xml_unescape(const std::string& text, const std::string& path) {
  std::string out;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '&') {
      out += text[i];
      continue;
    }
    const size_t end = text.find(';', i);
    if (end == std::string::npos) fail("{}: malformed XML: '&' without ';'", path);
    const std::string entity = text.substr(i + 1, end - i - 1);
    if (entity == "amp")
      out += '&';
    else if (entity == "lt")
      out += '<';
    else if (entity == "gt")
      out += '>';
    else if (entity == "quot")
      out += '"';
    else if (entity == "apos")
      out += '\'';
    else if (entity.size() > 1 && entity[0] == '#') {
      const bool hex = entity[1] == 'x' || entity[1] == 'X';
      const long code = std::strtol(entity.c_str() + (hex ? 2 : 1), nullptr, hex ? 16 : 10);
      if (code > 0 && code < 0x80)
        out += static_cast<char>(code);
      else
        out += '?';  // names and numbers here are ASCII
    } else {
      fail("{}: malformed XML: unknown entity &{};", path, entity);
    }
    i = end;
  }
  return out;
}

// Every element of the document in order, with its attributes and parent. Throws Error naming
// the file for malformed markup (unclosed tags, mismatched end tags, unquoted attributes).
std::vector<XmlElement> parse_xml(const std::string& text, const std::string& path) {
  std::vector<XmlElement> elements;
  std::vector<int> open;
  size_t i = 0;
  const auto malformed = [&](const char* what) { fail("{}: malformed XML: {} (at byte {})", path, what, i); };
  while ((i = text.find('<', i)) != std::string::npos) {
    if (text.compare(i, 4, "<!--") == 0) {
      const size_t end = text.find("-->", i + 4);
      if (end == std::string::npos) malformed("unterminated comment");
      i = end + 3;
      continue;
    }
    if (text.compare(i, 2, "<?") == 0 || text.compare(i, 2, "<!") == 0) {
      const size_t end = text.find('>', i);
      if (end == std::string::npos) malformed("unterminated declaration");
      i = end + 1;
      continue;
    }
    const size_t end = text.find('>', i);
    if (end == std::string::npos) malformed("unterminated tag");
    std::string body = text.substr(i + 1, end - i - 1);
    if (!body.empty() && body[0] == '/') {
      const std::string tag = body.substr(1, body.find_first_of(" \t\r\n", 1) - 1);
      if (open.empty() || elements[open.back()].tag != tag) malformed("mismatched end tag");
      open.pop_back();
      i = end + 1;
      continue;
    }
    const bool self_closing = !body.empty() && body.back() == '/';
    if (self_closing) body.pop_back();
    XmlElement element;
    size_t k = body.find_first_of(" \t\r\n");
    element.tag = body.substr(0, k);
    if (element.tag.empty()) malformed("empty tag");
    while (k != std::string::npos && k < body.size()) {
      k = body.find_first_not_of(" \t\r\n", k);
      if (k == std::string::npos) break;
      const size_t eq = body.find('=', k);
      if (eq == std::string::npos) malformed("attribute without a value");
      std::string name = body.substr(k, eq - k);
      name.erase(name.find_last_not_of(" \t\r\n") + 1);
      size_t q = body.find_first_not_of(" \t\r\n", eq + 1);
      if (q == std::string::npos || (body[q] != '"' && body[q] != '\'')) malformed("unquoted attribute");
      const size_t close = body.find(body[q], q + 1);
      if (close == std::string::npos) malformed("unterminated attribute");
      element.attributes[name] = xml_unescape(body.substr(q + 1, close - q - 1), path);
      k = close + 1;
    }
    element.parent = open.empty() ? -1 : open.back();
    if (element.parent >= 0) elements[element.parent].children.push_back(static_cast<int>(elements.size()));
    elements.push_back(std::move(element));
    if (!self_closing) open.push_back(static_cast<int>(elements.size()) - 1);
    i = end + 1;
  }
  if (!open.empty()) fail("{}: malformed XML: <{}> is never closed", path, elements[open.back()].tag);
  return elements;
}

std::string attribute(const XmlElement& e, const std::string& name) {
  const auto it = e.attributes.find(name);
  return it == e.attributes.end() ? "" : it->second;
}

// One number or a colour: "x" or "r, g, b" (commas and/or spaces).
std::vector<double> parse_numbers(const std::string& text, const std::string& what, const std::string& path) {
  std::string spaced = text;
  std::replace(spaced.begin(), spaced.end(), ',', ' ');
  std::istringstream in(spaced);
  std::vector<double> values;
  std::string token;
  while (in >> token) {
    char* end = nullptr;
    const double x = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0' || !std::isfinite(x))
      fail("{}: {}: '{}' is not a number", path, what, text);
    values.push_back(x);
  }
  if (values.size() != 1 && values.size() != 3) fail("{}: {}: '{}' is not one number or three", path, what, text);
  return values;
}

// Sets the named parameter (a colour takes one value for every channel, or three), inside the
// model's bounds: a value outside them is clamped with a warning.
void set_parameter(const Model& model, Material& material, const std::string& param, const std::vector<double>& value,
                   const std::string& path, std::vector<std::string>& warnings) {
  const ParamSpec& p = *model.find_parameter(param);
  const int offset = model.offset_of(param);
  for (int c = 0; c < p.channels; ++c) {
    double x = value.size() == 3 ? value[c] : value[0];
    if (x < p.lower || x > p.upper) {
      warnings.push_back(fmt::format("{}: {} of '{}' is {}, outside the {} model's [{}, {}]: clamped", path, param,
                                     material.name, x, model.name(), p.lower, p.upper));
      x = std::clamp(x, p.lower, p.upper);
    }
    material.values[offset + c] = x;
  }
}

std::vector<double> json_numbers(const nlohmann::json& j, size_t count, const std::string& what,
                                 const std::string& path) {
  std::vector<double> values;
  if (j.is_number())
    values.push_back(j.get<double>());
  else if (j.is_array())
    for (const nlohmann::json& x : j) {
      if (!x.is_number()) fail("{}: {} holds a non-number", path, what);
      values.push_back(x.get<double>());
    }
  else
    fail("{}: {} is not a number or an array of numbers", path, what);
  if (values.size() < count) fail("{}: {} has {} values, expected {}", path, what, values.size(), count);
  values.resize(count);
  return values;
}

// KHR_materials_ior's ior = 0, which the extension allows: ((ior-1)/(ior+1))² = 1, so the
// dielectric has F0 = min(specularColor, 1)·specular per channel and F90 = specular (a Fresnel
// of 1 when both are 1). The gltf-specular model's ior lies in [1, 3] (((ior-1)/(ior+1))² up to
// 1/4), so the material is read as one the model holds exactly, where there is one:
//  - specular 0: no dielectric reflection at any ior: ior 1.5;
//  - every min(specularColor, 1) ≤ 1/4: ior 3 and specularColor·4, the same F0 and F90;
//  - specular 1 and specularColor ≥ 1: F = 1 for the dielectric and no diffuse under it, so the
//    dielectric is the glTF metal of base colour 1 and (1-m)·1 + m·Schlick(b) = Schlick(m·b + 1-m):
//    metallic 1 with base colour m·b + 1 - m;
// otherwise no brdffit model holds it (openpbr's specular_ior is within [1, 3] too, principled's
// F0 at most 0.08), and the file is refused naming the material.
void read_fresnel_one(const Model& model, Material& material, double specular,
                      const std::vector<double>& specular_color, const std::string& path, const std::string& where,
                      std::vector<std::string>& warnings) {
  Rgb<double> f0;  // before the specular weight
  for (int c = 0; c < 3; ++c) f0[c] = std::min(std::max(specular_color[c], 0.0), 1.0);
  const std::string what =
      fmt::format("{}: {} has KHR_materials_ior ior 0 (a dielectric F0 of specularColor)", path, where);
  if (specular == 0.0) {
    set_parameter(model, material, "ior", {1.5}, path, warnings);
    warnings.push_back(what + " with specularFactor 0, which reflects nothing at any ior: read exactly as ior 1.5");
  } else if (f0.maxCoeff() <= 0.25) {
    set_parameter(model, material, "ior", {3.0}, path, warnings);
    set_parameter(model, material, "specularColor", {4 * f0[0], 4 * f0[1], 4 * f0[2]}, path, warnings);
    warnings.push_back(what + ": read exactly as ior 3 with specularColorFactor times 4 (the same F0)");
  } else if (specular == 1.0 && f0.minCoeff() == 1.0) {
    const int base = model.offset_of("baseColor"), metallic = model.offset_of("metallic");
    const double m = material.values[metallic];
    // Written 1 - m(1 - b): within [0, 1] in floating point by construction, as the model requires.
    for (int c = 0; c < 3; ++c) material.values[base + c] = 1.0 - m * (1.0 - material.values[base + c]);
    material.values[metallic] = 1.0;
    warnings.push_back(what + " with specular 1: a Fresnel of 1, read exactly as metallic 1 with baseColor " +
                       "metallic·baseColor + 1 - metallic");
  } else {
    fail(
        "{}: {} has KHR_materials_ior ior 0 (Fresnel 1): a dielectric F0 of {:.4g}, {:.4g}, {:.4g} and F90 {:.4g}, "
        "which no brdffit model holds (their ior is within [1, 3]: F0 up to 0.25). It is held exactly with "
        "specularFactor 0, with specularFactor 1 and specularColorFactor 1, or with specularColorFactor up to 0.25",
        path, where, specular * f0[0], specular * f0[1], specular * f0[2], specular);
  }
}

// KHR_materials_clearcoat's factors (defaults 0) into the gltf+clearcoat model (or gltf+clearcoat+sheen). A roughness
// below the model's bound (the extension's default 0) is clamped with a warning, silently when the factor is 0: the
// coat is then off, whatever its roughness.
void read_clearcoat(const Model& model, Material& material, const nlohmann::json& coat, const std::string& path,
                    const std::string& where, std::vector<std::string>& warnings) {
  const double factor =
      json_numbers(coat.value("clearcoatFactor", nlohmann::json(0.0)), 1, where + " clearcoatFactor", path)[0];
  const double roughness = json_numbers(coat.value("clearcoatRoughnessFactor", nlohmann::json(0.0)), 1,
                                        where + " clearcoatRoughnessFactor", path)[0];
  set_parameter(model, material, "clearcoatFactor", {factor}, path, warnings);
  if (factor == 0.0) {
    const ParamSpec& p = *model.find_parameter("clearcoatRoughnessFactor");
    material.values[model.offset_of(p.name)] = std::clamp(roughness, p.lower, p.upper);
  } else {
    set_parameter(model, material, "clearcoatRoughnessFactor", {roughness}, path, warnings);
  }
  for (const char* texture : {"clearcoatTexture", "clearcoatRoughnessTexture", "clearcoatNormalTexture"})
    if (coat.contains(texture))
      warnings.push_back(fmt::format("{}: {} has a {}: only the factors are scored", path, where, texture));
}

// KHR_materials_sheen's factors (defaults 0) into the gltf+sheen model (or gltf+clearcoat+sheen). A
// roughness below the model's bound 0.1 (the extension's default 0) is clamped with a warning,
// silently when the colour is 0: the sheen is then off, whatever its roughness.
void read_sheen(const Model& model, Material& material, const nlohmann::json& sheen, const std::string& path,
                const std::string& where, std::vector<std::string>& warnings) {
  const std::vector<double> colour = json_numbers(sheen.value("sheenColorFactor", nlohmann::json{0.0, 0.0, 0.0}), 3,
                                                  where + " sheenColorFactor", path);
  const double roughness = json_numbers(sheen.value("sheenRoughnessFactor", nlohmann::json(0.0)), 1,
                                        where + " sheenRoughnessFactor", path)[0];
  set_parameter(model, material, "sheenColorFactor", colour, path, warnings);
  if (std::all_of(colour.begin(), colour.end(), [](double c) { return c == 0.0; })) {
    const ParamSpec& p = *model.find_parameter("sheenRoughnessFactor");
    material.values[model.offset_of(p.name)] = std::clamp(roughness, p.lower, p.upper);
  } else {
    set_parameter(model, material, "sheenRoughnessFactor", {roughness}, path, warnings);
  }
  for (const char* texture : {"sheenColorTexture", "sheenRoughnessTexture"})
    if (sheen.contains(texture))
      warnings.push_back(fmt::format("{}: {} has a {}: only the factors are scored", path, where, texture));
}

// One entry of a glTF file's "materials" (an object). A material with KHR_materials_clearcoat,
// KHR_materials_sheen or both is read as gltf+clearcoat, gltf+sheen or gltf+clearcoat+sheen, unless
// it also has KHR_materials_ior or KHR_materials_specular, which gltf-specular holds (no model holds
// both: the coat and sheen are then reported as left out).
Material read_gltf_material(const nlohmann::json& m, int index, const std::string& path,
                            std::vector<std::string>& warnings) {
  const nlohmann::json extensions = m.value("extensions", nlohmann::json::object());
  const bool has_specular = extensions.contains("KHR_materials_ior") || extensions.contains("KHR_materials_specular");
  const bool has_clearcoat = !has_specular && extensions.contains("KHR_materials_clearcoat");
  const bool has_sheen = !has_specular && extensions.contains("KHR_materials_sheen");
  const Model& model = *find_model(has_specular    ? "gltf-specular"
                                   : has_clearcoat ? (has_sheen ? "gltf+clearcoat+sheen" : "gltf+clearcoat")
                                   : has_sheen     ? "gltf+sheen"
                                                   : "gltf");
  Material material{m.value("name", fmt::format("material {}", index)), model.name(), model.default_values()};
  // glTF's defaults where a factor is absent: baseColor 1, metallic 1, roughness 1.
  const nlohmann::json pbr = m.value("pbrMetallicRoughness", nlohmann::json::object());
  const std::string where = fmt::format("material '{}'", material.name);
  set_parameter(model, material, "baseColor",
                json_numbers(pbr.value("baseColorFactor", nlohmann::json{1.0, 1.0, 1.0, 1.0}), 3,
                             where + " baseColorFactor", path),
                path, warnings);
  set_parameter(model, material, "metallic",
                json_numbers(pbr.value("metallicFactor", nlohmann::json(1.0)), 1, where + " metallicFactor", path),
                path, warnings);
  set_parameter(model, material, "roughness",
                json_numbers(pbr.value("roughnessFactor", nlohmann::json(1.0)), 1, where + " roughnessFactor", path),
                path, warnings);
  if (has_specular) {
    const nlohmann::json ior_extension = extensions.value("KHR_materials_ior", nlohmann::json::object());
    const nlohmann::json spec = extensions.value("KHR_materials_specular", nlohmann::json::object());
    const double ior = json_numbers(ior_extension.value("ior", nlohmann::json(1.5)), 1, where + " ior", path)[0];
    const double specular =
        json_numbers(spec.value("specularFactor", nlohmann::json(1.0)), 1, where + " specularFactor", path)[0];
    const std::vector<double> specular_color = json_numbers(
        spec.value("specularColorFactor", nlohmann::json{1.0, 1.0, 1.0}), 3, where + " specularColorFactor", path);
    set_parameter(model, material, "specular", {specular}, path, warnings);
    set_parameter(model, material, "specularColor", specular_color, path, warnings);
    if (ior == 0.0)  // with the specular weight as read into the model's [0, 1]
      read_fresnel_one(model, material, material.values[model.offset_of("specular")], specular_color, path, where,
                       warnings);
    else
      set_parameter(model, material, "ior", {ior}, path, warnings);
  }
  if (has_clearcoat) read_clearcoat(model, material, extensions["KHR_materials_clearcoat"], path, where, warnings);
  if (has_sheen) read_sheen(model, material, extensions["KHR_materials_sheen"], path, where, warnings);
  for (const char* texture : {"baseColorTexture", "metallicRoughnessTexture"})
    if (pbr.contains(texture))
      warnings.push_back(fmt::format("{}: {} has a {}: only the factors are scored", path, where, texture));
  for (const auto& [name, value] : extensions.items())
    if (name != "KHR_materials_ior" && name != "KHR_materials_specular" &&
        !(has_clearcoat && name == "KHR_materials_clearcoat") && !(has_sheen && name == "KHR_materials_sheen"))
      warnings.push_back(
          fmt::format("{}: {} uses {}, which the {} model it is read as leaves out", path, where, name, model.name()));
  return material;
}

std::vector<Material> read_gltf(const std::string& path, std::vector<std::string>& warnings) {
  const std::string text = read_material_file(path);
  check_json_depth(text, path, "glTF (JSON) file");
  nlohmann::json gltf;
  try {
    gltf = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    fail("{}: not a glTF (JSON) file: {}", path, e.what());
  }
  if (!gltf.is_object() || !gltf.contains("materials") || !gltf["materials"].is_array())
    fail("{}: a glTF file without materials", path);
  std::vector<Material> materials;
  int index = 0;
  for (const nlohmann::json& m : gltf["materials"]) {
    if (!m.is_object()) fail("{}: materials[{}]: expected an object, found {}", path, index, m.type_name());
    try {
      materials.push_back(read_gltf_material(m, index, path, warnings));
    } catch (const nlohmann::json::exception& e) {
      // A field of the wrong type (e.g. "name": 3): named by the material and nlohmann's words.
      fail("{}: materials[{}]: {}", path, index, e.what());
    }
    ++index;
  }
  return materials;
}

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

std::vector<Material> read_materialx(const std::string& path, std::vector<std::string>& warnings) {
  const std::vector<XmlElement> elements = parse_xml(read_material_file(path), path);
  if (elements.empty() || elements[0].tag != "materialx") fail("{}: not a MaterialX document (<materialx>)", path);
  const Model& model = *find_model("openpbr");
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
    Material material{named != material_of_shader.end() ? named->second : shader, model.name(), model.default_values()};
    // The specification's defaults where an input is absent (they differ from the fit's starts).
    set_parameter(model, material, "base_color", {0.8}, path, warnings);
    set_parameter(model, material, "specular_roughness", {0.3}, path, warnings);
    double base_weight = 1.0, specular_weight = 1.0;
    for (const int k : elements[i].children) {
      if (elements[k].tag != "input") continue;
      const std::string name = attribute(elements[k], "name");
      if (!attribute(elements[k], "nodename").empty() || !attribute(elements[k], "nodegraph").empty()) {
        warnings.push_back(
            fmt::format("{}: {} of '{}' is connected to a node: left at its default", path, name, material.name));
        continue;
      }
      const std::vector<double> value = parse_numbers(attribute(elements[k], "value"), name, path);
      if (name == "base_weight")
        base_weight = value[0];
      else if (name == "specular_weight")
        specular_weight = value[0];
      else if (model.find_parameter(name))
        set_parameter(model, material, name, value, path, warnings);
      else if (name == "specular_roughness_anisotropy" && value[0] != 0.0)
        warnings.push_back(fmt::format("{}: specular_roughness_anisotropy {} of '{}' is held at 0 by the openpbr model",
                                       path, value[0], material.name));
      else if (value.size() == 1 && value[0] != 0.0 && name.find("weight") != std::string::npos)
        warnings.push_back(fmt::format("{}: {} = {} of '{}' is outside the opaque base brdffit's openpbr model has",
                                       path, name, value[0], material.name));
    }
    fold_base_weight(model, material, std::clamp(base_weight, 0.0, 1.0), path, warnings);
    if (specular_weight != 1.0)
      warnings.push_back(fmt::format("{}: specular_weight {} of '{}' is held at 1 by the openpbr model: not scored",
                                     path, specular_weight, material.name));
    materials.push_back(std::move(material));
  }
  return materials;
}

// Mitsuba 3's principled BSDF as the mitsuba-principled model, whose parameters carry the plugin's names.
std::vector<Material> read_mitsuba(const std::string& path, std::vector<std::string>& warnings) {
  const std::vector<XmlElement> elements = parse_xml(read_material_file(path), path);
  if (elements.empty() || elements[0].tag != "scene") fail("{}: not a Mitsuba scene (<scene>)", path);
  const Model& model = *find_model("mitsuba-principled");
  std::vector<Material> materials;
  for (size_t i = 0; i < elements.size(); ++i) {
    if (elements[i].tag != "bsdf" || attribute(elements[i], "type") != "principled") continue;
    const std::string id = attribute(elements[i], "id");
    Material material{id.empty() ? fmt::format("bsdf {}", materials.size()) : id, model.name(), model.default_values()};
    // Mitsuba's defaults where a parameter is absent.
    const std::map<std::string, std::vector<double>> defaults = {
        {"base_color", {0.5}}, {"metallic", {0.0}},  {"roughness", {0.5}},
        {"specular", {0.5}},   {"spec_tint", {0.0}}, {"flatness", {0.0}},
        {"sheen", {0.0}},      {"clearcoat", {0.0}}, {"clearcoat_gloss", {0.0}}};
    for (const auto& [name, value] : defaults) set_parameter(model, material, name, value, path, warnings);
    double sheen_tint = 0.0;
    std::optional<double> eta;
    bool has_specular = false;
    for (const int k : elements[i].children) {
      const std::string name = attribute(elements[k], "name");
      if (elements[k].tag == "texture") {
        warnings.push_back(fmt::format("{}: {} of '{}' is a texture: left at its default", path, name, material.name));
        continue;
      }
      if (elements[k].tag != "rgb" && elements[k].tag != "float") continue;
      const std::vector<double> value = parse_numbers(attribute(elements[k], "value"), name, path);
      has_specular = has_specular || name == "specular";
      if (model.find_parameter(name))
        set_parameter(model, material, name, value, path, warnings);
      else if (name == "eta")
        eta = value[0];
      else if (name == "sheen_tint")
        sheen_tint = value[0];
      else if (value[0] != 0.0)
        warnings.push_back(fmt::format("{}: {} = {} of '{}' is not in brdffit's mitsuba-principled model (held at 0)",
                                       path, name, value[0], material.name));
    }
    if (eta) {
      // The plugin takes eta or specular, never both, and derives one from the other:
      // η = 2/(1 - √(0.08·specular)) - 1, so specular = ((η-1)/(η+1))²/0.08, exactly.
      if (has_specular)
        fail("{}: '{}' gives both eta and specular, which Mitsuba refuses (one is derived from the other)", path,
             material.name);
      if (*eta <= 0.0) fail("{}: eta of '{}' is {}: an index of refraction is positive", path, material.name, *eta);
      const double r = (*eta - 1.0) / (*eta + 1.0);
      if (*eta < 1.0)
        warnings.push_back(fmt::format(
            "{}: eta {} of '{}' is below 1: read as the specular of 1/eta (the same F0), without the total internal "
            "reflection the plugin's Fresnel has beyond the critical angle",
            path, *eta, material.name));
      set_parameter(model, material, "specular", {r * r / 0.08}, path, warnings);
    }
    if (sheen_tint != 0.5 && material.values[model.offset_of("sheen")] > 0.0)
      warnings.push_back(fmt::format("{}: sheen_tint {} of '{}' is held at 0.5 by the mitsuba-principled model", path,
                                     sheen_tint, material.name));
    materials.push_back(std::move(material));
  }
  return materials;
}

}  // namespace

std::vector<Material> read_materials(const std::string& path, std::vector<std::string>& warnings) {
  const std::string extension = std::filesystem::path(path).extension().string();
  std::vector<Material> materials;
  if (extension == ".gltf")
    materials = read_gltf(path, warnings);
  else if (extension == ".mtlx")
    materials = read_materialx(path, warnings);
  else if (extension == ".xml")
    materials = read_mitsuba(path, warnings);
  else
    fail("{}: a material is read from .gltf, .mtlx (OpenPBR) or Mitsuba .xml (principled)", path);
  if (materials.empty())
    fail("{}: holds no {}", path,
         extension == ".gltf"   ? "material"
         : extension == ".mtlx" ? "open_pbr_surface"
                                : "principled bsdf");
  return materials;
}

Material read_material(const std::string& path, const std::string& name, std::vector<std::string>& warnings) {
  std::vector<Material> materials = read_materials(path, warnings);
  std::string names;
  for (const Material& m : materials) names += (names.empty() ? "" : ", ") + m.name;
  if (name.empty()) {
    if (materials.size() > 1)
      fail("{}: holds {} materials ({}): choose one with --name", path, materials.size(), names);
    return materials.front();
  }
  for (Material& m : materials)
    if (m.name == name) return m;
  fail("{}: has no material '{}' (it has: {})", path, name, names);
}

Material material_for_scoring(const std::string& path, const std::string& name, const std::string& model,
                              std::vector<std::string>& warnings) {
  Material material = read_material(path, name, warnings);
  if (model.empty() || model == material.model) return material;
  if (!find_model(model)) fail("unknown model '{}' (known: {})", model, model_names());
  warnings.push_back(fmt::format("the {} material '{}' is scored converted to {} (through the metallic-roughness core)",
                                 material.model, material.name, model));
  Material converted = convert_material(material.model, material.values, model);
  converted.name = material.name;
  return converted;
}

}  // namespace brdffit
