// Choosing a reader for a measured input.
#include "brdffit/measured.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "brdffit/compressed.h"
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

// By content first (an RGL tensor file's magic, a MERL header's 90x90 θh/θd bins), then by the
// name's extension, so a misnamed table still opens and a malformed one gets its reader's
// message. `name` is the path without .xz/.gz; messages name the file itself.
Format detect_format(const std::string& path, const std::string& name, const std::string& bytes) {
  if (bytes.compare(0, 12, "tensor_file\0", 12) == 0) return Format::Rgl;
  if (ends_with(name, ".csv")) return Format::Csv;
  if (bytes.size() >= 12) {
    int32_t dims[3];
    std::memcpy(dims, bytes.data(), sizeof dims);
    if (dims[0] == 90 && dims[1] == 90) return Format::Merl;
  }
  if (ends_with(name, ".binary")) return Format::Merl;
  if (ends_with(name, ".bsdf")) return Format::Rgl;
  fail("{}: unknown format (expected a MERL .binary, an RGL .bsdf or a .csv of samples, or one of them as .xz/.gz)",
       path);
}

std::unique_ptr<MeasuredBrdf> parse_table(const std::string& path, const std::string& bytes, Format format) {
  switch (format) {
    case Format::Merl: return std::make_unique<MerlTable>(MerlTable::parse(bytes, path));
    case Format::Rgl: return std::make_unique<RglBrdf>(RglBrdf::parse(bytes, path));
    case Format::Csv: break;
  }
  fail("{}: a CSV of samples is not a table that can be evaluated at any pair of directions", path);
}

// The first bytes of a regular file, enough for detect_format and compression_of.
std::string read_head(const std::string& path) {
  check_input_file(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("{}: cannot open: {}", path, std::strerror(errno));
  std::string head(16, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  return head;
}

// A measured input as its reader takes it: a table's bytes whole (decompressed from .xz/.gz), a
// compressed CSV's text whole, an uncompressed CSV not at all (its text can be as large as its
// samples and is streamed line by line instead).
struct MeasuredInput {
  Format format;
  std::optional<std::string> bytes;
};

MeasuredInput read_input(const std::string& path) {
  const std::string head = read_head(path);
  if (const Compression compression = compression_of(head); compression != Compression::None) {
    // The format is told by the first bytes out, and a MERL header's dimensions bound the rest.
    const std::string name = without_compression_suffix(path);
    std::string bytes = decompress_file(path, compression, [&](const std::string& first) {
      const Format format = detect_format(path, name, first);
      return format == Format::Merl ? MerlTable::file_size(first, path) : kMaxInputBytes;
    });
    const Format format = detect_format(path, name, bytes);
    return {format, std::move(bytes)};
  }
  const Format format = detect_format(path, path, head);
  if (format == Format::Csv) return {format, std::nullopt};
  // A MERL table is at most 90x90x360 bins of 3 doubles: a larger file is refused unread.
  constexpr uint64_t kLargestMerl = 12 + uint64_t{3} * 90 * 90 * 360 * sizeof(double);
  std::string bytes = read_file(path, format == Format::Merl ? kLargestMerl : kMaxInputBytes);
  return {detect_format(path, path, bytes), std::move(bytes)};
}

SampleSet csv_samples(const std::string& path, const MeasuredInput& input) {
  if (input.bytes) {
    std::istringstream text(*input.bytes);
    return read_csv_samples(text, path);
  }
  std::ifstream lines(path, std::ios::binary);
  if (!lines) fail("{}: cannot open: {}", path, std::strerror(errno));
  return read_csv_samples(lines, path);
}

}  // namespace

std::unique_ptr<MeasuredBrdf> open_measured(const std::string& path) {
  const MeasuredInput input = read_input(path);
  return parse_table(path, input.bytes ? *input.bytes : std::string(), input.format);
}

SampleSet load_samples(const std::string& path, const SamplingOptions& options) {
  std::unique_ptr<MeasuredBrdf> table;
  {
    const MeasuredInput input = read_input(path);
    if (input.format == Format::Csv) {
      SampleSet set = csv_samples(path, input);
      apply_sampling_options(set, options);
      return set;
    }
    table = parse_table(path, *input.bytes, input.format);
  }  // the file's bytes are gone before the samples are made (a MERL table's are 35 MB)
  return table->samples(options);
}

TableInfo describe_measured(const std::string& path) {
  const MeasuredInput input = read_input(path);
  if (input.format != Format::Csv) return parse_table(path, *input.bytes, input.format)->describe();
  const SampleSet set = csv_samples(path, input);
  TableInfo info;
  info.format = "csv";
  info.resolution = std::to_string(set.size()) + " samples";
  info.valid = set.size();
  for (const Sample& s : set.samples) info.include_in_range(s.value / s.l.z());
  info.albedo = Rgb<double>::Constant(std::nan(""));
  return info;
}

bool has_table_extension(const std::string& path) {
  std::string name = path;
  for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::string extension = std::filesystem::path(without_compression_suffix(name)).extension().string();
  return extension == ".binary" || extension == ".bsdf" || extension == ".csv";
}

std::string table_material_name(const std::string& path) {
  const std::filesystem::path file(without_compression_suffix(path));
  return has_table_extension(path) ? file.stem().string() : std::filesystem::path(path).filename().string();
}

}  // namespace brdffit
