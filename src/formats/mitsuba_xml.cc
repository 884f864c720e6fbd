// Mitsuba 3's principled BSDF in a scene file (.xml): the mitsuba-principled model, whose
// parameters carry the plugin's names, written and read back (material_export.h).
#include <fmt/format.h>

#include <map>
#include <optional>

#include "brdffit/error.h"
#include "brdffit/material_export.h"
#include "brdffit/material_formats.h"
#include "brdffit/registry.h"
#include "brdffit/text.h"
#include "brdffit/xml_reader.h"

namespace brdffit {

std::string mitsuba_document(const Material& material, const std::string& comment) {
  if (material.model != "mitsuba-principled")
    fail("Mitsuba's principled BSDF holds a mitsuba-principled material, not {}", material.model);
  const Model& model = *find_model(material.model);
  const std::vector<double>& v = material.values;
  const std::string id = xml_name(material.name);
  std::string xml = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n";
  xml += "<!-- " + xml_comment_text(comment) +
         "\n     anisotropic 0 as brdffit's mitsuba-principled model holds it."
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
  xml += "        <float name=\"anisotropic\" value=\"0\"/>\n";
  xml += "    </bsdf>\n</scene>\n";
  return xml;
}

namespace {

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
        {"base_color", {0.5}}, {"metallic", {0.0}},       {"roughness", {0.5}}, {"specular", {0.5}},
        {"spec_tint", {0.0}},  {"flatness", {0.0}},       {"sheen", {0.0}},     {"sheen_tint", {0.0}},
        {"clearcoat", {0.0}},  {"clearcoat_gloss", {0.0}}};
    for (const auto& [name, value] : defaults) set_parameter(model, material, name, value, path, warnings);
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
    materials.push_back(std::move(material));
  }
  return materials;
}

std::string write_mitsuba(const Material& material, const MaterialProvenance& provenance) {
  return mitsuba_document(material, provenance.comment);
}

}  // namespace

MaterialFormatInfo mitsuba_format() {
  return {MaterialFormat::Mitsuba,
          "mitsuba",
          "Mitsuba 3 principled",
          ".xml",
          "Mitsuba .xml (principled)",
          "principled bsdf",
          {"mitsuba-principled"},
          nullptr,
          write_mitsuba,
          read_mitsuba};
}

}  // namespace brdffit
