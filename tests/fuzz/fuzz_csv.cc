// Any text given to the CSV reader either parses or raises brdffit::Error. A parsed set has
// unit directions above the horizon and finite non-negative values; subsets stay within it;
// writing it and reading it back keeps every sample.
#include <algorithm>
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
  // The same samples in the same order: directions and weights to rounding, values too (they are
  // written as f = value/cosθi and read back times cosθi).
  const auto near = [](double a, double b) {
    return std::abs(a - b) <= 1e-12 * std::max(std::abs(a), std::abs(b)) + 1e-300;
  };
  for (size_t i = 0; i < set.size(); ++i) {
    const brdffit::Sample &a = set.samples[i], &b = again.samples[i];
    for (int k = 0; k < 3; ++k)
      if (!near(a.l[k], b.l[k]) || !near(a.v[k], b.v[k]) || !near(a.value[k], b.value[k])) std::abort();
    if (!near(a.weight, b.weight)) std::abort();
  }
  brdffit::apply_sampling_options(set, brdffit::SamplingOptions{80.0, 3, size});
  if (set.size() > 3) std::abort();
  return 0;
}
