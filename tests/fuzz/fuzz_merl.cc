// Any bytes given to the MERL reader either parse or raise brdffit::Error; a parsed table
// answers lookups (and, when small enough to fuzz quickly, samples) without crashing. Odd first bytes feed the input to the
// reader as a whole file (header checks); even ones tile it into a full-size table body behind
// a valid header, so the value checks (NaN, negative bins) and lookups are reached too.
#include <cstring>

#include "brdffit/error.h"
#include "brdffit/merl.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  std::string bytes;
  if (data[0] & 1) {
    bytes.assign(reinterpret_cast<const char*>(data + 1), size - 1);
  } else {
    const int32_t dims[3] = {90, 90, 180};
    bytes.assign(reinterpret_cast<const char*>(dims), sizeof dims);
    const size_t body = size_t(3) * 90 * 90 * 180 * sizeof(double);
    bytes.reserve(bytes.size() + body);
    while (bytes.size() < sizeof dims + body)
      bytes.append(reinterpret_cast<const char*>(data + 1), std::min(size - 1, sizeof dims + body - bytes.size()));
  }
  try {
    const brdffit::MerlTable table = brdffit::MerlTable::parse(bytes, "fuzz.binary");
    for (auto interpolation : {brdffit::Interpolation::Nearest, brdffit::Interpolation::Trilinear})
      table.lookup(brdffit::Vec3(0.3, 0.1, 0.9).normalized(), brdffit::Vec3(-0.2, 0.4, 0.8).normalized(), interpolation);
    if (data[0] & 1) table.samples(brdffit::SamplingOptions{80.0, 100, 1});  // full tables: too slow per input
  } catch (const brdffit::Error&) {
  }
  return 0;
}
