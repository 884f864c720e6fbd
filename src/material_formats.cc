// The table of material formats and what looks formats up in it: by name, by a file's
// extension, to read a file (material_export.h). Each format's entry is in its own file under
// formats/ (material_formats.h).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/material_export.h"
#include "brdffit/material_formats.h"
#include "brdffit/registry.h"

namespace brdffit {

const std::vector<MaterialFormatInfo>& material_formats() {
  static const std::vector<MaterialFormatInfo> formats = {gltf_format(), openpbr_format(), mitsuba_format()};
  return formats;
}

namespace {

// The format whose files end in `extension`, if any.
const MaterialFormatInfo* format_of_extension(const std::string& extension) {
  for (const MaterialFormatInfo& info : material_formats())
    if (extension == info.extension) return &info;
  return nullptr;
}

}  // namespace

std::string material_format_list(const char* MaterialFormatInfo::*field) {
  std::vector<std::string> words;
  for (const MaterialFormatInfo& info : material_formats()) words.push_back(info.*field);
  return join_words(words, "or");
}

const MaterialFormatInfo& material_format_info(MaterialFormat format) {
  for (const MaterialFormatInfo& info : material_formats())
    if (info.format == format) return info;
  fail("material format {} has no entry in material_formats()", static_cast<int>(format));
}

const char* material_format_name(MaterialFormat format) { return material_format_info(format).name; }

std::vector<std::string> native_models(MaterialFormat format) { return material_format_info(format).native_models; }

MaterialFormat material_format(const std::string& name, const std::string& path) {
  const std::string extension = std::filesystem::path(path).extension().string();
  const MaterialFormatInfo* implied = format_of_extension(extension);
  const std::string names = material_format_list(&MaterialFormatInfo::name);
  if (name.empty()) {
    if (implied) return implied->format;
    fail("--format: {} (not implied by the name {}: {})", names, path,
         material_format_list(&MaterialFormatInfo::extension));
  }
  for (const MaterialFormatInfo& info : material_formats()) {
    if (name != info.name) continue;
    // A file named for one format holding another would be misread by every tool that opens it.
    if (implied && implied != &info)
      fail(
          "--format {} conflicts with the output {}, whose extension {} is the {} format's: leave out --format, or "
          "name the output for {}",
          name, path, extension, implied->name, name);
    return info.format;
  }
  fail("--format: {}, not '{}'", names, name);
}

// The readers' helpers (material_formats.h).

std::string read_material_file(const std::string& path) { return read_file(path, kMaxMaterialFileBytes); }

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

std::vector<Material> read_materials(const std::string& path, std::vector<std::string>& warnings) {
  const MaterialFormatInfo* format = format_of_extension(std::filesystem::path(path).extension().string());
  if (!format) fail("{}: a material is read from {}", path, material_format_list(&MaterialFormatInfo::files));
  std::vector<Material> materials = format->read(path, warnings);
  if (materials.empty()) fail("{}: holds no {}", path, format->element);
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
