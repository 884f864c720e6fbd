// Any bytes given to the MERL reader either parse or raise brdffit::Error; a parsed table gives
// finite, non-negative lookups. An odd first byte feeds the rest of the input to the reader as
// a whole file (the header and size checks); an even one repeats it to fill the body of a
// full-size table behind a valid header, so that the value checks (NaN, infinite, negative
// bins) and the lookups see fuzzed values too.
#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "brdffit/error.h"
#include "brdffit/merl.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using brdffit::Vec3;
  if (size < 2) return 0;
  const char* rest = reinterpret_cast<const char*>(data + 1);
  std::string bytes;
  if (data[0] & 1) {
    bytes.assign(rest, size - 1);
  } else {
    const int32_t dims[3] = {90, 90, 180};
    const size_t file_size = sizeof dims + size_t(3) * 90 * 90 * 180 * sizeof(double);
    bytes.reserve(file_size);
    bytes.assign(reinterpret_cast<const char*>(dims), sizeof dims);
    while (bytes.size() < file_size) bytes.append(rest, std::min(size - 1, file_size - bytes.size()));
  }
  try {
    const brdffit::MerlTable table = brdffit::MerlTable::parse(bytes, "fuzz.binary");
    const Vec3 directions[] = {{0, 0, 1}, {0.3, 0.1, 0.9}, {-0.2, 0.4, 0.8}, {1, 0, 1e-9}, {0, -1, 0.3}};
    for (const Vec3& l : directions)
      for (const Vec3& v : directions)
        for (auto interpolation : {brdffit::Interpolation::Nearest, brdffit::Interpolation::Trilinear}) {
          const brdffit::Rgb<double> f = table.lookup(l.normalized(), v.normalized(), interpolation);
          if (!f.allFinite() || (f.array() < 0).any()) std::abort();
        }
  } catch (const brdffit::Error&) {
  }
  return 0;
}
