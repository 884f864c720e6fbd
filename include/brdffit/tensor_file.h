// Mitsuba's tensor file container, used by the RGL material database's .bsdf files:
//   "tensor_file\0" (12 bytes), version 1.0 (two bytes), uint32 field count, then per field
//   uint16 name length, the name, uint16 rank, uint8 type, uint64 data offset, rank × uint64
//   shape; each field's data (little endian, row-major) lies at its offset.
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

    size_t count() const;
    // The values as float32 (the field must be Float32) or uint8 (UInt8).
    std::vector<float> floats() const;
  };

  // Parses a whole file's bytes; throws Error naming `name` and the problem.
  static TensorFile parse(const std::string& bytes, const std::string& name);

  // The field, checked for type and rank; throws Error naming the file, field and problem.
  const Field& field(const std::string& field_name, Type type, size_t rank) const;
  bool has(const std::string& field_name) const { return fields_.count(field_name) > 0; }

 private:
  std::string name_;
  std::map<std::string, Field> fields_;
};

const char* type_name(TensorFile::Type type);

}  // namespace brdffit
