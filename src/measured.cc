// Choosing a reader for a measured input.
#include "brdffit/measured.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
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

// A table file's bytes, for a format whose size is known read only up to that size: a MERL
// table is at most 90x90x360 bins of 3 doubles, so a larger file is refused before it is read.
std::string read_table_bytes(const std::string& path, const std::string& head) {
  constexpr uint64_t kLargestMerl = 12 + uint64_t{3} * 90 * 90 * 360 * sizeof(double);
  const bool merl = detect_format(path, head) == Format::Merl;
  return read_file(path, merl ? kLargestMerl : kMaxInputBytes);
}

// A CSV's samples, read from the file line by line: its text can be as large as its samples
// and is never needed whole.
SampleSet stream_csv_samples(const std::string& path) {
  std::ifstream lines(path, std::ios::binary);
  if (!lines) fail("{}: cannot open: {}", path, std::strerror(errno));
  return read_csv_samples(lines, path);
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
  const std::string bytes = read_table_bytes(path, read_head(path));
  return parse_table(path, bytes, detect_format(path, bytes));
}

SampleSet load_samples(const std::string& path, const SamplingOptions& options) {
  std::unique_ptr<MeasuredBrdf> table;
  {
    const std::string head = read_head(path);
    if (detect_format(path, head) == Format::Csv) {
      SampleSet set = stream_csv_samples(path);
      apply_sampling_options(set, options);
      return set;
    }
    const std::string bytes = read_table_bytes(path, head);
    table = parse_table(path, bytes, detect_format(path, bytes));
  }  // the file's bytes are gone before the samples are made (a MERL table's are 35 MB)
  return table->samples(options);
}

TableInfo describe_measured(const std::string& path) {
  const std::string head = read_head(path);
  if (detect_format(path, head) != Format::Csv) {
    const std::string bytes = read_table_bytes(path, head);
    return parse_table(path, bytes, detect_format(path, bytes))->info();
  }
  const SampleSet set = stream_csv_samples(path);
  TableInfo info;
  info.format = "csv";
  info.resolution = std::to_string(set.size()) + " samples";
  info.valid = set.size();
  for (const Sample& s : set.samples) info.include_in_range(s.value / s.l.z());
  info.albedo = Rgb<double>::Constant(std::nan(""));
  return info;
}

bool has_table_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".binary" || extension == ".bsdf" || extension == ".csv";
}

std::string table_material_name(const std::string& path) {
  const std::filesystem::path file(path);
  return has_table_extension(path) ? file.stem().string() : file.filename().string();
}

}  // namespace brdffit
