// The reader of published fits (BBM .fit files, `score --published`): any bytes either raise
// brdffit::Error or give materials whose terms map onto models with exactly their values, each
// finite and at least the parameter's lower bound (find_published_fits checks them so).
#include <cmath>
#include <cstdlib>

#include "brdffit/error.h"
#include "brdffit/model.h"
#include "brdffit/published_fits.h"
#include "brdffit/registry.h"
#include "fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace brdffit;
  const std::string path = fuzz::input_file("published", ".fit", data, size);
  try {
    for (const auto& [material, terms] : read_published_fits(path)) {
      try {
        for (const PublishedFit& fit : find_published_fits(path, material)) {
          const Model* model = find_model(fit.model);
          if (!model || static_cast<int>(fit.values.size()) != model->num_values()) std::abort();
          size_t i = 0;
          for (const ParamSpec& p : model->parameters())
            for (int c = 0; c < p.channels; ++c, ++i)
              if (!(fit.values[i] >= p.lower && std::isfinite(fit.values[i]))) std::abort();
        }
      } catch (const Error&) {
      }
    }
  } catch (const Error&) {
  }
  return 0;
}
