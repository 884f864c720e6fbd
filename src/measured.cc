// Choosing a reader for a measured input.
#include "brdffit/measured.h"

#include <cerrno>
#include <cstring>
#include <fstream>

#include "brdffit/csv_samples.h"
#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/merl.h"
#include "brdffit/rgl.h"

namespace brdffit {

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

enum class Format { Merl, Rgl, Csv };

// By content first (an RGL tensor file's magic, a MERL header's 90x90 θh/θd bins), then by
// extension, so a misnamed table still opens and a malformed one gets its reader's message.
Format detect_format(const std::string& path, const std::string& bytes) {
  if (bytes.compare(0, 12, "tensor_file\0", 12) == 0) return Format::Rgl;
  if (ends_with(path, ".csv")) return Format::Csv;
  if (bytes.size() >= 12) {
    int32_t dims[3];
    std::memcpy(dims, bytes.data(), sizeof dims);
    if (dims[0] == 90 && dims[1] == 90) return Format::Merl;
  }
  if (ends_with(path, ".binary")) return Format::Merl;
  if (ends_with(path, ".bsdf")) return Format::Rgl;
  fail("{}: unknown format (expected a MERL .binary, an RGL .bsdf or a .csv of samples)", path);
}

std::unique_ptr<MeasuredBrdf> parse_table(const std::string& path, const std::string& bytes, Format format) {
  switch (format) {
    case Format::Merl: return std::make_unique<MerlTable>(MerlTable::parse(bytes, path));
    case Format::Rgl: return std::make_unique<RglBrdf>(RglBrdf::parse(bytes, path));
    case Format::Csv: break;
  }
  fail("{}: a CSV of samples is not a table that can be evaluated at any pair of directions", path);
}

// The first bytes of a regular file, enough for detect_format.
std::string read_head(const std::string& path) {
  check_input_file(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("{}: cannot open: {}", path, std::strerror(errno));
  std::string head(16, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  return head;
}

}  // namespace

Rgb<double> directional_albedo(const MeasuredBrdf& brdf, const Vec3& v) {
  const int n = 128;
  Rgb<double> sum = Rgb<double>::Zero();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      // Cosine-weighted: pdf = cosθ/π, so ∫ f cosθ dω = π · mean(f).
      const double u1 = (i + 0.5) / n, u2 = (j + 0.5) / n;
      const double r = std::sqrt(u1), phi = 2 * kPi * u2;
      const Vec3 l(r * std::cos(phi), r * std::sin(phi), std::sqrt(1 - u1));
      sum += brdf.eval(l, v);
    }
  return sum * (kPi / (n * n));
}

std::unique_ptr<MeasuredBrdf> open_measured(const std::string& path) {
  const std::string bytes = read_file(path);
  return parse_table(path, bytes, detect_format(path, bytes));
}

SampleSet load_samples(const std::string& path, const SamplingOptions& options) {
  std::unique_ptr<MeasuredBrdf> table;
  {
    if (detect_format(path, read_head(path)) == Format::Csv) {
      // Streamed: a CSV's text can be as large as its samples, and is never needed whole.
      std::ifstream lines(path, std::ios::binary);
      if (!lines) fail("{}: cannot open: {}", path, std::strerror(errno));
      SampleSet set = read_csv_samples(lines, path);
      apply_sampling_options(set, options);
      return set;
    }
    const std::string bytes = read_file(path);
    table = parse_table(path, bytes, detect_format(path, bytes));
  }  // the file's bytes are gone before the samples are made (a MERL table's are 35 MB)
  return table->samples(options);
}

TableInfo describe_measured(const std::string& path) {
  const std::string bytes = read_file(path);
  const Format format = detect_format(path, bytes);
  if (format != Format::Csv) return parse_table(path, bytes, format)->info();
  const SampleSet set = parse_csv_samples(bytes, path);
  TableInfo info;
  info.format = "csv";
  info.resolution = std::to_string(set.size()) + " samples";
  info.valid = set.size();
  for (const Sample& s : set.samples) info.include_in_range(s.value / s.l.z());
  info.albedo = Rgb<double>::Constant(std::nan(""));
  return info;
}

}  // namespace brdffit
