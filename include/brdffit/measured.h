// Measured reflectance tables (MERL .binary, RGL .bsdf) and tabulated samples (CSV): the one
// entry point the rest of brdffit uses to read measured data, choosing the reader (merl.h,
// rgl.h, csv_samples.h) for a path. The readers' common base class is in measured_brdf.h.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "brdffit/measured_brdf.h"
#include "brdffit/samples.h"

namespace brdffit {

// Opens a MERL or RGL table, choosing the reader by content (an RGL tensor file's magic, a
// MERL header of 90x90 bins), then by extension (.binary, .bsdf). Throws Error naming the file
// and the problem.
std::unique_ptr<MeasuredBrdf> open_measured(const std::string& path);

// Samples from any readable input: MERL, RGL or CSV. Throws Error naming the file and the problem.
SampleSet load_samples(const std::string& path, const SamplingOptions& options);

// The summary of any readable input, for `brdffit info`. A CSV's rows are its valid entries
// (the range is over their f; it has no albedo: NaN).
TableInfo describe_measured(const std::string& path);

// Whether a path ends in a table extension (.binary, .bsdf, .csv, in any case).
bool has_table_extension(const std::string& path);

// What a material measured in a table is called: the file name without its table extension
// (other file names whole). The batch's result documents and summary, compare, report and
// export all name materials this way.
std::string table_material_name(const std::string& path);

}  // namespace brdffit
