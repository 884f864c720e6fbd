// Renderer materials from fits: the library side of `brdffit export`, and of `score --material`.
//
// A fit of a renderer's own BRDF is written unchanged:
//   glTF 2.0 (.gltf)        the `gltf` fit (core metallic-roughness), the `gltf-specular` fit
//                           (with KHR_materials_ior and KHR_materials_specular), the
//                           `gltf+clearcoat`, `gltf+sheen` or `gltf+clearcoat+sheen` fit (with
//                           KHR_materials_clearcoat, KHR_materials_sheen or both), on a small
//                           sphere mesh so that any viewer shows it;
//   OpenPBR (.mtlx)         the `openpbr` fit, or the `openpbr+coat`, `openpbr+fuzz` or
//                           `openpbr+coat+fuzz` fit (with its coat and fuzz inputs), as a MaterialX
//                           document with an open_pbr_surface;
//   Mitsuba 3 (.xml)        the `mitsuba-principled` fit as Mitsuba's `principled` BSDF (the model is
//                           what that plugin evaluates; anisotropic 0 as held).
// Any other renderer model's fit, or a ggx fit, can be converted instead: the materials share a
// metallic-roughness core (base colour, metallic, roughness, and the dielectric's IOR, specular
// weight and tint), of which the target keeps all it can hold (gltf-specular all; openpbr the IOR
// with the weight folded in, and the tint; principled and mitsuba-principled the dielectric F0 as
// specular = F0/0.08; gltf neither: into glTF, a fit whose dielectric is not the core's IOR 1.5,
// weight 1 and no tint becomes gltf-specular), with every other parameter at the target's default. A ggx
// fit's core is the metallic-roughness match below. A converted material is not what was fitted,
// so its error on the original data is computed and reported beside the fit's own, with its
// difference from the fit on a fixed set of directions. A target that nests the source model converts parameter by
// parameter instead: a `principled` fit (Burley's formulas) becomes a `mitsuba-principled` material of the same values,
// which Mitsuba renders differently (exact Fresnel, Rec. 709 tints, its clearcoat normalisation).
//
// ggx → metallic-roughness (models/ggx.h: f = albedo/π + D·F·G/(4 n·l n·v), F Schlick of f0):
//   glTF's material at normal incidence has diffuse reflectance (1-m)·0.96·base and specular F0
//   0.04·(1-m) + m·base. Requiring both to equal the fit's albedo a and f0 f for the luminance
//   (Rec. 709) of each colour gives, with t = 1 - m, 0.0384 t² - (a + 0.96 f) t + a = 0, a root of
//   which is t = 1 for a dielectric (f = 0.04) and t = 0 for a metal (a = 0); when both lie in
//   [0, 1] the larger is taken (the least metallic match); no real root: m = 0. Then per channel
//   the base colour b in [0, 1] that best matches both equations (least squares):
//   b = ((1-m)·0.96·a + m·(f - 0.04(1-m))) / (((1-m)·0.96)² + m²).
#pragma once

#include <string>
#include <vector>

#include "brdffit/math.h"
#include "brdffit/metric.h"
#include "brdffit/result_json.h"

namespace brdffit {

struct MetallicRoughness {
  Rgb<double> base_color = Rgb<double>::Zero();
  double metallic = 0.0;
  double roughness = 0.5;
  // What the material implies at normal incidence (see above), to compare with the fit.
  Rgb<double> albedo = Rgb<double>::Zero();
  Rgb<double> f0 = Rgb<double>::Zero();
};

MetallicRoughness metallic_roughness(const Rgb<double>& albedo, const Rgb<double>& f0, double roughness);

// The material formats: MaterialFormat names one, material_formats() describes each (see
// MaterialFormatInfo below). Adding a format: docs/architecture.md, "Adding a material format".
enum class MaterialFormat { Gltf, OpenPbr, Mitsuba };
const char* material_format_name(MaterialFormat format);
// The format named (gltf, openpbr, mitsuba), or when `name` is empty the one implied by the
// path's extension (.gltf, .mtlx, .xml); throws Error otherwise, and when the name and the
// extension imply different formats.
MaterialFormat material_format(const std::string& name, const std::string& path);
// The models a format writes unchanged (gltf: gltf, gltf-specular, gltf+clearcoat, gltf+sheen,
// gltf+clearcoat+sheen).
std::vector<std::string> native_models(MaterialFormat format);

// A material of one of the renderer models (gltf, gltf-specular, gltf+clearcoat, gltf+sheen,
// gltf+clearcoat+sheen, openpbr, principled, mitsuba-principled).
struct Material {
  std::string name;
  std::string model;
  std::vector<double> values;  // flattened, in the model's parameter order
};

// The material `model` (a renderer model) closest to `source_model` with `values`, through their
// shared metallic-roughness core (see above). Throws Error when source_model has no core.
Material convert_material(const std::string& source_model, const std::vector<double>& values, const std::string& model);

struct ExportRequest {
  MaterialFormat format = MaterialFormat::Gltf;
  std::string model;   // the fit to export; empty: the format's own model
  bool force = false;  // export a fit whose verdict is poor or failed (with a warning)
};

struct MaterialExport {
  Material material;
  std::string source_model;  // the fit the material comes from
  bool converted = false;    // material.model differs from source_model
  std::string metric;        // the document's metric
  double fit_error = NAN;    // the fit's own error, from the document
  // Converted materials: both errors on the original data, all samples (NaN when it could not
  // be read; a warning then says why).
  double converted_error = NAN, source_error_on_data = NAN;
  // Converted materials: the metric of the material against the fit's own shaded values on fixed
  // directions (20,000 pairs uniform in solid angle, from a fixed seed): needs no data, so it is
  // there when the original data cannot be read.
  double converted_vs_fit = NAN;
  std::string conversion;  // "unchanged", "parameter by parameter (...)" or "through the metallic-roughness core"
  std::vector<std::string> warnings;
  std::string text;  // the file's contents
};

// Chooses the fit, refuses a poor or failed verdict without request.force, converts when asked
// and writes the file's text. Throws Error naming the document for anything it cannot export.
MaterialExport export_material(const FitDocument& document, const ExportRequest& request);

// The files for one material; `provenance` goes into the glTF extras and the XML comment.
std::string gltf_document(const Material& material, const nlohmann::json& provenance);
std::string materialx_document(const Material& material, const std::string& comment);
std::string mitsuba_document(const Material& material, const std::string& comment);

// Where an exported material comes from, as its file records it: glTF in the material's extras
// (`fields`), the XML formats in a comment (`comment`, one sentence).
struct MaterialProvenance {
  nlohmann::json fields;
  std::string comment;
};

// One material format: everything export, import and the command line need of it. Each format's
// entry, writer and reader are in its own file under src/formats/.
struct MaterialFormatInfo {
  MaterialFormat format;
  const char* name;       // what --format accepts: "gltf"
  const char* title;      // for help texts: "glTF 2.0"
  const char* extension;  // of the files it writes and reads: ".gltf"
  const char* files;      // its files in messages and help texts: ".gltf", "Mitsuba .xml (principled)"
  const char* element;    // what a file holds one of per material: "material", "open_pbr_surface"
  // The models it writes unchanged, in the order export looks for a fit of them; the first is the
  // one it is named for.
  std::vector<std::string> native_models;
  // The native model a fit of another model is converted to; null: the first native model.
  std::string (*conversion_target)(const std::string& source_model, const std::vector<double>& values);
  // The file's text for a material of a native model; throws Error for another model.
  std::string (*write)(const Material& material, const MaterialProvenance& provenance);
  // Every material of the file at `path`, each as a native model, with warnings for what the model
  // leaves out (see read_materials); throws Error naming the file.
  std::vector<Material> (*read)(const std::string& path, std::vector<std::string>& warnings);
};

// Every format, in the order help texts and messages list them.
const std::vector<MaterialFormatInfo>& material_formats();
const MaterialFormatInfo& material_format_info(MaterialFormat format);
// One field of every format for a sentence: material_format_list(&MaterialFormatInfo::name) is
// "gltf, openpbr or mitsuba".
std::string material_format_list(const char* MaterialFormatInfo::*field);

// The largest material file read_materials reads (a real one is a few kilobytes).
constexpr uint64_t kMaxMaterialFileBytes = uint64_t{16} << 20;

// Materials read back from a .gltf, .mtlx or Mitsuba .xml file, each as the matching model
// (gltf, gltf-specular, gltf+clearcoat, gltf+sheen or gltf+clearcoat+sheen; openpbr, openpbr+coat, openpbr+fuzz or
// openpbr+coat+fuzz, the smallest holding the layers whose weight is not 0; mitsuba-principled). Inputs the model does
// not have (textures, transmission, ...) or holds fixed are reported in `warnings`. Throws Error naming the file
// when it is not one of these formats, is larger than kMaxMaterialFileBytes or holds no material. Time and memory are
// linear in the file's size.
std::vector<Material> read_materials(const std::string& path, std::vector<std::string>& warnings);
// The material called `name` (empty: the file's only material); throws Error naming the file
// and the materials it has otherwise.
Material read_material(const std::string& path, const std::string& name, std::vector<std::string>& warnings);

// What `score --material` evaluates: the material called `name` in `path`, converted to `model`
// when that is given and differs (with a warning saying so).
Material material_for_scoring(const std::string& path, const std::string& name, const std::string& model,
                              std::vector<std::string>& warnings);

}  // namespace brdffit
