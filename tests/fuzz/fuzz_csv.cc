// Any text given to the CSV reader either parses or raises brdffit::Error.
#include "brdffit/csv_samples.h"
#include "brdffit/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    brdffit::parse_csv_samples(std::string(reinterpret_cast<const char*>(data), size), "fuzz.csv");
  } catch (const brdffit::Error&) {
  }
  return 0;
}
