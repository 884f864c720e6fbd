#include "brdffit/tensor_file.h"

#include <cstring>
#include <limits>

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

}  // namespace

const char* type_name(TensorFile::Type type) {
  static const char* names[] = {"invalid", "uint8", "int8", "uint16", "int16", "uint32", "int32",
                                "uint64",  "int64", "float16", "float32", "float64"};
  const auto index = static_cast<size_t>(type);
  return index < sizeof names / sizeof names[0] ? names[index] : "invalid";
}

size_t TensorFile::Field::count() const { return bytes.size() / type_size(type); }

std::vector<float> TensorFile::Field::floats() const {
  std::vector<float> values(count());
  if (type == Type::Float32) {
    std::memcpy(values.data(), bytes.data(), bytes.size());
  } else {
    for (size_t i = 0; i < values.size(); ++i) values[i] = bytes[i];  // UInt8
  }
  return values;
}

TensorFile TensorFile::parse(const std::string& bytes, const std::string& name) {
  TensorFile file;
  file.name_ = name;
  Reader in(bytes, name);
  if (in.read_string(12, "header") != std::string("tensor_file\0", 12)) fail("{}: not a tensor file (bad header)", name);
  const auto major = in.read<uint8_t>("version"), minor = in.read<uint8_t>("version");
  if (major != 1 || minor != 0) fail("{}: unsupported tensor file version {}.{} (1.0 expected)", name, major, minor);
  const auto field_count = in.read<uint32_t>("field count");
  for (uint32_t i = 0; i < field_count; ++i) {
    const std::string field_name = in.read_string(in.read<uint16_t>("field name length"), "field name");
    const auto rank = in.read<uint16_t>("field rank");
    const auto type_code = in.read<uint8_t>("field type");
    const auto offset = in.read<uint64_t>("field offset");
    if (type_code < 1 || type_code > static_cast<uint8_t>(Type::Float64))
      fail("{}: field '{}' has unknown type code {}", name, field_name, type_code);
    Field field;
    field.type = static_cast<Type>(type_code);
    uint64_t count = 1;
    for (uint16_t d = 0; d < rank; ++d) {
      const auto extent = in.read<uint64_t>("field shape");
      if (extent != 0 && count > std::numeric_limits<uint64_t>::max() / extent / 8)
        fail("{}: field '{}' has an impossible shape", name, field_name);
      count *= extent;
      field.shape.push_back(extent);
    }
    const uint64_t size = count * type_size(field.type);
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
  if (it == fields_.end()) fail("{}: missing field '{}'", name_, field_name);
  const Field& f = it->second;
  if (f.type != type)
    fail("{}: field '{}' is {}, expected {}", name_, field_name, type_name(f.type), type_name(type));
  if (f.shape.size() != rank) fail("{}: field '{}' has rank {}, expected {}", name_, field_name, f.shape.size(), rank);
  return f;
}

}  // namespace brdffit
