// Test helper: writes Mitsuba tensor files (the RGL .bsdf container) field by field, and builds
// small synthetic RGL BRDFs of any resolution. Plain C++ with no brdffit dependency, so the
// same bytes can be given to the public RGL loader when computing reference values.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

namespace brdffit::test {

struct TensorField {
  std::string name;
  uint8_t type;  // Mitsuba Struct::Type code: 1 uint8, 5 uint32, 10 float32, ...
  std::vector<uint64_t> shape;
  std::string data;
};

constexpr uint8_t kUInt8 = 1, kUInt32 = 5, kFloat32 = 10, kFloat64 = 11;

template <class T>
void append_raw(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

// The bytes of a tensor file holding `fields` (data after the header, in field order).
inline std::string tensor_file_bytes(const std::vector<TensorField>& fields) {
  std::string header("tensor_file\0", 12);
  header += std::string("\x01\x00", 2);
  append_raw(header, static_cast<uint32_t>(fields.size()));
  size_t header_size = header.size();
  for (const TensorField& f : fields) header_size += 2 + f.name.size() + 2 + 1 + 8 + 8 * f.shape.size();
  uint64_t offset = header_size;
  std::string data;
  for (const TensorField& f : fields) {
    append_raw(header, static_cast<uint16_t>(f.name.size()));
    header += f.name;
    append_raw(header, static_cast<uint16_t>(f.shape.size()));
    append_raw(header, f.type);
    append_raw(header, offset);
    for (uint64_t extent : f.shape) append_raw(header, extent);
    data += f.data;
    offset += f.data.size();
  }
  return header + data;
}

// A float32 field of `shape` whose value at each row-major multi-index is value(index).
inline TensorField float_field(const std::string& name, const std::vector<uint64_t>& shape,
                               const std::function<double(const std::vector<uint64_t>&)>& value) {
  TensorField field{name, kFloat32, shape, ""};
  std::vector<uint64_t> index(shape.size(), 0);
  uint64_t count = 1;
  for (uint64_t e : shape) count *= e;
  for (uint64_t n = 0; n < count; ++n) {
    append_raw(field.data, static_cast<float>(value(index)));
    for (size_t d = shape.size(); d-- > 0;) {  // row-major increment
      if (++index[d] < shape[d]) break;
      index[d] = 0;
    }
  }
  return field;
}

inline TensorField float_values(const std::string& name, const std::vector<float>& values) {
  return float_field(name, {values.size()}, [&](const std::vector<uint64_t>& i) { return values[i[0]]; });
}

inline TensorField bytes_field(const std::string& name, const std::string& bytes) {
  return {name, kUInt8, {bytes.size()}, bytes};
}

// A smooth synthetic RGL BRDF with deliberately unequal grid resolutions (none of them the
// database's 32x32 or 128x128): θi on 5 uneven values, VNDF 20x12, RGB 24x24, NDF 17x3, σ 9x3.
// Isotropic: one φi value. Anisotropic: four φi values spanning [-π, π]. Values are simple
// rational functions of the grid indices, different per channel; a few RGB values are negative
// (out of gamut).
inline std::vector<TensorField> synthetic_rgl_fields(bool anisotropic) {
  const double pi = 3.14159265358979323846;
  const std::vector<float> phi_i =
      anisotropic ? std::vector<float>{float(-pi), float(-pi / 3), float(pi / 3), float(pi)} : std::vector<float>{0.0f};
  const std::vector<float> theta_i = {0.0f, 0.35f, 0.8f, 1.2f, float(pi / 2)};
  const uint64_t np = phi_i.size(), nt = theta_i.size(), n_rgb = 24;
  using Index = std::vector<uint64_t>;
  return {
      bytes_field("description", "synthetic test BRDF"),
      float_values("phi_i", phi_i),
      float_values("theta_i", theta_i),
      float_field("ndf", {3, 17},
                  [](const Index& i) {
                    const double u = i[1] / 16.0;
                    return 1.0 / (0.04 + u * u) + 0.2 * i[0];
                  }),
      float_field("sigma", {3, 9}, [](const Index& i) { return 1.0 - 0.05 * i[1] + 0.01 * i[0]; }),
      float_field("vndf", {np, nt, 12, 20},
                  [](const Index& i) {
                    const double x = i[3] / 19.0, y = i[2] / 11.0;
                    return 1.0 / (0.05 + 0.1 * i[1] + x * x) * (1.0 + 0.3 * y + 0.1 * i[0] * y * y);
                  }),
      float_field("luminance", {np, nt, n_rgb, n_rgb}, [](const Index&) { return 1.0; }),
      float_field("rgb", {np, nt, 3, n_rgb, n_rgb},
                  [](const Index& i) {
                    const double x = i[4] / 23.0, y = i[3] / 23.0;
                    const double c = i[2];
                    return (0.2 + 0.3 * c) * (1.0 + (c + 1) * x * x) * (0.6 + (0.4 - 0.3 * c) * y) *
                               (1.0 + 0.1 * i[1] + 0.05 * i[0]) -
                           (x > 0.9 && y > 0.9 ? 1.5 : 0.0);
                  }),
      {"jacobian", kUInt8, {1}, std::string(1, '\x01')},
  };
}

}  // namespace brdffit::test
