// For the material import targets (fuzz_gltf, fuzz_mtlx, fuzz_mitsuba): any bytes read as a
// material file either raise brdffit::Error or give materials of a known model, each with
// exactly that model's values, finite and within the parameters' bounds (import clamps), so
// that scoring them stays finite.
#pragma once

#include <cmath>
#include <cstdlib>

#include "brdffit/error.h"
#include "brdffit/material_export.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"
#include "fuzz_file.h"

namespace brdffit::fuzz {

inline int read_material_file(const char* name, const char* extension, const uint8_t* data, size_t size) {
  const std::string path = input_file(name, extension, data, size);
  try {
    std::vector<std::string> warnings;
    for (const Material& material : read_materials(path, warnings)) {
      const Model* model = find_model(material.model);
      if (!model || static_cast<int>(material.values.size()) != model->num_values()) std::abort();
      size_t i = 0;
      for (const ParamSpec& p : model->parameters())
        for (int c = 0; c < p.channels; ++c, ++i)
          if (!(material.values[i] >= p.lower && material.values[i] <= p.upper)) std::abort();
    }
  } catch (const Error&) {
  }
  return 0;
}

}  // namespace brdffit::fuzz
