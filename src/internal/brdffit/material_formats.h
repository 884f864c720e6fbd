// What the material formats' files (src/formats/*.cc) share with the table that lists them
// (material_formats.cc): each format's entry, and the helpers of their readers.
#pragma once

#include <string>
#include <vector>

#include "brdffit/material_export.h"
#include "brdffit/model.h"

namespace brdffit {

// Each format's entry of material_formats(), defined in its own file.
MaterialFormatInfo gltf_format();     // formats/gltf.cc
MaterialFormatInfo openpbr_format();  // formats/openpbr_mtlx.cc
MaterialFormatInfo mitsuba_format();  // formats/mitsuba_xml.cc

// A material file, read whole: refused above kMaxMaterialFileBytes, far above any real one, so
// that reading stays bounded.
std::string read_material_file(const std::string& path);

// One number or a colour: "x" or "r, g, b" (commas and/or spaces); throws Error naming the file
// and `what` otherwise.
std::vector<double> parse_numbers(const std::string& text, const std::string& what, const std::string& path);

// Sets the named parameter (a colour takes one value for every channel, or three), inside the
// model's bounds: a value outside them is clamped with a warning.
void set_parameter(const Model& model, Material& material, const std::string& param, const std::vector<double>& value,
                   const std::string& path, std::vector<std::string>& warnings);

}  // namespace brdffit
