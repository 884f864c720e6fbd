// Renderer materials from fits: choosing the fit, converting it when the format does not hold its
// model, scoring the conversion, and writing the file through the format's entry of
// material_formats() (material_export.h).
#include "brdffit/material_export.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <random>

#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/material_convert.h"
#include "brdffit/measured.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"

namespace brdffit {

namespace {

constexpr int kFixedDirectionPairs = 20000;  // MaterialExport::converted_vs_fit
constexpr uint64_t kFixedDirectionsSeed = 1;

// A fit's values for export: a per-channel fit's shape parameters are the mean of its channels'.
std::vector<double> export_values(const Model& model, const FitResult& fit, std::vector<std::string>& warnings) {
  if (static_cast<int>(fit.values.size()) != model.num_values())
    fail("the {} result has {} values, the model has {}", fit.model, fit.values.size(), model.num_values());
  std::vector<double> values = fit.values;
  if (fit.channel_values.size() == 3) {
    int offset = 0;
    for (const ParamSpec& p : model.parameters()) {
      if (p.channels == 1)
        values[offset] =
            (fit.channel_values[0][offset] + fit.channel_values[1][offset] + fit.channel_values[2][offset]) / 3;
      offset += p.channels;
    }
    warnings.push_back("a per-channel fit: its shape parameters are written as the mean of the three channels'");
  }
  return values;
}

// The fit's shaded values on the fixed directions of MaterialExport::converted_vs_fit: pairs
// uniform in solid angle (cosθ uniform in [0, 1), φ uniform) from a fixed seed, so that the
// metric estimates the same hemisphere integrals as on a densely measured table.
SampleSet fixed_directions(const Model& model, const std::vector<double>& values,
                           const std::vector<std::vector<double>>& per_channel_values) {
  SampleSet set;
  set.source = "fixed directions";
  set.weighting = "solid-angle";
  std::mt19937_64 rng(kFixedDirectionsSeed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto direction = [&] {
    const double z = unit(rng), phi = 2 * kPi * unit(rng), r = std::sqrt(1.0 - z * z);
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
  };
  for (int i = 0; i < kFixedDirectionPairs; ++i) {
    Sample s;
    s.l = direction();
    s.v = direction();
    s.value = shade_fitted(model, values, per_channel_values, s.l, s.v);
    set.samples.push_back(s);
  }
  return set;
}

// The model of `format` a fit of another model becomes.
std::string conversion_target(const MaterialFormatInfo& format, const std::string& source_model,
                              const std::vector<double>& values) {
  return format.conversion_target ? format.conversion_target(source_model, values) : format.native_models.front();
}

}  // namespace

MaterialExport export_material(const FitDocument& document, const ExportRequest& request) {
  const MaterialFormatInfo& format = material_format_info(request.format);
  const std::vector<std::string>& natives = format.native_models;
  const FitResult* fit = nullptr;
  if (request.model.empty()) {
    for (const std::string& model : natives)
      if (!fit) fit = find_result(document.results, model);
    if (!fit)
      fail("{}: has no {} fit; fit with -m {} to export it unchanged, or convert another fit with -m ({})",
           document.path, natives.front(), natives.front(), fmt::join(convertible_models(), ", "));
  } else {
    fit = find_result(document.results, request.model);
    if (!fit) fail("{}: has no {} fit", document.path, request.model);
  }
  MaterialExport out;
  out.source_model = fit->model;
  if (!fit->ok) fail("{}: the {} fit failed ({}): nothing to export", document.path, fit->model, fit->error);
  if (fit->verdict != Verdict::Good) {
    // The reason is the first "poor fit" warning: notes come before it (an isotropic form's).
    const auto poor = std::find_if(fit->warnings.begin(), fit->warnings.end(),
                                   [](const std::string& w) { return w.rfind("poor fit", 0) == 0; });
    const std::string why = poor != fit->warnings.end() ? " (" + *poor + ")"
                            : fit->warnings.empty()     ? ""
                                                        : " (" + fit->warnings.front() + ")";
    if (!request.force)
      fail("{}: the {} fit's verdict is {}{}; it does not describe the measurement. Export it anyway with --force",
           document.path, fit->model, verdict_name(fit->verdict), why);
    out.warnings.push_back(fmt::format("the {} fit's verdict is {}{}: exported because of --force", fit->model,
                                       verdict_name(fit->verdict), why));
  }
  const Model& source = *find_model(fit->model);
  const std::vector<double> values = export_values(source, *fit, out.warnings);
  const std::string metric_name = document.json.value("metric", "cosine");
  const Metric metric = parse_metric(metric_name).value_or(Metric::Cosine);
  out.metric = metric_name;
  out.fit_error = fit->metrics.get(metric);

  out.converted = std::find(natives.begin(), natives.end(), fit->model) == natives.end();
  out.material = out.converted ? convert_material(fit->model, values, conversion_target(format, fit->model, values))
                               : Material{"", fit->model, values};
  out.material.name = material_name(document);
  if (out.converted) {
    out.converted_vs_fit = evaluate_metrics(*find_model(out.material.model), out.material.values,
                                            fixed_directions(source, fit->values, fit->channel_values))
                               .get(metric);
    try {
      const SampleSet data = load_samples(document.input_path, SamplingOptions{});
      out.converted_error = evaluate_metrics(*find_model(out.material.model), out.material.values, data).get(metric);
      out.source_error_on_data = evaluate_metrics(source, fit->values, data, fit->channel_values).get(metric);
    } catch (const Error& e) {
      out.warnings.push_back(
          fmt::format("the converted material could not be scored on the original data: {}", e.what()));
    }
  }

  const Nesting* by_name = nesting_of(*find_model(out.material.model), fit->model);
  out.conversion = !out.converted ? "unchanged"
                   : by_name      ? fmt::format("parameter by parameter ({})", by_name->why)
                                  : "through the metallic-roughness core";
  const std::string conversion = out.converted ? fmt::format("converted from the {} fit {}", fit->model, out.conversion)
                                               : fmt::format("the {} fit, unchanged", fit->model);
  nlohmann::json provenance = {{"result", document.path},     {"input", document.input_path},
                               {"model", out.material.model}, {"source_model", fit->model},
                               {"converted", out.converted},  {"verdict", verdict_name(fit->verdict)},
                               {"metric", metric_name},       {"metrics", fit_result_json(*fit)["metrics"]}};
  if (out.converted) {
    provenance["converted_error_on_input"] = out.converted_error;
    provenance["converted_vs_fit"] = out.converted_vs_fit;
  }
  const std::string comment = fmt::format(
      "brdffit {}: fitted to {}: {} ({} error {:.4g}{}).", BRDFFIT_VERSION, document.input_path, conversion,
      metric_name, out.fit_error,
      out.converted ? fmt::format("; this converted material's error on the same data {:.4g}, against the fit on fixed "
                                  "directions {:.4g}",
                                  out.converted_error, out.converted_vs_fit)
                    : "");
  out.text = format.write(out.material, {provenance, comment});
  return out;
}

}  // namespace brdffit
