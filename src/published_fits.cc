#include "brdffit/published_fits.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/registry.h"

namespace brdffit {

namespace {

// Recursive-descent parser of one line's right-hand side:
//   call  := NAME '(' [ item { ',' item } ] ')'
//   item  := NAME '=' value | call
//   value := number | '[' value { ',' value } ']'
// Aggregate(...) holds calls only and is flattened; any other call holds key = value items.
class LineParser {
 public:
  // `text` is the part of line `line` that starts at column `column` (1-based) of the line.
  LineParser(const std::string& path, int line, size_t column, const std::string& text)
      : path_(path), line_(line), column_(column), text_(text) {}

  std::vector<PublishedTerm> parse_terms() {
    std::vector<PublishedTerm> terms;
    parse_call(terms);
    skip_space();
    if (pos_ != text_.size()) error("unexpected '{}' after the model", text_.substr(pos_, 20));
    return terms;
  }

 private:
  template <class... Args>
  [[noreturn]] void error(fmt::format_string<Args...> format, Args&&... args) {
    fail("{}:{}: {} (column {})", path_, line_, fmt::format(format, std::forward<Args>(args)...), column_ + pos_);
  }

  void skip_space() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  bool accept(char c) {
    skip_space();
    if (pos_ < text_.size() && text_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  void expect(char c) {
    if (!accept(c)) error("expected '{}'", c);
  }
  bool at_name() {
    skip_space();
    return pos_ < text_.size() && (std::isalpha(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_');
  }
  std::string name() {
    if (!at_name()) error("expected a name");
    const size_t start = pos_;
    while (pos_ < text_.size() && (std::isalnum(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_')) ++pos_;
    return text_.substr(start, pos_ - start);
  }
  double number() {
    skip_space();
    const char* begin = text_.c_str() + pos_;
    char* end = nullptr;
    const double value = std::strtod(begin, &end);
    if (end == begin) error("expected a number");
    pos_ += static_cast<size_t>(end - begin);
    if (!std::isfinite(value))
      error("'{}' is not a finite number", std::string(begin, static_cast<size_t>(end - begin)));
    return value;
  }
  // A number or a list; nested lists (Bagher's complex eta = [[re...], [im...]]) are flattened
  // in reading order.
  void value(std::vector<double>& values, int depth = 0) {
    if (accept('[')) {
      if (depth >= kMaxDepth) error("lists nested deeper than {}", kMaxDepth);
      do value(values, depth + 1);
      while (accept(','));
      expect(']');
    } else {
      values.push_back(number());
    }
  }

  // Parses NAME(...) at the cursor; appends the term, or Aggregate's terms, to `terms`.
  void parse_call(std::vector<PublishedTerm>& terms, int depth = 0) {
    if (depth >= kMaxDepth) error("terms nested deeper than {}", kMaxDepth);
    PublishedTerm term{name(), {}};
    const bool aggregate = term.model == "Aggregate";
    expect('(');
    if (!accept(')')) {
      do {
        skip_space();
        const size_t start = pos_;
        const std::string key = name();
        skip_space();
        if (pos_ < text_.size() && text_[pos_] == '(') {  // a nested term
          if (!aggregate) error("'{}' cannot hold the term '{}'", term.model, key);
          pos_ = start;
          parse_call(terms, depth + 1);
          continue;
        }
        if (aggregate) error("Aggregate holds terms, not the parameter '{}'", key);
        expect('=');
        if (term.parameters.count(key)) error("parameter '{}' given twice", key);
        value(term.parameters[key]);
      } while (accept(','));
      expect(')');
    }
    if (!aggregate) terms.push_back(std::move(term));
  }

  static constexpr int kMaxDepth = 8;  // BBM's files nest 2 deep; bounds the recursion on bad input
  const std::string& path_;
  const int line_;
  const size_t column_;
  const std::string& text_;
  size_t pos_ = 0;
};

std::string trimmed(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

}  // namespace

std::map<std::string, std::vector<PublishedTerm>> read_published_fits(const std::string& path) {
  std::map<std::string, std::vector<PublishedTerm>> fits;
  std::stringstream lines(read_file(path));
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string text = trimmed(line);
    if (text.empty() || text[0] == '#') continue;
    const size_t eq = text.find('=');
    if (eq == std::string::npos) fail("{}:{}: expected 'material = Model(...)'", path, number);
    const std::string material = trimmed(text.substr(0, eq));
    if (material.empty()) fail("{}:{}: no material name before '='", path, number);
    for (char c : material)
      if (std::isspace(static_cast<unsigned char>(c)) || c == '(' || c == ')' || c == ',')
        fail("{}:{}: '{}' is not a material name", path, number, material);
    const std::string body = text.substr(eq + 1);
    const size_t body_column = line.find_first_not_of(" \t\f\v") + eq + 2;  // 1-based, in `line`
    std::vector<PublishedTerm> terms = LineParser(path, number, body_column, body).parse_terms();
    if (terms.empty()) fail("{}:{}: {} has no model terms", path, number, material);
    if (!fits.emplace(material, std::move(terms)).second)
      fail("{}:{}: material '{}' appears twice", path, number, material);
  }
  return fits;
}

namespace {

// Each of our literature models, the one published lobe it maps, and for each of our
// parameters besides `albedo` the published parameter it takes (same meaning, no rescaling).
struct Mapping {
  struct Parameter {
    const char* ours;
    const char* theirs;
    int row = -1;  // >= 0: this row of a nested list (Bagher's eta = [[f0...], [f1...]]); -1: all of it
  };
  const char* model;
  const char* term;
  std::vector<Parameter> parameters;
};

const std::vector<Mapping>& mappings() {
  static const std::vector<Mapping> list = {
      {"cook-torrance", "NganCookTorrance", {{"specular", "albedo"}, {"f0", "eta"}, {"m", "roughness"}}},
      {"ward", "NganWard", {{"specular", "albedo"}, {"alpha", "roughness"}}},
      {"ashikhmin-shirley",
       "NganAshikhminShirley",
       {{"specular", "albedo"}, {"f0", "fresnelReflectance"}, {"n", "sharpness"}}},
      {"lafortune", "NganLafortune", {{"specular", "albedo"}, {"cxy", "Cxy"}, {"cz", "Cz"}, {"n", "sharpness"}}},
      {"low-smooth", "LowSmooth", {{"A", "A"}, {"B", "B"}, {"C", "C"}, {"eta", "eta"}}},
      {"low-microfacet", "LowMicrofacetFit", {{"A", "A"}, {"B", "B"}, {"C", "C"}, {"eta", "eta"}}},
      {"low-cook-torrance", "LowCookTorrance", {{"specular", "albedo"}, {"m", "roughness"}, {"eta", "eta"}}},
      {"low-ashikhmin-shirley",
       "LowAshikhminShirley",
       {{"specular", "albedo"}, {"n", "sharpness"}, {"eta", "fresnelReflectance"}}},
      {"sgd",
       "Bagher",
       {{"specular", "albedo"},
        {"alpha", "alpha"},
        {"p", "p"},
        {"f0", "eta", 0},
        {"f1", "eta", 1},
        {"K", "K"},
        {"lambda", "Lambda"},
        {"c", "c"},
        {"k", "k"},
        {"theta0", "theta0"}}},
  };
  return list;
}

// Writes a published parameter (or one row of it) into our flattened values: colours take 3
// values (or one, for grey), scalars exactly one.
bool copy(const PublishedTerm& term, const Mapping::Parameter& parameter, const Model& model,
          std::vector<double>& values) {
  const auto it = term.parameters.find(parameter.theirs);
  const ParamSpec* spec = model.find_parameter(parameter.ours);
  if (it == term.parameters.end() || !spec) return false;
  std::vector<double> v = it->second;
  if (parameter.row >= 0) {  // rows of `channels` values each
    const size_t row = static_cast<size_t>(parameter.row), n = static_cast<size_t>(spec->channels);
    if (v.size() % n != 0 || (row + 1) * n > v.size()) return false;
    v = std::vector<double>(v.begin() + row * n, v.begin() + (row + 1) * n);
  }
  if (v.size() == 1) v.assign(spec->channels, v[0]);
  if (static_cast<int>(v.size()) != spec->channels) return false;
  std::copy(v.begin(), v.end(), values.begin() + model.offset_of(parameter.ours));
  return true;
}

// The number of distinct published parameters a mapping reads.
size_t published_parameter_count(const Mapping& mapping) {
  std::vector<std::string> names;
  for (const Mapping::Parameter& p : mapping.parameters)
    if (std::find(names.begin(), names.end(), p.theirs) == names.end()) names.push_back(p.theirs);
  return names.size();
}

}  // namespace

std::optional<std::vector<double>> to_model_values(const Model& model, const std::vector<PublishedTerm>& terms) {
  for (const Mapping& mapping : mappings()) {
    if (model.name() != mapping.model) continue;
    const PublishedTerm* lambertian = nullptr;
    const PublishedTerm* lobe = nullptr;
    for (const PublishedTerm& t : terms) {
      const PublishedTerm** slot = t.model == "Lambertian" ? &lambertian : t.model == mapping.term ? &lobe : nullptr;
      if (!slot || *slot) return std::nullopt;  // a term we do not map, or a second lobe
      *slot = &t;
    }
    if (!lobe) return std::nullopt;
    std::vector<double> values = model.default_values();
    if (lambertian) {
      if (lambertian->parameters.size() != 1 || !copy(*lambertian, {"albedo", "albedo"}, model, values))
        return std::nullopt;
    } else {
      std::fill_n(values.begin() + model.offset_of("albedo"), 3, 0.0);
    }
    if (lobe->parameters.size() != published_parameter_count(mapping)) return std::nullopt;  // one we cannot represent
    for (const Mapping::Parameter& parameter : mapping.parameters)
      if (!copy(*lobe, parameter, model, values)) return std::nullopt;
    return values;
  }
  return std::nullopt;
}

namespace {

// Checked as --param values are, against the lower bounds (see check_parameter_values): a
// denormal or negative width would score as NaN or infinity.
PublishedFit published_fit(const std::string& fit_file, const std::string& material, const Model& model,
                           const std::vector<PublishedTerm>& terms, std::vector<double> values) {
  std::string term;
  for (const PublishedTerm& t : terms)
    if (t.model != "Lambertian") term = t.model;
  check_parameter_values(model, values, fmt::format("{}: {} ({} as {})", fit_file, material, term, model.name()),
                         BoundsCheck::AtLeastLower);
  return PublishedFit{material, model.name(), term, std::move(values)};
}

}  // namespace

std::optional<PublishedFit> find_published_fit(const std::string& fit_file, const std::string& material,
                                               const Model& model) {
  const auto fits = read_published_fits(fit_file);
  const auto it = fits.find(material);
  if (it == fits.end()) return std::nullopt;
  std::optional<std::vector<double>> values = to_model_values(model, it->second);
  if (!values) return std::nullopt;
  return published_fit(fit_file, material, model, it->second, std::move(*values));
}

std::vector<PublishedFit> find_published_fits(const std::string& fit_file, const std::string& material) {
  const auto fits = read_published_fits(fit_file);
  const auto it = fits.find(material);
  if (it == fits.end()) {
    std::string some;
    int listed = 0;
    for (const auto& [name, terms] : fits)
      if (listed++ < 5) some += (some.empty() ? "" : ", ") + name;
    fail("{}: no material '{}' ({} materials{}{})", fit_file, material, fits.size(), fits.empty() ? "" : ": ",
         some + (fits.size() > 5 ? ", ..." : ""));
  }
  std::vector<PublishedFit> found;
  for (const auto& model : all_models())
    if (std::optional<std::vector<double>> values = to_model_values(*model, it->second))
      found.push_back(published_fit(fit_file, material, *model, it->second, std::move(*values)));
  if (found.empty()) {
    std::string terms;
    for (const PublishedTerm& t : it->second) terms += (terms.empty() ? "" : " + ") + t.model;
    fail("{}: the fit of '{}' ({}) maps onto none of brdffit's models (see `brdffit score --help`)", fit_file, material,
         terms);
  }
  return found;
}

}  // namespace brdffit
