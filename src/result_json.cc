#include "brdffit/result_json.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/measured.h"
#include "brdffit/registry.h"

namespace brdffit {

namespace {

constexpr int kSchema = 1;

nlohmann::json numbers(const std::vector<double>& xs) {
  if (xs.size() == 1) return number_or_null(xs[0]);
  nlohmann::json array = nlohmann::json::array();
  for (double x : xs) array.push_back(number_or_null(x));
  return array;
}

std::vector<double> read_numbers(const nlohmann::json& j) {
  std::vector<double> xs;
  auto read = [](const nlohmann::json& x) { return x.is_number() ? x.get<double>() : NAN; };
  if (j.is_array())
    for (const auto& x : j) xs.push_back(read(x));
  else
    xs.push_back(read(j));
  return xs;
}

Verdict verdict_from(const std::string& name, const std::string& path) {
  for (Verdict v : {Verdict::Good, Verdict::Poor, Verdict::Failed})
    if (name == verdict_name(v)) return v;
  fail("{}: unknown verdict '{}' (good, poor or failed)", path, name);
}

// The flattened value slots of a model: for each value, its parameter.
std::vector<const ParamSpec*> value_specs(const Model& model) {
  std::vector<const ParamSpec*> slots;
  for (const ParamSpec& p : model.parameters())
    for (int c = 0; c < p.channels; ++c) slots.push_back(&p);
  return slots;
}

// Fails naming the file and field unless x lies within the parameter's bounds (a hair of
// rounding allowed: documents store values to 17 digits).
void check_in_bounds(double x, const ParamSpec& spec, const std::string& where) {
  const double slack = 1e-9 * std::max(1.0, spec.upper - spec.lower);
  if (!std::isfinite(x) || x < spec.lower - slack || x > spec.upper + slack)
    fail("{}: {} = {} is outside the bounds [{}, {}] of {}", where, spec.name, x, spec.lower, spec.upper, spec.name);
}

// A fitted value vector as the model needs it: one finite number per flattened value, each in
// its parameter's bounds.
std::vector<double> read_value_vector(const nlohmann::json& j, const Model& model, const std::string& where) {
  const std::vector<const ParamSpec*> slots = value_specs(model);
  if (!j.is_array() || j.size() != slots.size())
    fail("{}: expected an array of the {} values of {}, found {}", where, slots.size(), model.name(),
         j.is_array() ? std::to_string(j.size()) + " values" : std::string(j.type_name()));
  std::vector<double> values;
  for (size_t i = 0; i < slots.size(); ++i) {
    if (!j[i].is_number()) fail("{}[{}]: not a number", where, i);
    values.push_back(j[i].get<double>());
    check_in_bounds(values.back(), *slots[i], fmt::format("{}[{}]", where, i));
  }
  return values;
}

// Checks a model result read back from `path` against the model's parameter list: the value
// vectors' sizes, every parameter's name, number of values and bounds. Failed results carry no
// values to check.
void validate_result(const FitResult& r, const Model& model, const std::string& where) {
  if (!r.ok) return;
  if (!r.channel_values.empty() && r.channel_values.size() != 3)
    fail("{}.channel_values: {} vectors, expected one per channel (3)", where, r.channel_values.size());
  for (const ParameterEstimate& e : r.parameters) {
    const ParamSpec* spec = model.find_parameter(e.name);
    if (!spec) fail("{}.parameters: {} has no parameter '{}'", where, model.name(), e.name);
    const std::string field = where + ".parameters." + e.name + ".value";
    if (e.value.size() != static_cast<size_t>(spec->channels) && e.value.size() != 3)
      fail("{}: {} values, {} has {}", field, e.value.size(), e.name, spec->channels);
    for (double x : e.value) check_in_bounds(x, *spec, field);
  }
}

// What a document's optional top-level fields must be when present: compare, report, export
// and --resume read them without checking again.
struct OptionalField {
  const char* name;
  bool (*is)(const nlohmann::json&);
  const char* expected;
};
const OptionalField kOptionalFields[] = {
    {"material", [](const nlohmann::json& j) { return j.is_string(); }, "a string"},
    {"metric", [](const nlohmann::json& j) { return j.is_string(); }, "a string"},
    {"weighting", [](const nlohmann::json& j) { return j.is_string(); }, "a string"},
    {"loss", [](const nlohmann::json& j) { return j.is_string(); }, "a string"},
    {"samples", [](const nlohmann::json& j) { return j.is_number_unsigned(); }, "a whole number"},
    {"per_channel", [](const nlohmann::json& j) { return j.is_boolean(); }, "true or false"},
    {"images", [](const nlohmann::json& j) { return j.is_array() || j.is_object(); }, "an array or object"},
    {"sphere", [](const nlohmann::json& j) { return j.is_object(); }, "an object"},
};

}  // namespace

size_t json_depth(const std::string& text) {
  size_t depth = 0, deepest = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;  // the escaped character is no quote
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return deepest;
}

void check_json_depth(const std::string& text, const std::string& path, const std::string& what) {
  // nlohmann's values copy, compare and destroy recursively: 200,000 brackets overflow the stack.
  const size_t depth = json_depth(text);
  if (depth > kMaxJsonDepth)
    fail("{}: not a {}: nested {} levels deep, more than the limit of {}", path, what, depth, kMaxJsonDepth);
}

nlohmann::json read_json_file(const std::string& path, const std::string& what) {
  const std::string text = read_file(path);
  check_json_depth(text, path, what);
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    fail("{}: not a {}: {}", path, what, e.what());
  }
}

const nlohmann::json* json_field(const nlohmann::json& j, std::initializer_list<const char*> keys) {
  const nlohmann::json* at = &j;
  for (const char* key : keys) {
    if (!at->is_object()) return nullptr;
    const auto it = at->find(key);
    if (it == at->end()) return nullptr;
    at = &*it;
  }
  return at;
}

std::string json_text(const nlohmann::json& j, int indent) {
  return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

void put_name(nlohmann::json& object, const std::string& key, const std::string& name) {
  if (valid_utf8(name)) {
    object[key] = name;
    return;
  }
  object[key] = nlohmann::json::parse(json_text(nlohmann::json(name)));  // bad bytes as U+FFFD
  std::string hex;
  for (const char c : name) hex += fmt::format("{:02x}", static_cast<unsigned char>(c));
  object[key + "_bytes"] = hex;
}

std::optional<std::string> get_name(const nlohmann::json& object, const std::string& key, const std::string& where) {
  if (!object.is_object()) return std::nullopt;
  const auto bytes = object.find(key + "_bytes");
  if (bytes != object.end()) {
    bool ok = bytes->is_string() && bytes->get_ref<const std::string&>().size() % 2 == 0;
    const std::string hex = ok ? bytes->get<std::string>() : std::string();
    std::string name;
    for (size_t i = 0; ok && i < hex.size(); i += 2) {
      ok = std::isxdigit(static_cast<unsigned char>(hex[i])) && std::isxdigit(static_cast<unsigned char>(hex[i + 1]));
      if (ok) name += static_cast<char>(std::stoi(hex.substr(i, 2), nullptr, 16));
    }
    if (!ok) fail("{}.{}_bytes: not a name's bytes in hex", where, key);
    return name;
  }
  const auto value = object.find(key);
  if (value == object.end() || !value->is_string()) return std::nullopt;
  return value->get<std::string>();
}

nlohmann::json number_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

std::string format_values(const std::vector<double>& xs, const char* format) {
  if (xs.size() == 1) return fmt::format(fmt::runtime(format), xs[0]);
  std::string out = "[";
  for (size_t i = 0; i < xs.size(); ++i) out += (i ? "," : "") + fmt::format(fmt::runtime(format), xs[i]);
  return out + "]";
}

const FitResult* find_result(const std::vector<FitResult>& results, const std::string& model) {
  for (const FitResult& result : results)
    if (result.model == model) return &result;
  return nullptr;
}

const FitResult* best_result(const std::vector<FitResult>& results, Metric metric) {
  const FitResult* best = nullptr;
  for (const FitResult& result : results) {
    const double error = result.metrics.get(metric);
    if (result.ok && result.verdict == Verdict::Good && std::isfinite(error) &&
        (!best || error < best->metrics.get(metric)))
      best = &result;
  }
  return best;
}

int count_poor(const std::vector<FitResult>& results) {
  return static_cast<int>(std::count_if(results.begin(), results.end(),
                                        [](const FitResult& r) { return r.ok && r.verdict == Verdict::Poor; }));
}

nlohmann::json metrics_json(const Metrics& metrics) {
  nlohmann::json out = nlohmann::json::object();
  for (const MetricInfo& info : kMetrics) out[info.name] = number_or_null(metrics.*info.value);
  return out;
}

Metrics metrics_from_json(const nlohmann::json& j) {
  Metrics metrics;
  if (!j.is_object()) return metrics;
  for (const MetricInfo& info : kMetrics) {
    const auto value = j.find(info.name);
    metrics.*info.value = value != j.end() && value->is_number() ? value->get<double>() : NAN;
  }
  return metrics;
}

nlohmann::json fit_result_json(const FitResult& result) {
  nlohmann::json parameters = nlohmann::json::object();
  for (const ParameterEstimate& p : result.parameters) {
    parameters[p.name] = {{"value", numbers(p.value)},
                          {"stddev", numbers(p.stddev)},
                          {"identifiable", p.identifiable},
                          {"at_bound", p.at_bound}};
    if (p.fixed) parameters[p.name]["fixed"] = true;  // held at a given value (--fix): not fitted
  }
  nlohmann::json out = {{"model", result.model},
                        {"status", result.ok ? "ok" : "failed"},
                        {"verdict", verdict_name(result.verdict)},
                        {"warnings", result.warnings},
                        {"error", result.ok ? nlohmann::json(nullptr) : nlohmann::json(result.error)},
                        {"parameters", parameters},
                        {"metrics", metrics_json(result.metrics)},
                        {"iterations", result.iterations},
                        {"termination", result.termination},
                        {"seconds", result.seconds}};
  // The exact flattened vectors, so a result can be re-evaluated without re-assembling them.
  out["values"] = result.values;
  if (!result.channel_values.empty()) out["channel_values"] = result.channel_values;
  return out;
}

nlohmann::json fit_document_json(const std::string& input_path, const SampleSet& data, const FitOptions& options,
                                 const std::vector<FitResult>& results) {
  nlohmann::json models = nlohmann::json::array();
  for (const FitResult& r : results) models.push_back(fit_result_json(r));
  std::string sha256;
  try {
    sha256 = sha256_file(input_path);
  } catch (const Error&) {
    // Inputs that are not a single file (a folder of photographs) have no one checksum.
  }
  nlohmann::json input = {{"sha256", sha256.empty() ? nlohmann::json(nullptr) : nlohmann::json(sha256)}};
  put_name(input, "path", absolute_path(input_path));
  nlohmann::json document = {{"schema", kSchema},
                             {"tool", "brdffit " BRDFFIT_VERSION},
                             {"input", input},
                             {"samples", data.size()},
                             {"weighting", data.weighting},
                             {"metric", metric_name(options.metric)},
                             {"per_channel", options.per_channel},
                             {"loss", loss_name(options.loss)},
                             {"models", models}};
  // Parameters held at given values (--fix), only when there are any: documents without stay as they were.
  for (const auto& [name, value] : options.fixed) document["fixed"][name] = value;
  return document;
}

FitDocument read_fit_document(const std::string& path) {
  FitDocument doc;
  doc.path = path;
  doc.json = read_json_file(path, "JSON file");
  try {
    const nlohmann::json* schema = json_field(doc.json, {"schema"});
    if (!schema || *schema != kSchema) fail("{}: not a brdffit result (schema {} expected)", path, kSchema);
    for (const OptionalField& field : kOptionalFields) {
      const nlohmann::json* value = json_field(doc.json, {field.name});
      if (value && !field.is(*value))
        fail("{}: {}: expected {}, found {}", path, field.name, field.expected, value->type_name());
    }
    const nlohmann::json* sha256 = json_field(doc.json, {"input", "sha256"});
    if (sha256 && !sha256->is_string() && !sha256->is_null())
      fail("{}: input.sha256: expected a string or null, found {}", path, sha256->type_name());
    const std::optional<std::string> input_path = get_name(doc.json.at("input"), "path", path + ": input");
    if (!input_path) fail("{}: input.path: missing or not a string", path);
    doc.input_path = *input_path;
    if (!doc.json.at("models").is_array()) fail("{}: models: not an array", path);
    size_t index = 0;
    for (const auto& m : doc.json.at("models")) {
      const std::string where = fmt::format("{}: models[{}]", path, index++);
      FitResult r;
      r.model = m.at("model").get<std::string>();
      const Model* model = find_model(r.model);
      if (!model) fail("{}.model: '{}' is not a model of this version of brdffit", where, r.model);
      r.model = model->name();  // a former name (gltf-clearcoat) as the model is now called
      const std::string status = m.at("status").get<std::string>();
      if (status != "ok" && status != "failed") fail("{}.status: '{}', expected ok or failed", where, status);
      r.ok = status == "ok";
      if (!r.ok && m.at("error").is_string()) r.error = m.at("error").get<std::string>();
      r.verdict = verdict_from(m.value("verdict", r.ok ? "good" : "failed"), path);
      r.warnings = m.value("warnings", std::vector<std::string>{});
      if (r.ok) {
        r.values = read_value_vector(m.at("values"), *model, where + ".values");
        if (m.contains("channel_values")) {
          const nlohmann::json& channels = m.at("channel_values");
          if (!channels.is_array() || channels.size() != 3)
            fail("{}.channel_values: expected one value vector per channel (3)", where);
          for (size_t c = 0; c < 3; ++c)
            r.channel_values.push_back(
                read_value_vector(channels[c], *model, fmt::format("{}.channel_values[{}]", where, c)));
        }
      } else {
        r.values = read_numbers(m.value("values", nlohmann::json::array()));  // nothing to use: kept for the record
      }
      for (const auto& [name, p] : m.at("parameters").items()) {
        ParameterEstimate e;
        e.name = name;
        e.value = read_numbers(p.at("value"));
        e.stddev = read_numbers(p.at("stddev"));
        e.identifiable = p.value("identifiable", true);
        e.at_bound = p.value("at_bound", false);
        e.fixed = p.value("fixed", false);
        r.parameters.push_back(e);
      }
      validate_result(r, *model, where);
      // JSON objects come back sorted by name; the model's own order reads better.
      {
        const std::vector<ParamSpec> specs = model->parameters();
        auto position = [&](const ParameterEstimate& e) {
          return std::find_if(specs.begin(), specs.end(), [&](const ParamSpec& p) { return p.name == e.name; }) -
                 specs.begin();
        };
        std::stable_sort(
            r.parameters.begin(), r.parameters.end(),
            [&](const ParameterEstimate& a, const ParameterEstimate& b) { return position(a) < position(b); });
      }
      const nlohmann::json& metrics = m.at("metrics");
      if (!metrics.is_object()) fail("{}.metrics: expected an object, found {}", where, metrics.type_name());
      r.metrics = metrics_from_json(metrics);
      r.iterations = m.value("iterations", 0);
      r.termination = m.value("termination", "");
      r.seconds = m.value("seconds", 0.0);
      doc.results.push_back(std::move(r));
    }
  } catch (const nlohmann::json::exception& e) {
    fail("{}: malformed brdffit result: {}", path, e.what());
  }
  return doc;
}

std::vector<std::string> read_summary_results(const std::string& path) {
  std::vector<std::string> results;
  const std::string text = read_file(path);
  check_json_depth(text, path, "batch summary");
  // Not JSON: not a summary (read as a result document, which says what is wrong).
  const nlohmann::json summary = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!summary.is_object() || !summary.contains("materials") || !summary["materials"].is_array()) return results;
  const std::filesystem::path folder = std::filesystem::path(absolute_path(path)).parent_path();
  size_t index = 0;
  for (const nlohmann::json& material : summary["materials"]) {
    const std::string where = fmt::format("{}: materials[{}]", path, index++);
    if (!material.is_object()) fail("{}: not an object", where);
    const nlohmann::json result = material.value("result", nlohmann::json());
    if (result.is_null()) continue;  // a material that failed has no document
    const std::optional<std::string> name = get_name(material, "result", where);
    if (!name || name->empty()) fail("{}.result: not a file name", where);
    results.push_back(absolute_path((folder / *name).string()));
  }
  return results;
}

std::vector<FitDocument> read_fit_documents(const std::vector<std::string>& inputs) {
  namespace fs = std::filesystem;
  std::vector<std::string> paths;
  for (const std::string& input : inputs) {
    std::error_code error;
    if (!fs::is_directory(input, error)) {
      const bool summary = fs::path(input).filename() == "summary.json";
      const std::vector<std::string> listed = summary ? read_summary_results(input) : std::vector<std::string>{};
      if (summary && !listed.empty())
        paths.insert(paths.end(), listed.begin(), listed.end());
      else
        paths.push_back(input);
      continue;
    }
    std::vector<std::string> found;
    for (const fs::directory_entry& entry : fs::directory_iterator(input, error))
      if (entry.is_regular_file() && entry.path().extension() == ".json" && entry.path().filename() != "summary.json")
        found.push_back(entry.path().string());
    if (error) fail("{}: cannot list the folder: {}", input, error.message());
    if (found.empty()) fail("{}: no result documents (.json) in this folder", input);
    std::sort(found.begin(), found.end());
    paths.insert(paths.end(), found.begin(), found.end());
  }
  // A shell glob over a batch folder names its documents and its summary: each document once.
  std::vector<FitDocument> documents;
  std::set<std::string> seen;
  for (const std::string& path : paths) {
    std::error_code error;
    const fs::path canonical = fs::weakly_canonical(path, error);
    if (seen.insert(error ? path : canonical.string()).second) documents.push_back(read_fit_document(path));
  }
  return documents;
}

std::vector<std::string> document_paths(const std::vector<FitDocument>& documents) {
  std::vector<std::string> paths;
  for (const FitDocument& document : documents) paths.push_back(document.path);
  return paths;
}

std::string fit_results_csv(const std::vector<FitResult>& results) {
  std::vector<std::pair<std::string, size_t>> columns;  // parameter name, components
  for (const FitResult& r : results)
    for (const ParameterEstimate& p : r.parameters)
      if (std::find(columns.begin(), columns.end(), std::pair(p.name, p.value.size())) == columns.end())
        columns.emplace_back(p.name, p.value.size());
  auto component_names = [](const std::string& name, size_t components) {
    if (components == 1) return std::vector<std::string>{name};
    return std::vector<std::string>{name + "_r", name + "_g", name + "_b"};
  };
  std::string csv = "model,status,verdict";
  for (const MetricInfo& info : kMetrics) csv += std::string(",") + info.name;
  csv += ",iterations,seconds";
  for (const auto& [name, components] : columns) {
    for (const std::string& c : component_names(name, components)) csv += "," + csv_field(c);
    for (const std::string& c : component_names(name + "_stddev", components)) csv += "," + csv_field(c);
    csv += "," + csv_field(name + "_at_bound") + "," + csv_field(name + "_identifiable") + "," +
           csv_field(name + "_fixed");
  }
  csv += "\n";
  auto number = [](double x) { return std::isfinite(x) ? fmt::format("{:.9g}", x) : std::string(); };
  for (const FitResult& r : results) {
    csv += fmt::format("{},{},{}", csv_field(r.model), r.ok ? "ok" : "failed", verdict_name(r.verdict));
    for (const MetricInfo& info : kMetrics) csv += fmt::format(",{:.9g}", r.metrics.*info.value);
    csv += fmt::format(",{},{:.3f}", r.iterations, r.seconds);
    for (const auto& [name, components] : columns) {
      const auto p = std::find_if(r.parameters.begin(), r.parameters.end(),
                                  [&name = name, components = components](const auto& e) {
                                    return e.name == name && e.value.size() == components;
                                  });
      if (p == r.parameters.end()) {
        csv += std::string(2 * components + 3, ',');
        continue;
      }
      for (double v : p->value) csv += "," + number(v);
      for (double s : p->stddev) csv += "," + number(s);
      csv += fmt::format(",{},{},{}", p->at_bound ? 1 : 0, p->identifiable ? 1 : 0, p->fixed ? 1 : 0);
    }
    csv += "\n";
  }
  return csv;
}

std::string material_name(const FitDocument& document) {
  if (const std::optional<std::string> name = get_name(document.json, "material", document.path)) return *name;
  return table_material_name(document.input_path);
}

}  // namespace brdffit
