// Any text given to the CSV reader either parses or raises brdffit::Error. A parsed set has
// unit directions above the horizon and finite non-negative values; subsets stay within it;
// writing it and reading it back keeps every sample.
#include <cmath>
#include <cstdlib>

#include "brdffit/csv_samples.h"
#include "brdffit/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  brdffit::SampleSet set;
  try {
    set = brdffit::parse_csv_samples(std::string(reinterpret_cast<const char*>(data), size), "fuzz.csv");
  } catch (const brdffit::Error&) {
    return 0;
  }
  for (const brdffit::Sample& s : set.samples)
    if (std::abs(s.l.norm() - 1) > 1e-12 || std::abs(s.v.norm() - 1) > 1e-12 || !(s.l.z() > 0 && s.v.z() > 0) ||
        !s.value.allFinite() || (s.value.array() < 0).any() || !(s.weight >= 0))
      std::abort();
  const brdffit::SampleSet again = brdffit::parse_csv_samples(brdffit::format_csv_samples(set), "again.csv");
  if (again.size() != set.size()) std::abort();
  brdffit::apply_sampling_options(set, brdffit::SamplingOptions{80.0, 3, size});
  if (set.size() > 3) std::abort();
  return 0;
}
