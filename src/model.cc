#include "brdffit/model.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <numeric>
#include <sstream>

#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/names.h"
#include "brdffit/param.h"
#include "brdffit/two_lobes.h"

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

const std::vector<Nesting>& Model::nestings() const {
  static const std::vector<Nesting> none;
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
  auto is_orientation = [&](const std::string& name) {
    const ParamSpec* p = model.find_parameter(name);
    return p && p->role == Role::Orientation;
  };
  for (const Nesting& nesting : model.nestings()) {
    if (!nesting.exact || nesting.fixed.empty()) continue;
    if (std::all_of(nesting.fixed.begin(), nesting.fixed.end(), [&](const auto& f) { return is_orientation(f.first); }))
      return &nesting;
  }
  return nullptr;
}

namespace {
const Model* find_registered(const std::string& name) {
  for (const auto& m : all_models())
    if (m->name() == name) return m.get();
  return nullptr;
}

// "FIRST+SECOND": built on first use and kept for the program's lifetime (callers hold
// pointers), so each pair is built once.
const Model* find_two_lobes(const std::string& name) {
  const size_t plus = name.find(kLobeSeparator);
  const Model* first = find_registered(name.substr(0, plus));
  const Model* second = find_registered(name.substr(plus + 1));
  if (!first || !second) return nullptr;
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<Model>> built;
  const std::lock_guard<std::mutex> lock(mutex);
  std::unique_ptr<Model>& model = built[name];
  if (!model) model = make_two_lobes(*first, *second);
  return model.get();
}
}  // namespace

const Model* find_model(const std::string& name) {
  if (name.find(kLobeSeparator) != std::string::npos) return find_two_lobes(name);
  return find_registered(name);
}

std::string model_names() {
  std::string names;
  for (const auto& m : all_models()) names += (names.empty() ? "" : ", ") + m->name();
  return names;
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

namespace {
// The name `typed` (one model or FIRST+SECOND) most likely meant, or "" (names.h).
std::string closest_model_name(const std::string& typed) {
  const size_t plus = typed.find(kLobeSeparator);
  if (plus != std::string::npos) {
    const std::string first = closest_model_name(typed.substr(0, plus)),
                      second = closest_model_name(typed.substr(plus + 1));
    return first.empty() || second.empty() ? "" : first + kLobeSeparator + second;
  }
  std::vector<std::string> known{"all"};
  for (const auto& m : all_models()) known.push_back(m->name());
  return closest_name(typed, known);
}
}  // namespace

std::vector<const Model*> parse_model_list(const std::string& list) {
  std::vector<const Model*> models;
  if (list == "all") {
    for (const auto& m : all_models()) models.push_back(m.get());
    return models;
  }
  std::vector<std::string> names;
  std::stringstream stream(list);
  for (std::string name; std::getline(stream, name, ',');)
    if (!name.empty()) names.push_back(name);
  for (const std::string& name : names) {
    const Model* m = nullptr;
    try {
      m = find_model(name);
    } catch (const Error& e) {  // FIRST+SECOND whose parts are no lobes over Lambert
      throw UsageError(fmt::format("--models: {}", e.what()));
    }
    if (!m) {
      // The whole list respelled, so that one typo among several names is fixed in one go.
      std::string respelled;
      for (const std::string& n : names) {
        const std::string closest = closest_model_name(n);
        respelled += (respelled.empty() ? "" : ",") + (closest.empty() ? n : closest);
      }
      const bool known = closest_model_name(name).size() > 0;
      fail_usage(
          "--models: unknown model '{}'{} (known: {}; two lobes over one Lambert base: FIRST+SECOND, e.g. "
          "ggx+ggx)",
          name, known ? "; did you mean -m " + respelled + "?" : "", model_names());
    }
    if (std::find(models.begin(), models.end(), m) == models.end()) models.push_back(m);
  }
  if (models.empty()) fail_usage("--models: no model named");
  return models;
}

Rgb<double> shade_fitted(const Model& model, const std::vector<double>& values,
                         const std::vector<std::vector<double>>& per_channel_values, const Vec3& l, const Vec3& v) {
  if (per_channel_values.empty()) return model.shade(values.data(), l, v);
  Rgb<double> shade;
  for (int c = 0; c < 3; ++c) shade[c] = model.shade(per_channel_values[c].data(), l, v)[c];
  return shade;
}

}  // namespace brdffit
