// glTF 2.0 (.gltf): the gltf model as the core metallic-roughness material, gltf-specular with
// KHR_materials_ior and KHR_materials_specular, gltf+clearcoat, gltf+sheen and
// gltf+clearcoat+sheen with KHR_materials_clearcoat, KHR_materials_sheen or both, gltf+anisotropy
// with KHR_materials_anisotropy, on a small sphere mesh so that any viewer shows it; and read back
// (material_export.h).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>

#include "brdffit/base64.h"
#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/material_convert.h"
#include "brdffit/material_export.h"
#include "brdffit/material_formats.h"
#include "brdffit/registry.h"
#include "brdffit/result_json.h"

namespace brdffit {

namespace {

template <class T>
void append_bytes(std::vector<uint8_t>& bytes, const T& value) {
  const auto* p = reinterpret_cast<const uint8_t*>(&value);
  bytes.insert(bytes.end(), p, p + sizeof(T));
}

// A unit UV sphere: positions (= normals), tangents, and triangles with a fan at each pole (no
// degenerate triangle), counter-clockwise seen from outside as glTF requires. The tangent runs
// along the longitude, ŷ × n normalised, with bitangent n × t (w = 1): the frame in which brdffit
// evaluates a model on a sphere (imaging/sphere.h's LocalFrame), x̂ at the poles.
struct SphereMesh {
  std::vector<float> positions;  // x, y, z per vertex
  std::vector<float> tangents;   // x, y, z, w per vertex
  std::vector<uint16_t> indices;
};

SphereMesh sphere_mesh(int rings = 16, int segments = 32) {
  SphereMesh mesh;
  const auto add = [&](double theta, double phi) {
    const bool pole = theta == 0.0 || theta == kPi;
    mesh.positions.push_back(static_cast<float>(std::sin(theta) * std::cos(phi)));
    mesh.positions.push_back(static_cast<float>(std::cos(theta)));
    mesh.positions.push_back(static_cast<float>(-std::sin(theta) * std::sin(phi)));
    // ŷ × n = (n_z, 0, -n_x) = sinθ·(-sin φ, 0, -cos φ).
    mesh.tangents.insert(mesh.tangents.end(), {pole ? 1.0f : static_cast<float>(-std::sin(phi)), 0.0f,
                                               pole ? 0.0f : static_cast<float>(-std::cos(phi)), 1.0f});
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

std::string gltf_document(const Material& material, const nlohmann::json& provenance) {
  const Model& model = *find_model(material.model);
  if (!is_gltf_model(material.model))
    fail("glTF holds a {} material, not {}", join_words(gltf_models(), "or"), material.model);
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
  // The stretch is relative to the mesh's TANGENT, which the extension then requires.
  const bool anisotropic = model.find_parameter("anisotropyStrength") != nullptr;
  if (anisotropic) {
    gltf_material["extensions"]["KHR_materials_anisotropy"] = {
        {"anisotropyStrength", value_at(model, v, "anisotropyStrength")},
        {"anisotropyRotation", value_at(model, v, "anisotropyRotation")}};
    extensions_used.push_back("KHR_materials_anisotropy");
  }

  // One buffer: positions, normals (the same unit vectors), 16-bit indices, then the tangents of
  // an anisotropic material.
  const SphereMesh mesh = sphere_mesh();
  std::vector<uint8_t> bytes;
  for (int copy = 0; copy < 2; ++copy)
    for (float x : mesh.positions) append_bytes(bytes, x);
  for (uint16_t i : mesh.indices) append_bytes(bytes, i);
  while (bytes.size() % 4) bytes.push_back(0);
  const size_t tangent_offset = bytes.size();
  if (anisotropic)
    for (float x : mesh.tangents) append_bytes(bytes, x);
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
  if (anisotropic) {
    gltf["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = 3;
    gltf["accessors"].push_back({{"bufferView", 3}, {"componentType", 5126}, {"count", vertices}, {"type", "VEC4"}});
    gltf["bufferViews"].push_back(
        {{"buffer", 0}, {"byteOffset", tangent_offset}, {"byteLength", vertices * 16}, {"target", 34962}});
  }
  if (!extensions_used.empty()) gltf["extensionsUsed"] = extensions_used;
  return gltf.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

namespace {

// The first `count` numbers of a number or an array of numbers (a baseColorFactor's alpha is
// left out); throws Error naming the file and `what` for anything else, or fewer.
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

// KHR_materials_anisotropy's strength and rotation (defaults 0) into the gltf+anisotropy model. The
// rotation is any angle in glTF; the lobe is the same turned by π, so it is brought into the
// model's interval of length π exactly.
void read_anisotropy(const Model& model, Material& material, const nlohmann::json& anisotropy, const std::string& path,
                     const std::string& where, std::vector<std::string>& warnings) {
  const double strength = json_numbers(anisotropy.value("anisotropyStrength", nlohmann::json(0.0)), 1,
                                       where + " anisotropyStrength", path)[0];
  const double rotation = json_numbers(anisotropy.value("anisotropyRotation", nlohmann::json(0.0)), 1,
                                       where + " anisotropyRotation", path)[0];
  set_parameter(model, material, "anisotropyStrength", {strength}, path, warnings);
  if (!std::isfinite(rotation)) fail("{}: {} anisotropyRotation is not a finite number", path, where);
  const ParamSpec& p = *model.find_parameter("anisotropyRotation");
  material.values[model.offset_of(p.name)] = p.lower + std::fmod(std::fmod(rotation - p.lower, kPi) + kPi, kPi);
  if (anisotropy.contains("anisotropyTexture"))
    warnings.push_back(fmt::format("{}: {} has an anisotropyTexture: only the factors are scored", path, where));
}

// One entry of a glTF file's "materials" (an object). A material with KHR_materials_clearcoat,
// KHR_materials_sheen or both is read as gltf+clearcoat, gltf+sheen or gltf+clearcoat+sheen, unless
// it also has KHR_materials_ior or KHR_materials_specular, which gltf-specular holds (no model holds
// both: the coat and sheen are then reported as left out). One with KHR_materials_anisotropy and
// none of those is read as gltf+anisotropy; with any of them, its anisotropy is reported as left out.
Material read_gltf_material(const nlohmann::json& m, int index, const std::string& path,
                            std::vector<std::string>& warnings) {
  const nlohmann::json extensions = m.value("extensions", nlohmann::json::object());
  const bool has_specular = extensions.contains("KHR_materials_ior") || extensions.contains("KHR_materials_specular");
  const bool has_clearcoat = !has_specular && extensions.contains("KHR_materials_clearcoat");
  const bool has_sheen = !has_specular && extensions.contains("KHR_materials_sheen");
  const bool has_anisotropy =
      !has_specular && !has_clearcoat && !has_sheen && extensions.contains("KHR_materials_anisotropy");
  const Model& model = *find_model(has_specular     ? "gltf-specular"
                                   : has_clearcoat  ? (has_sheen ? "gltf+clearcoat+sheen" : "gltf+clearcoat")
                                   : has_sheen      ? "gltf+sheen"
                                   : has_anisotropy ? "gltf+anisotropy"
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
  if (has_anisotropy) read_anisotropy(model, material, extensions["KHR_materials_anisotropy"], path, where, warnings);
  for (const char* texture : {"baseColorTexture", "metallicRoughnessTexture"})
    if (pbr.contains(texture))
      warnings.push_back(fmt::format("{}: {} has a {}: only the factors are scored", path, where, texture));
  for (const auto& [name, value] : extensions.items())
    if (name != "KHR_materials_ior" && name != "KHR_materials_specular" &&
        !(has_clearcoat && name == "KHR_materials_clearcoat") && !(has_sheen && name == "KHR_materials_sheen") &&
        !(has_anisotropy && name == "KHR_materials_anisotropy"))
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

// A fit of another model becomes gltf, with the clear coat and sheen of an openpbr+coat or +fuzz
// source (material_convert.h), unless its dielectric is not the core's (IOR 1.5, weight 1, no
// tint), which only gltf-specular's KHR_materials_ior and KHR_materials_specular hold (without
// layers: no model holds both).
std::string gltf_conversion_target(const std::string& source_model, const std::vector<double>& values) {
  const Core core = core_of(source_model, values);
  const bool core_dielectric =
      std::abs(core.ior - 1.5) < 1e-9 && core.specular_weight == 1.0 && core.specular_color == Rgb<double>::Ones();
  if (!core_dielectric) return "gltf-specular";
  return std::string("gltf") + (core.coat.weight > 0.0 ? "+clearcoat" : "") + (core.sheen.weight > 0.0 ? "+sheen" : "");
}

std::string write_gltf(const Material& material, const MaterialProvenance& provenance) {
  return gltf_document(material, provenance.fields);
}

}  // namespace

MaterialFormatInfo gltf_format() {
  return {MaterialFormat::Gltf,   "gltf",     "glTF 2.0", ".gltf", ".gltf", "material",
          gltf_models(),  // the core first: what most viewers read
          gltf_conversion_target, write_gltf, read_gltf};
}

}  // namespace brdffit
