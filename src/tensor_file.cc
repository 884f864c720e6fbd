#include "brdffit/tensor_file.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstring>
#include <limits>
#include <stdexcept>

#include "brdffit/error.h"

namespace brdffit {

namespace {

size_t type_size(TensorFile::Type type) {
  switch (type) {
    case TensorFile::Type::UInt8:
    case TensorFile::Type::Int8: return 1;
    case TensorFile::Type::UInt16:
    case TensorFile::Type::Int16:
    case TensorFile::Type::Float16: return 2;
    case TensorFile::Type::UInt32:
    case TensorFile::Type::Int32:
    case TensorFile::Type::Float32: return 4;
    case TensorFile::Type::UInt64:
    case TensorFile::Type::Int64:
    case TensorFile::Type::Float64: return 8;
  }
  return 0;
}

// Reads little-endian values from a byte buffer, failing cleanly at its end.
class Reader {
 public:
  Reader(const std::string& bytes, const std::string& name) : bytes_(bytes), name_(name) {}
  template <class T>
  T read(const char* what) {
    T value;
    take(&value, sizeof value, what);
    return value;
  }
  std::string read_string(size_t length, const char* what) {
    std::string s(length, '\0');
    take(s.data(), length, what);
    return s;
  }

 private:
  void take(void* out, size_t size, const char* what) {
    if (bytes_.size() - position_ < size) fail("{}: truncated tensor file: ends inside the {}", name_, what);
    std::memcpy(out, bytes_.data() + position_, size);
    position_ += size;
  }
  const std::string& bytes_;
  const std::string& name_;
  size_t position_ = 0;
};

// "[1, 8, *, *]": a shape for messages, 0 standing for any extent when `wildcards`.
std::string shape_text(const std::vector<uint64_t>& shape, bool wildcards) {
  std::vector<std::string> extents;
  for (uint64_t e : shape) extents.push_back(wildcards && e == 0 ? "*" : std::to_string(e));
  return fmt::format("[{}]", fmt::join(extents, ", "));
}

}  // namespace

const char* type_name(TensorFile::Type type) {
  static const char* names[] = {"invalid", "uint8",  "int8",  "uint16",  "int16",   "uint32",
                                "int32",   "uint64", "int64", "float16", "float32", "float64"};
  const auto index = static_cast<size_t>(type);
  return index < sizeof names / sizeof names[0] ? names[index] : "invalid";
}

size_t TensorFile::Field::count() const { return bytes.size() / type_size(type); }

std::vector<float> TensorFile::Field::floats() const {
  if (type != Type::Float32) throw std::logic_error("TensorFile::Field::floats() on a non-float32 field");
  std::vector<float> values(count());
  std::memcpy(values.data(), bytes.data(), values.size() * sizeof(float));
  return values;
}

std::vector<float> TensorFile::release_floats(const std::string& field_name) {
  Field& f = fields_.at(field_name);
  std::vector<float> values = f.floats();
  std::vector<uint8_t>().swap(f.bytes);
  return values;
}

TensorFile TensorFile::parse(const std::string& bytes, const std::string& name) {
  TensorFile file;
  file.name_ = name;
  Reader in(bytes, name);
  if (bytes.compare(0, 12, "tensor_file\0", 12) != 0) fail("{}: not a tensor file (bad header)", name);
  in.read_string(12, "header");
  const auto major = in.read<uint8_t>("version"), minor = in.read<uint8_t>("version");
  if (major != 1 || minor != 0) fail("{}: unsupported tensor file version {}.{} (1.0 expected)", name, major, minor);
  const auto field_count = in.read<uint32_t>("field count");
  for (uint32_t i = 0; i < field_count; ++i) {
    const std::string field_name = in.read_string(in.read<uint16_t>("field name length"), "field name");
    if (field_name.empty()) fail("{}: field {} has an empty name", name, i);
    const auto rank = in.read<uint16_t>("field rank");
    const auto type_code = in.read<uint8_t>("field type");
    const auto offset = in.read<uint64_t>("field offset");
    if (type_code < 1 || type_code > static_cast<uint8_t>(Type::Float64))
      fail("{}: field '{}' has unknown type code {}", name, field_name, type_code);
    Field field;
    field.type = static_cast<Type>(type_code);
    // The data must lie inside the file, so its size (and so every extent) is bounded by the
    // file's; checking as the product grows keeps it from overflowing.
    uint64_t size = type_size(field.type);
    for (uint16_t d = 0; d < rank; ++d) {
      const auto extent = in.read<uint64_t>("field shape");
      field.shape.push_back(extent);
      if (size != 0 && extent > bytes.size() / size)
        fail("{}: truncated tensor file: field '{}' of shape {} does not fit in the file's {} bytes", name, field_name,
             shape_text(field.shape, false), bytes.size());
      size *= extent;
    }
    if (offset > bytes.size() || size > bytes.size() - offset)
      fail("{}: truncated tensor file: field '{}' needs bytes {}..{}, the file has {}", name, field_name, offset,
           offset + size, bytes.size());
    field.bytes.assign(bytes.begin() + static_cast<std::ptrdiff_t>(offset),
                       bytes.begin() + static_cast<std::ptrdiff_t>(offset + size));
    if (!file.fields_.emplace(field_name, std::move(field)).second)
      fail("{}: field '{}' appears twice", name, field_name);
  }
  return file;
}

const TensorFile::Field& TensorFile::field(const std::string& field_name, Type type, size_t rank) const {
  const auto it = fields_.find(field_name);
  if (it == fields_.end()) {
    std::vector<std::string> present;
    for (const auto& [n, f] : fields_) present.push_back("'" + n + "'");
    fail("{}: missing field '{}' (the file has {})", name_, field_name,
         present.empty() ? std::string("no fields") : fmt::format("{}", fmt::join(present, ", ")));
  }
  const Field& f = it->second;
  if (f.type != type) fail("{}: field '{}' is {}, expected {}", name_, field_name, type_name(f.type), type_name(type));
  if (f.shape.size() != rank)
    fail("{}: field '{}' has rank {} (shape {}), expected {}", name_, field_name, f.shape.size(),
         shape_text(f.shape, false), rank);
  return f;
}

void TensorFile::expect_shape(const std::string& field_name, const std::vector<uint64_t>& shape) const {
  const auto it = fields_.find(field_name);
  bool matches = it != fields_.end() && it->second.shape.size() == shape.size();
  for (size_t d = 0; matches && d < shape.size(); ++d) matches = shape[d] == 0 || shape[d] == it->second.shape[d];
  if (!matches)
    fail("{}: field '{}' has shape {}, expected {}", name_, field_name,
         it == fields_.end() ? "none" : shape_text(it->second.shape, false), shape_text(shape, true));
}

}  // namespace brdffit
