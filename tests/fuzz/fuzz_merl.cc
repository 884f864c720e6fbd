// Any bytes given to the MERL reader either parse or raise brdffit::Error; a parsed table
// answers lookups and samples without crashing.
#include "brdffit/error.h"
#include "brdffit/merl.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const brdffit::MerlTable table =
        brdffit::MerlTable::parse(std::string(reinterpret_cast<const char*>(data), size), "fuzz.binary");
    table.lookup(brdffit::Vec3(0.3, 0.1, 0.9).normalized(), brdffit::Vec3(-0.2, 0.4, 0.8).normalized(),
                 brdffit::Interpolation::Trilinear);
  } catch (const brdffit::Error&) {
  }
  return 0;
}
