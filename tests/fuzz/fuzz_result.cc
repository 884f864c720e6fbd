// Any bytes read back as a result document (the JSON that fit, sphere and batch write, and
// compare, report, render and export read) either raise brdffit::Error or give results that
// the readers' users can use without checking again: each ok result has exactly its model's
// values (three vectors of them when per channel) within the parameters' bounds, so that
// shading, comparing and exporting them stay finite and in bounds.
#include <cmath>
#include <cstdlib>

#include "brdffit/compare.h"
#include "brdffit/error.h"
#include "brdffit/material_export.h"
#include "brdffit/registry.h"
#include "brdffit/result_json.h"
#include "fuzz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace brdffit;
  const std::string path = fuzz::input_file("result", ".json", data, size);
  try {
    const FitDocument document = read_fit_document(path);
    for (const FitResult& r : document.results) {
      if (!r.ok) continue;
      const Model* model = find_model(r.model);
      if (!model || static_cast<int>(r.values.size()) != model->num_values()) std::abort();
      if (!r.channel_values.empty() && r.channel_values.size() != 3) std::abort();
      for (const std::vector<double>& values : r.channel_values)
        if (static_cast<int>(values.size()) != model->num_values()) std::abort();
      const Vec3 l = Vec3(0.3, 0.2, 0.9).normalized(), v = Vec3(-0.1, 0.4, 0.8).normalized();
      const Rgb<double> shaded = model->shade(r.values.data(), l, v);
      (void)shaded;  // may be NaN for a degenerate but in-bounds value: only reading must be safe
    }
    const Comparison comparison = compare_results({document}, common_metric({document}));
    comparison_markdown(comparison);
    comparison_csv(comparison);
    try {
      ExportRequest request;
      request.force = true;  // poor and failed fits too: only reading must be safe
      export_material(document, request);
    } catch (const Error&) {
    }
  } catch (const Error&) {
  }
  return 0;
}
