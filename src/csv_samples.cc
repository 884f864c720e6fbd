#include "brdffit/csv_samples.h"

#include <fmt/format.h>

#include <cmath>
#include <sstream>
#include <vector>

#include "brdffit/error.h"

namespace brdffit {

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream stream(line);
  std::string field;
  while (std::getline(stream, field, ',')) {
    const size_t begin = field.find_first_not_of(" \t\r"), end = field.find_last_not_of(" \t\r");
    fields.push_back(begin == std::string::npos ? "" : field.substr(begin, end - begin + 1));
  }
  if (!line.empty() && line.back() == ',') fields.push_back("");
  return fields;
}

Vec3 from_angles(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

}  // namespace

SampleSet parse_csv_samples(const std::string& text, const std::string& name) {
  enum class Form { Unknown, Angles, Vectors } form = Form::Unknown;
  double angle_unit = 0.0;  // radians per unit; 0 until a '# unit:' line
  bool has_weight = false;
  SampleSet set;
  set.source = name;
  std::stringstream lines(text);
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos) continue;
    if (line[first] == '#') {
      const std::string comment = line.substr(first + 1);
      if (comment.find("unit:") != std::string::npos) {
        if (comment.find("degree") != std::string::npos)
          angle_unit = kPi / 180.0;
        else if (comment.find("radian") != std::string::npos)
          angle_unit = 1.0;
        else
          fail("{}:{}: unknown angle unit (use '# unit: degrees' or '# unit: radians')", name, number);
      }
      continue;
    }
    const std::vector<std::string> fields = split(line);
    if (form == Form::Unknown) {
      const std::vector<std::string> angles = {"theta_i", "phi_i", "theta_o", "phi_o", "r", "g", "b"};
      const std::vector<std::string> vectors = {"lx", "ly", "lz", "vx", "vy", "vz", "r", "g", "b"};
      auto matches = [&](const std::vector<std::string>& columns) {
        if (fields.size() != columns.size() && !(fields.size() == columns.size() + 1 && fields.back() == "weight"))
          return false;
        return std::equal(columns.begin(), columns.end(), fields.begin());
      };
      if (matches(angles)) {
        form = Form::Angles;
        if (angle_unit == 0.0) fail("{}:{}: angle columns need a '# unit: degrees' or '# unit: radians' line before the header", name, number);
      } else if (matches(vectors)) {
        form = Form::Vectors;
      } else {
        fail("{}:{}: unrecognised header '{}' (expected theta_i,phi_i,theta_o,phi_o,r,g,b[,weight] or "
             "lx,ly,lz,vx,vy,vz,r,g,b[,weight])", name, number, line);
      }
      has_weight = fields.back() == "weight";
      continue;
    }
    const size_t direction_columns = form == Form::Angles ? 4 : 6;
    const size_t expected = direction_columns + 3 + (has_weight ? 1 : 0);
    if (fields.size() != expected) fail("{}:{}: {} fields, the header has {}", name, number, fields.size(), expected);
    std::vector<double> x(expected);
    for (size_t i = 0; i < expected; ++i) {
      size_t used = 0;
      try {
        x[i] = std::stod(fields[i], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != fields[i].size() || !std::isfinite(x[i]))
        fail("{}:{}: field {} '{}' is not a finite number", name, number, i + 1, fields[i]);
    }
    Sample s;
    if (form == Form::Angles) {
      s.l = from_angles(x[0] * angle_unit, x[1] * angle_unit);
      s.v = from_angles(x[2] * angle_unit, x[3] * angle_unit);
    } else {
      s.l = normalized_or_zero(Vec3(x[0], x[1], x[2]));
      s.v = normalized_or_zero(Vec3(x[3], x[4], x[5]));
      if (s.l.isZero() || s.v.isZero()) fail("{}:{}: a direction is the zero vector", name, number);
    }
    if (s.l.z() <= 0.0 || s.v.z() <= 0.0) fail("{}:{}: a direction lies on or below the horizon", name, number);
    const Rgb<double> f(x[direction_columns], x[direction_columns + 1], x[direction_columns + 2]);
    if ((f.array() < 0.0).any()) fail("{}:{}: negative reflectance", name, number);
    s.value = f * s.l.z();
    s.weight = has_weight ? x[expected - 1] : 1.0;
    if (s.weight < 0.0) fail("{}:{}: negative weight", name, number);
    set.samples.push_back(s);
  }
  if (form == Form::Unknown) fail("{}: no CSV header found", name);
  if (set.samples.empty()) fail("{}: no samples after the header", name);
  set.weighting = has_weight ? "from file" : "uniform";
  return set;
}

std::string format_csv_samples(const SampleSet& set) {
  std::string out = "lx,ly,lz,vx,vy,vz,r,g,b,weight\n";
  for (const Sample& s : set.samples) {
    const Rgb<double> f = s.value / s.l.z();
    out += fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", s.l.x(),
                       s.l.y(), s.l.z(), s.v.x(), s.v.y(), s.v.z(), f[0], f[1], f[2], s.weight);
  }
  return out;
}

}  // namespace brdffit
