// Tabulated BRDF samples as CSV.
//
// The first line that is not blank and does not start with '#' is the header. It names the
// direction columns in one of two forms, then r,g,b and optionally weight:
//   theta_i,phi_i,theta_o,phi_o,r,g,b[,weight]   angles; a '# unit: degrees' or
//                                                  '# unit: radians' line before the header
//                                                  says which (required)
//   lx,ly,lz,vx,vy,vz,r,g,b[,weight]               direction vectors (need not be unit)
// r,g,b are BRDF values f in 1/sr; samples store f·cosθi. The normal is +z; both directions
// must lie above the horizon. Lines starting with '#' are comments.
#pragma once

#include <string>

#include "brdffit/samples.h"

namespace brdffit {

// Parses CSV text; `name` is used in messages ("name:line: problem").
SampleSet parse_csv_samples(const std::string& text, const std::string& name);

// Writes samples in the direction-vector form (f = value / cosθi).
std::string format_csv_samples(const SampleSet& set);

}  // namespace brdffit
