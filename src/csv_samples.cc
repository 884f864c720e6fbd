#include "brdffit/csv_samples.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <optional>
#include <sstream>
#include <vector>

#include "brdffit/error.h"

namespace brdffit {

namespace {

std::string trim(const std::string& s) {
  const size_t begin = s.find_first_not_of(" \t\r"), end = s.find_last_not_of(" \t\r");
  return begin == std::string::npos ? "" : s.substr(begin, end - begin + 1);
}

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  size_t begin = 0;
  for (size_t comma; (comma = line.find(',', begin)) != std::string::npos; begin = comma + 1)
    fields.push_back(trim(line.substr(begin, comma - begin)));
  fields.push_back(trim(line.substr(begin)));
  return fields;
}

// A whole field as a finite double, independent of the locale; false otherwise.
bool parse_number(const std::string& field, double& value) {
  const char* begin =
      field.data() + (field.size() > 1 && field[0] == '+' && field[1] != '-');  // from_chars takes no '+'
  const char* end = field.data() + field.size();
  const auto [stop, error] = std::from_chars(begin, end, value);
  return error == std::errc() && stop == end && std::isfinite(value);
}

Vec3 from_angles(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

enum class Form { Angles, Vectors };

struct Header {
  Form form;
  bool has_weight;
  size_t direction_columns() const { return form == Form::Angles ? 4 : 6; }
  size_t columns() const { return direction_columns() + 3 + (has_weight ? 1 : 0); }
};

// The header's form, or nothing when the fields name neither form.
std::optional<Header> parse_header(const std::vector<std::string>& fields) {
  static const std::vector<std::string> angles = {"theta_i", "phi_i", "theta_o", "phi_o", "r", "g", "b"};
  static const std::vector<std::string> vectors = {"lx", "ly", "lz", "vx", "vy", "vz", "r", "g", "b"};
  for (const auto& [form, columns] : {std::pair{Form::Angles, &angles}, {Form::Vectors, &vectors}}) {
    const bool has_weight = fields.size() == columns->size() + 1 && fields.back() == "weight";
    if ((fields.size() == columns->size() || has_weight) &&
        std::equal(columns->begin(), columns->end(), fields.begin()))
      return Header{form, has_weight};
  }
  return std::nullopt;
}

}  // namespace

SampleSet parse_csv_samples(const std::string& text, const std::string& name) {
  std::istringstream lines(text);
  return read_csv_samples(lines, name);
}

SampleSet read_csv_samples(std::istream& lines, const std::string& name) {
  std::optional<Header> header;
  double radians_per_unit = 0.0;  // 0 until a '# unit:' line
  SampleSet set;
  set.source = name;
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte order mark
    line = trim(line);
    if (line.empty()) continue;
    if (line[0] == '#') {
      // Before the header, '# unit: ...' states the angle unit; other comments are ignored.
      const std::string comment = trim(line.substr(1));
      if (header || comment.rfind("unit:", 0) != 0) continue;
      const std::string unit = trim(comment.substr(5));
      if (unit == "degrees")
        radians_per_unit = kPi / 180.0;
      else if (unit == "radians")
        radians_per_unit = 1.0;
      else
        fail("{}:{}: unknown angle unit '{}' (use '# unit: degrees' or '# unit: radians')", name, number, unit);
      continue;
    }
    const std::vector<std::string> fields = split_fields(line);
    if (!header) {
      header = parse_header(fields);
      if (!header)
        fail(
            "{}:{}: unrecognised header '{}' (expected theta_i,phi_i,theta_o,phi_o,r,g,b[,weight] or "
            "lx,ly,lz,vx,vy,vz,r,g,b[,weight])",
            name, number, line);
      if (header->form == Form::Angles && radians_per_unit == 0.0)
        fail("{}:{}: angle columns need a '# unit: degrees' or '# unit: radians' line before the header", name, number);
      continue;
    }
    if (fields.size() != header->columns())
      fail("{}:{}: {} fields, the header has {}", name, number, fields.size(), header->columns());
    std::vector<double> x(fields.size());
    for (size_t i = 0; i < fields.size(); ++i)
      if (!parse_number(fields[i], x[i]))
        fail("{}:{}: field {} '{}' is not a finite number", name, number, i + 1, fields[i]);
    Sample s;
    if (header->form == Form::Angles) {
      s.l = from_angles(x[0] * radians_per_unit, x[1] * radians_per_unit);
      s.v = from_angles(x[2] * radians_per_unit, x[3] * radians_per_unit);
    } else {
      s.l = normalized_or_zero(Vec3(x[0], x[1], x[2]));
      s.v = normalized_or_zero(Vec3(x[3], x[4], x[5]));
      if (s.l.isZero() || s.v.isZero()) fail("{}:{}: a direction is the zero vector", name, number);
    }
    if (!(s.l.z() > 0.0 && s.v.z() > 0.0)) fail("{}:{}: a direction lies on or below the horizon", name, number);
    const size_t rgb = header->direction_columns();
    const Rgb<double> f(x[rgb], x[rgb + 1], x[rgb + 2]);
    if ((f.array() < 0.0).any()) fail("{}:{}: negative reflectance", name, number);
    s.value = f * s.l.z();
    s.weight = header->has_weight ? x.back() : 1.0;
    if (s.weight < 0.0) fail("{}:{}: negative weight", name, number);
    set.samples.push_back(s);
  }
  if (lines.bad()) fail("{}: read error", name);
  if (!header) fail("{}: no CSV header found", name);
  if (set.samples.empty()) fail("{}: no samples after the header", name);
  set.weighting = header->has_weight ? "from file" : "uniform";
  return set;
}

std::string format_csv_samples(const SampleSet& set) {
  std::string out = "lx,ly,lz,vx,vy,vz,r,g,b,weight\n";
  for (const Sample& s : set.samples) {
    const Rgb<double> f = s.value / s.l.z();
    out += fmt::format("{},{},{},{},{},{},{},{},{},{}\n", s.l.x(), s.l.y(), s.l.z(), s.v.x(), s.v.y(), s.v.z(), f[0],
                       f[1], f[2], s.weight);
  }
  return out;
}

}  // namespace brdffit
