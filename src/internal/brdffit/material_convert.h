// What the conversion between renderer materials (material_convert.cc, described in
// material_export.h) shares with the material formats' files: the metallic-roughness core every
// renderer material has, the list of those materials, and reading a parameter by name.
#pragma once

#include <string>
#include <vector>

#include "brdffit/math.h"
#include "brdffit/model.h"

namespace brdffit {

// The models of glTF's material: the core, and the core with KHR extensions (gltf-specular's
// KHR_materials_ior and _specular, the layers of KHR_materials_clearcoat and _sheen). They share
// the core's parameters baseColor, metallic and roughness.
const std::vector<std::string>& gltf_models();
bool is_gltf_model(const std::string& name);

// The models of OpenPBR Surface: the opaque base and its coat and fuzz layers (models/openpbr_layers.h),
// which share the base's parameters.
const std::vector<std::string>& openpbr_models();
bool is_openpbr_model(const std::string& name);

// Every renderer material (the glTF models, the OpenPBR models, principled, mitsuba-principled):
// what a conversion writes.
const std::vector<std::string>& renderer_materials();
// What a conversion reads: ggx (through metallic_roughness) and every renderer material.
const std::vector<std::string>& convertible_models();

// The metallic-roughness core every renderer material shares, with the dielectric's reflection:
// F0 = specular_weight·((ior-1)/(ior+1))² (tinted by specular_color where the model has one).
// Each target keeps what it can hold of it: gltf-specular all three; openpbr the ior, folding the
// weight into it (same F0) and the tint; principled and mitsuba-principled F0 as specular = F0/0.08;
// gltf and its extension models none (ior 1.5). A source without them has weight 1 and tint 1.
// The layers over the core, a coat and a sheen, go with it where source and target both have one,
// by their meaning: gltf+clearcoat's clearcoatFactor and clearcoatRoughnessFactor are OpenPBR's
// coat_weight and coat_roughness (coat_ior 1.5, coat_color 1: the extension's coat), and
// gltf+sheen's sheenColorFactor is OpenPBR's fuzz_weight·fuzz_color (the strongest channel the
// weight), sheenRoughnessFactor its fuzz_roughness. Their formulas differ (KHR's Fresnel mix and
// Charlie sheen against MaterialX's albedo scaling and Zeltner's fuzz), so such a conversion is
// approximate (its error shows); a layer the target has not is left out.
struct Core {
  Rgb<double> base_color = Rgb<double>::Constant(0.5);
  double metallic = 0.0, roughness = 0.5, ior = 1.5;
  double specular_weight = 1.0;
  Rgb<double> specular_color = Rgb<double>::Ones();
  struct Coat {
    double weight = 0.0, roughness = 0.1, ior = 1.5;  // weight 0: none
    Rgb<double> color = Rgb<double>::Ones();
  } coat;
  struct Sheen {
    double weight = 0.0, roughness = 0.5;  // weight 0: none
    Rgb<double> color = Rgb<double>::Ones();
  } sheen;
};

// The core of a fit of a renderer material or ggx (the metallic-roughness match of
// material_export.h); throws Error for any other model.
Core core_of(const std::string& model_name, const std::vector<double>& values);

// The target's nesting of the source when both are renderer materials: the conversion then maps
// every parameter by name (principled → mitsuba-principled) instead of through the core. Null
// otherwise (a nesting of lambert or ggx is a fitting start, not a material).
const Nesting* nesting_of(const Model& target, const std::string& source_model);

// A parameter of `model` in its flattened `values`, by name: a colour, or one value.
Rgb<double> colour_at(const Model& model, const std::vector<double>& values, const char* name);
double value_at(const Model& model, const std::vector<double>& values, const char* name);

}  // namespace brdffit
