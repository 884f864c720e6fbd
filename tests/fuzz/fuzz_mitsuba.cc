// Material import of .xml files: see fuzz_material.h for what must hold.
#include "fuzz_material.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return brdffit::fuzz::read_material_file("mitsuba", ".xml", data, size);
}
