// Any bytes given to the RGL reader either parse or raise brdffit::Error; a parsed file
// evaluates to finite, non-negative values at directions across the hemisphere (normal,
// grazing, mirror, opposite azimuths) and below it.
#include <cstdlib>
#include <optional>

#include "brdffit/error.h"
#include "brdffit/rgl.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using brdffit::Vec3;
  std::optional<brdffit::RglBrdf> brdf;
  try {
    brdf.emplace(brdffit::RglBrdf::parse(std::string(reinterpret_cast<const char*>(data), size), "fuzz.bsdf"));
  } catch (const brdffit::Error&) {
    return 0;
  }
  const Vec3 directions[] = {{0, 0, 1},    {0.3, 0.1, 0.9},   {-0.2, 0.4, 0.8},
                             {1, 0, 1e-9}, {-1, -1e-7, 0.02}, {0, -1, 0.3}};
  for (const Vec3& l : directions)
    for (const Vec3& v : directions) {
      const brdffit::Rgb<double> f = brdf->eval(l.normalized(), v.normalized());
      if (!f.allFinite() || (f.array() < 0).any()) std::abort();
    }
  if (!brdf->eval(Vec3(0, 0, -1), Vec3(0, 0, 1)).isZero()) std::abort();
  return 0;
}
