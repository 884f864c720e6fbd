#include "brdffit/published_fits.h"

#include <regex>
#include <sstream>

#include "brdffit/error.h"
#include "brdffit/io.h"

namespace brdffit {

std::map<std::string, std::vector<PublishedTerm>> read_published_fits(const std::string& path) {
  std::map<std::string, std::vector<PublishedTerm>> fits;
  std::stringstream lines(read_file(path));
  std::string line;
  // A term: Name(key = value or [v, v, v], ...); the outer Aggregate( ... ) only groups terms.
  const std::regex term_pattern(R"(([A-Za-z]\w*)\(([^()]*)\))");
  const std::regex parameter_pattern(R"((\w+)\s*=\s*(\[[^\]]*\]|[-+0-9.eE]+))");
  for (int number = 1; std::getline(lines, line); ++number) {
    if (line.empty() || line[0] == '#') continue;
    const size_t eq = line.find('=');
    if (eq == std::string::npos) fail("{}:{}: expected 'material = Aggregate(...)'", path, number);
    const std::string material = std::regex_replace(line.substr(0, eq), std::regex(R"(^\s+|\s+$)"), "");
    std::vector<PublishedTerm> terms;
    const std::string body = line.substr(eq + 1);
    for (std::sregex_iterator t(body.begin(), body.end(), term_pattern), end; t != end; ++t) {
      PublishedTerm term{(*t)[1], {}};
      const std::string arguments = (*t)[2];
      for (std::sregex_iterator p(arguments.begin(), arguments.end(), parameter_pattern); p != end; ++p) {
        std::string text = (*p)[2];
        std::vector<double> values;
        std::stringstream numbers(text.front() == '[' ? text.substr(1, text.size() - 2) : text);
        for (std::string item; std::getline(numbers, item, ',');) {
          try {
            values.push_back(std::stod(item));
          } catch (const std::exception&) {
            fail("{}:{}: '{}' is not a number", path, number, item);
          }
        }
        term.parameters[(*p)[1]] = values;
      }
      terms.push_back(term);
    }
    if (material.empty() || terms.empty()) fail("{}:{}: no material or no model terms", path, number);
    fits[material] = terms;
  }
  return fits;
}

namespace {

const PublishedTerm* find_term(const std::vector<PublishedTerm>& terms, const std::string& name) {
  for (const PublishedTerm& t : terms)
    if (t.model == name) return &t;
  return nullptr;
}

// Writes a published parameter (1 or 3 values) into our flattened values.
bool copy(const PublishedTerm& term, const std::string& from, const Model& model, const std::string& to,
          std::vector<double>& values) {
  const auto it = term.parameters.find(from);
  const ParamSpec* spec = model.find_parameter(to);
  if (it == term.parameters.end() || !spec) return false;
  std::vector<double> v = it->second;
  if (v.size() == 1) v.assign(spec->channels, v[0]);
  if (static_cast<int>(v.size()) != spec->channels) return false;
  std::copy(v.begin(), v.end(), values.begin() + model.offset_of(to));
  return true;
}

}  // namespace

std::optional<std::vector<double>> to_model_values(const Model& model, const std::vector<PublishedTerm>& terms) {
  // Ngan's term name and, for each of our parameters, theirs.
  struct Mapping {
    const char* model;
    const char* term;
    std::vector<std::pair<const char*, const char*>> parameters;  // ours, theirs
  };
  static const std::vector<Mapping> mappings = {
      {"cook-torrance", "NganCookTorrance", {{"specular", "albedo"}, {"f0", "eta"}, {"m", "roughness"}}},
      {"ward", "NganWard", {{"specular", "albedo"}, {"alpha", "roughness"}}},
      {"ashikhmin-shirley", "NganAshikhminShirley",
       {{"specular", "albedo"}, {"f0", "fresnelReflectance"}, {"n", "sharpness"}}},
      {"lafortune", "NganLafortune", {{"specular", "albedo"}, {"cxy", "Cxy"}, {"cz", "Cz"}, {"n", "sharpness"}}},
  };
  for (const Mapping& mapping : mappings) {
    if (model.name() != mapping.model) continue;
    const PublishedTerm* lambertian = find_term(terms, "Lambertian");
    const PublishedTerm* lobe = find_term(terms, mapping.term);
    if (!lambertian || !lobe) return std::nullopt;
    std::vector<double> values = model.default_values();
    if (!copy(*lambertian, "albedo", model, "albedo", values)) return std::nullopt;
    for (const auto& [ours, theirs] : mapping.parameters)
      if (!copy(*lobe, theirs, model, ours, values)) return std::nullopt;
    return values;
  }
  return std::nullopt;
}

}  // namespace brdffit
