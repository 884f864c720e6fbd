#include "brdffit/result_json.h"

#include <algorithm>
#include <cmath>

#include "brdffit/error.h"
#include "brdffit/io.h"

namespace brdffit {

namespace {

constexpr int kSchema = 1;

// JSON has no NaN: a number that is not finite is written as null.
nlohmann::json number(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

nlohmann::json numbers(const std::vector<double>& xs) {
  if (xs.size() == 1) return number(xs[0]);
  nlohmann::json array = nlohmann::json::array();
  for (double x : xs) array.push_back(number(x));
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

nlohmann::json metrics_json(const Metrics& m) {
  return {{"cosine", number(m.cosine)}, {"log", number(m.log)}, {"relative", number(m.relative)},
          {"l2", number(m.l2)},         {"max", number(m.max)},           {"typical", number(m.typical)}};
}

Verdict verdict_from(const std::string& name, const std::string& path) {
  for (Verdict v : {Verdict::Good, Verdict::Poor, Verdict::Failed})
    if (name == verdict_name(v)) return v;
  fail("{}: unknown verdict '{}' (good, poor or failed)", path, name);
}

const char* loss_name(LossKind loss) {
  switch (loss) {
    case LossKind::Huber: return "huber";
    case LossKind::Cauchy: return "cauchy";
    case LossKind::None: break;
  }
  return "none";
}

}  // namespace

nlohmann::json fit_result_json(const FitResult& result) {
  nlohmann::json parameters = nlohmann::json::object();
  for (const ParameterEstimate& p : result.parameters)
    parameters[p.name] = {{"value", numbers(p.value)},
                          {"stddev", numbers(p.stddev)},
                          {"identifiable", p.identifiable},
                          {"at_bound", p.at_bound}};
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
  return {{"schema", kSchema},
          {"tool", "brdffit " BRDFFIT_VERSION},
          {"input", {{"path", input_path}, {"sha256", sha256.empty() ? nlohmann::json(nullptr) : nlohmann::json(sha256)}}},
          {"samples", data.size()},
          {"weighting", data.weighting},
          {"metric", metric_name(options.metric)},
          {"per_channel", options.per_channel},
          {"loss", loss_name(options.loss)},
          {"models", models}};
}

FitDocument read_fit_document(const std::string& path) {
  FitDocument doc;
  doc.path = path;
  try {
    doc.json = nlohmann::json::parse(read_file(path));
  } catch (const nlohmann::json::exception& e) {
    fail("{}: not a JSON file: {}", path, e.what());
  }
  try {
    if (!doc.json.is_object() || doc.json.value("schema", 0) != kSchema)
      fail("{}: not a brdffit result (schema {} expected)", path, kSchema);
    doc.input_path = doc.json.at("input").at("path").get<std::string>();
    for (const auto& m : doc.json.at("models")) {
      FitResult r;
      r.model = m.at("model").get<std::string>();
      r.ok = m.at("status") == "ok";
      if (!r.ok && m.at("error").is_string()) r.error = m.at("error").get<std::string>();
      r.verdict = verdict_from(m.value("verdict", r.ok ? "good" : "failed"), path);
      r.warnings = m.value("warnings", std::vector<std::string>{});
      r.values = m.at("values").get<std::vector<double>>();
      if (m.contains("channel_values")) r.channel_values = m.at("channel_values").get<std::vector<std::vector<double>>>();
      for (const auto& [name, p] : m.at("parameters").items()) {
        ParameterEstimate e;
        e.name = name;
        e.value = read_numbers(p.at("value"));
        e.stddev = read_numbers(p.at("stddev"));
        e.identifiable = p.value("identifiable", true);
        e.at_bound = p.value("at_bound", false);
        r.parameters.push_back(e);
      }
      // JSON objects come back sorted by name; a known model's own order reads better.
      if (const Model* model = find_model(r.model)) {
        const std::vector<ParamSpec> specs = model->parameters();
        auto position = [&](const ParameterEstimate& e) {
          return std::find_if(specs.begin(), specs.end(), [&](const ParamSpec& p) { return p.name == e.name; }) -
                 specs.begin();
        };
        std::stable_sort(r.parameters.begin(), r.parameters.end(),
                         [&](const ParameterEstimate& a, const ParameterEstimate& b) { return position(a) < position(b); });
      }
      const auto& metrics = m.at("metrics");
      auto metric = [&](const char* key) { return metrics.at(key).is_number() ? metrics.at(key).get<double>() : NAN; };
      r.metrics = {metric("cosine"), metric("log"), metric("relative"), metric("l2"), metric("max")};
      if (metrics.contains("typical")) r.metrics.typical = metric("typical");
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

}  // namespace brdffit
