// Any bytes read as a batch summary either raise brdffit::Error or list absolute, non-empty
// paths of result documents (what compare and report then open).
#include <cstdlib>

#include "brdffit/error.h"
#include "brdffit/result_json.h"
#include "fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = brdffit::fuzz::input_file("summary", ".json", data, size);
  try {
    for (const std::string& result : brdffit::read_summary_results(path))
      if (result.empty() || result[0] != '/') std::abort();
  } catch (const brdffit::Error&) {
  }
  return 0;
}
