// Mitsuba's tensor file container, used by the RGL material database's .bsdf files:
//   "tensor_file\0" (12 bytes), version 1.0 (two uint8), uint32 field count, then per field
//   uint16 name length, the name, uint16 rank, uint8 type, uint64 data offset, rank × uint64
//   shape; each field's data (little endian, row-major) lies at its offset.
// Type codes follow Mitsuba's Struct::Type: 1 uint8, 2 int8, 3 uint16, 4 int16, 5 uint32,
// 6 int32, 7 uint64, 8 int64, 9 float16, 10 float32, 11 float64.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace brdffit {

class TensorFile {
 public:
  enum class Type : uint8_t { UInt8 = 1, Int8, UInt16, Int16, UInt32, Int32, UInt64, Int64, Float16, Float32, Float64 };

  struct Field {
    Type type;
    std::vector<uint64_t> shape;
    std::vector<uint8_t> bytes;  // the raw data

    size_t count() const;  // number of values: the product of the shape
    // The values of a Float32 field (throws std::logic_error for other types).
    std::vector<float> floats() const;
  };

  // Parses a whole file's bytes; throws Error naming `name` and the problem (bad header or
  // version, truncated header, unknown type, empty or repeated field name, data beyond the end).
  static TensorFile parse(const std::string& bytes, const std::string& name);

  // The field, checked for type and rank; throws Error naming the file, field and problem.
  const Field& field(const std::string& field_name, Type type, size_t rank) const;
  // The values of a Float32 field, whose raw bytes are then freed (its shape stays): a large
  // table is then held once as values, not twice.
  std::vector<float> release_floats(const std::string& field_name);
  // The field's shape must equal `shape`; 0 in `shape` matches any extent. Throws Error naming
  // the file, field and both shapes otherwise.
  void expect_shape(const std::string& field_name, const std::vector<uint64_t>& shape) const;
  bool has(const std::string& field_name) const { return fields_.count(field_name) > 0; }
  const std::string& name() const { return name_; }

 private:
  std::string name_;
  std::map<std::string, Field> fields_;
};

const char* type_name(TensorFile::Type type);

}  // namespace brdffit
