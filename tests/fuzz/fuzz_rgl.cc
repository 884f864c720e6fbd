// Any bytes given to the RGL reader either parse or raise brdffit::Error; a parsed file
// evaluates without crashing.
#include "brdffit/error.h"
#include "brdffit/rgl.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const brdffit::RglBrdf brdf =
        brdffit::RglBrdf::parse(std::string(reinterpret_cast<const char*>(data), size), "fuzz.bsdf");
    brdf.eval(brdffit::Vec3(0.3, 0.1, 0.9).normalized(), brdffit::Vec3(-0.2, 0.4, 0.8).normalized());
  } catch (const brdffit::Error&) {
  }
  return 0;
}
