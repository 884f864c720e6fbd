#include "brdffit/model.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "brdffit/error.h"
#include "brdffit/param.h"

namespace brdffit {

const char* role_name(Role role) {
  switch (role) {
    case Role::DiffuseColour: return "diffuse colour";
    case Role::SpecularColour: return "specular colour";
    case Role::F0: return "F0";
    case Role::Roughness: return "roughness";
    case Role::Exponent: return "exponent";
    case Role::Wrap: return "wrap";
    case Role::Orientation: return "orientation";
    case Role::Anisotropy: return "anisotropy";
    case Role::Shape: return "shape";
  }
  return "shape";
}

int flattened_size(const std::vector<ParamSpec>& params) {
  return std::accumulate(params.begin(), params.end(), 0, [](int n, const ParamSpec& p) { return n + p.channels; });
}

std::vector<double> Model::default_values() const {
  std::vector<double> values;
  for (const ParamSpec& p : parameters()) values.insert(values.end(), p.channels, p.default_value);
  return values;
}

int Model::offset_of(const std::string& param_name) const {
  int offset = 0;
  for (const ParamSpec& p : parameters()) {
    if (p.name == param_name) return offset;
    offset += p.channels;
  }
  return -1;
}

const ParamSpec* Model::find_parameter(const std::string& param_name) const {
  for (const ParamSpec& p : parameters())
    if (p.name == param_name) return &p;
  return nullptr;
}

Rgb<double> Model::shade_linear_parts(const double* values, const Vec3& l, const Vec3& v, Rgb<double>* basis) const {
  std::vector<double> probe(values, values + num_values());
  std::vector<std::pair<int, int>> linear;  // offset and channels of each linear parameter
  int offset = 0;
  for (const ParamSpec& p : parameters()) {
    if (p.linear) {
      linear.emplace_back(offset, p.channels);
      std::fill_n(probe.begin() + offset, p.channels, 0.0);
    }
    offset += p.channels;
  }
  const Rgb<double> base = shade(probe.data(), l, v);
  for (size_t j = 0; j < linear.size(); ++j) {
    const auto [at, channels] = linear[j];
    std::fill_n(probe.begin() + at, channels, 1.0);
    basis[j] = shade(probe.data(), l, v) - base;
    std::fill_n(probe.begin() + at, channels, 0.0);
  }
  return base;
}

const std::vector<Nesting>& Model::nestings() const {
  static const std::vector<Nesting> none;
  return none;
}

const RecoveryFacts& Model::recovery_facts() const {
  static const RecoveryFacts none;
  return none;
}

std::vector<double> embed_values(const Model& outer, const Nesting& nesting, const Model& inner,
                                 const std::vector<double>& inner_values) {
  std::vector<double> values = outer.default_values();
  auto place = [&](const std::string& name) {
    const ParamSpec* p = outer.find_parameter(name);
    if (!p) fail("{}: nesting of {} names no parameter '{}'", outer.name(), inner.name(), name);
    return std::pair{p, outer.offset_of(name)};
  };
  for (const Nesting::Copy& copy : nesting.copies) {
    const auto [to, to_offset] = place(copy.to);
    const ParamSpec* from = inner.find_parameter(copy.from);
    if (!from) fail("{}: nesting names no parameter '{}' of {}", outer.name(), copy.from, inner.name());
    const int from_offset = inner.offset_of(copy.from);
    for (int c = 0; c < to->channels; ++c) {
      const double x = inner_values[from_offset + (from->channels == 3 ? c : 0)];
      values[to_offset + c] = std::clamp(copy.transform ? copy.transform(x) : x, to->lower, to->upper);
    }
  }
  for (const auto& [name, value] : nesting.fixed) {
    const auto [p, offset] = place(name);
    std::fill_n(values.begin() + offset, p->channels, value);
  }
  return values;
}

const Nesting* isotropic_form(const Model& model) {
  auto is_anisotropic = [&](const std::string& name) {
    const ParamSpec* p = model.find_parameter(name);
    return p && (p->role == Role::Orientation || p->role == Role::Anisotropy);
  };
  for (const Nesting& nesting : model.nestings()) {
    if (!nesting.exact || nesting.fixed.empty()) continue;
    if (std::all_of(nesting.fixed.begin(), nesting.fixed.end(), [&](const auto& f) { return is_anisotropic(f.first); }))
      return &nesting;
  }
  return nullptr;
}

std::vector<std::pair<std::string, double>> isotropic_holds(const Model& model) {
  const std::vector<ParamSpec>& params = model.parameters();
  if (std::none_of(params.begin(), params.end(), [](const ParamSpec& p) { return p.role == Role::Anisotropy; }))
    return {};
  std::vector<std::pair<std::string, double>> holds;
  for (const ParamSpec& p : params) {
    if (p.role == Role::Anisotropy) holds.emplace_back(p.name, 0.0);
    if (p.role == Role::Orientation) holds.emplace_back(p.name, p.default_value);
  }
  return holds;
}

namespace {
std::vector<double> parse_numbers(const std::string& text, const std::string& what) {
  std::vector<double> numbers;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(item, &used);
    } catch (const std::exception&) {
      fail("{}: '{}' is not a number", what, item);
    }
    if (used != item.size() || !std::isfinite(value)) fail("{}: '{}' is not a finite number", what, item);
    numbers.push_back(value);
  }
  if (numbers.empty()) fail("{}: no value given", what);
  return numbers;
}
}  // namespace

void check_parameter_value(const ParamSpec& spec, double x, const std::string& where, BoundsCheck bounds) {
  if (bounds == BoundsCheck::AtLeastLower && !(x >= spec.lower && std::isfinite(x)))
    fail("{}: {} must be at least {}, got {}", where, spec.name, spec.lower, x);
  if (bounds == BoundsCheck::Both && !(x >= spec.lower && x <= spec.upper))
    fail("{}: {} must lie in [{}, {}], got {}", where, spec.name, spec.lower, spec.upper, x);
  if (spec.integer && x != std::round(x)) fail("{}: {} must be an integer, got {}", where, spec.name, x);
}

void check_parameter_values(const Model& model, const std::vector<double>& values, const std::string& where,
                            BoundsCheck bounds) {
  if (static_cast<int>(values.size()) != model.num_values())
    fail("{}: {} values, {} has {}", where, values.size(), model.name(), model.num_values());
  size_t i = 0;
  for (const ParamSpec& spec : model.parameters())
    for (int c = 0; c < spec.channels; ++c) check_parameter_value(spec, values[i++], where, bounds);
}

std::vector<double> parameter_values(const Model& model, const std::vector<std::string>& assignments) {
  std::vector<double> values = model.default_values();
  for (const std::string& assignment : assignments) {
    const size_t eq = assignment.find('=');
    if (eq == std::string::npos) fail("--param '{}': expected NAME=VALUE", assignment);
    const std::string name = assignment.substr(0, eq);
    const ParamSpec* spec = model.find_parameter(name);
    if (!spec) {
      std::string known;
      for (const ParamSpec& p : model.parameters()) known += (known.empty() ? "" : ", ") + p.name;
      fail("--param '{}': model {} has no parameter '{}' (it has: {})", assignment, model.name(), name, known);
    }
    std::vector<double> numbers = parse_numbers(assignment.substr(eq + 1), "--param " + name);
    if (numbers.size() == 1) numbers.assign(spec->channels, numbers[0]);
    if (static_cast<int>(numbers.size()) != spec->channels)
      fail("--param '{}': {} takes {} value(s), got {}", assignment, name, spec->channels == 3 ? "1 or 3" : "1",
           numbers.size());
    for (double x : numbers) check_parameter_value(*spec, x, "--param '" + assignment + "'");
    std::copy(numbers.begin(), numbers.end(), values.begin() + model.offset_of(name));
  }
  return values;
}

Vec3 parse_vec3(const std::string& text, const std::string& what) {
  const std::vector<double> numbers = parse_numbers(text, what);
  if (numbers.size() != 3) fail("{}: expected X,Y,Z, got '{}'", what, text);
  return Vec3(numbers[0], numbers[1], numbers[2]);
}

Rgb<double> shade_fitted(const Model& model, const std::vector<double>& values,
                         const std::vector<std::vector<double>>& per_channel_values, const Vec3& l, const Vec3& v) {
  if (per_channel_values.empty()) return model.shade(values.data(), l, v);
  Rgb<double> shade;
  for (int c = 0; c < 3; ++c) shade[c] = model.shade(per_channel_values[c].data(), l, v)[c];
  return shade;
}

}  // namespace brdffit
