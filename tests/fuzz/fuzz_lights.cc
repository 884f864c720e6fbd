// Any bytes read as a lights file (directions, intensities, exposure times; the first byte
// chooses which and how many rows are expected) either raise brdffit::Error or give what the
// sphere pipeline relies on: unit directions, and intensities and exposures that are positive,
// finite and whose products and inverses stay finite.
#include <cmath>
#include <cstdlib>

#include "brdffit/error.h"
#include "brdffit/imaging/sphere.h"
#include "fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace brdffit;
  if (size < 1) return 0;
  const size_t expected = 1 + (data[0] >> 2) % 8;
  const std::string path = fuzz::input_file("lights", ".txt", data + 1, size - 1);
  try {
    switch (data[0] % 3) {
      case 0:
        for (const Vec3& d : read_light_directions(path, expected))
          if (!d.allFinite() || std::abs(d.norm() - 1.0) > 1e-9) std::abort();
        break;
      case 1:
        for (const Rgb<double>& i : read_light_intensities(path, expected))
          if (!((i.array() > 0).all() && i.cwiseInverse().allFinite() && (i * 1e6).allFinite())) std::abort();
        break;
      default:
        for (double t : read_exposures(path, expected))
          if (!(t > 0 && std::isfinite(1 / t) && std::isfinite(t * 1e6))) std::abort();
    }
  } catch (const Error&) {
  }
  return 0;
}
