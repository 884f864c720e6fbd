// Tabulated BRDF samples as CSV.
//
// Lines starting with '#' are comments and blank lines are skipped. The first other line is the
// header, naming the columns in one of two forms, then r,g,b and optionally weight:
//   theta_i,phi_i,theta_o,phi_o,r,g,b[,weight]   spherical angles of the light (i) and view (o)
//                                                 directions; a comment line '# unit: degrees'
//                                                 or '# unit: radians' before the header states
//                                                 their unit (required)
//   lx,ly,lz,vx,vy,vz,r,g,b[,weight]               direction vectors (need not be unit length)
// Every following line is one sample with that many comma-separated numbers (decimal, '.' as
// the decimal point whatever the locale). The normal is +z; both directions must lie above the
// horizon. r,g,b are BRDF values f in 1/sr (non-negative); samples store f·cosθi. The weight
// (non-negative, default 1) is the sample's relative importance in a fit.
// Example:
//   # unit: degrees
//   theta_i,phi_i,theta_o,phi_o,r,g,b
//   30,0,30,180,0.52,0.31,0.12
#pragma once

#include <istream>
#include <string>

#include "brdffit/samples.h"

namespace brdffit {

// Parses CSV text; `name` is used in messages ("name:line: problem").
SampleSet parse_csv_samples(const std::string& text, const std::string& name);

// The same, line by line from a stream: memory holds the samples, never the whole text (a CSV
// of millions of samples is read from its file this way).
SampleSet read_csv_samples(std::istream& lines, const std::string& name);

// Writes samples in the direction-vector form with weights (f = value / cosθi), with enough
// digits that parsing the text gives the same doubles back.
std::string format_csv_samples(const SampleSet& set);

}  // namespace brdffit
