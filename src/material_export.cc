// ggx fits as glTF and Mitsuba materials (see material_export.h for the mapping).
#include "brdffit/material_export.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/model.h"
#include "brdffit/render.h"

namespace brdffit {

namespace {

constexpr double kDielectricF0 = 0.04;                   // glTF's (IOR 1.5), and Mitsuba's at specular = 0.5
constexpr double kDiffuseThrough = 1.0 - kDielectricF0;  // the light the dielectric coat lets through

// The metallic value that matches a single (luminance) albedo a and f0 f; see the header.
double solve_metallic(double a, double f) {
  const double qa = kDielectricF0 * kDiffuseThrough, qb = -(a + kDiffuseThrough * f), qc = a;
  const double discriminant = qb * qb - 4.0 * qa * qc;
  if (discriminant < 0.0) return 0.0;  // f0 darker than any dielectric's: the closest is m = 0
  // Both roots match; the larger one when it is a valid 1 - m, i.e. the least metallic material.
  // (The other root is then at most 1 only for very dark colours.)
  const double smaller = (-qb - std::sqrt(discriminant)) / (2.0 * qa), larger = (-qb + std::sqrt(discriminant)) / (2.0 * qa);
  const double t = larger <= 1.0 + 1e-12 ? larger : smaller;
  return std::clamp(1.0 - t, 0.0, 1.0);
}

std::string material_name(const FitDocument& document) {
  if (document.json.contains("material") && document.json["material"].is_string())
    return document.json["material"].get<std::string>();
  return std::filesystem::path(document.input_path).stem().string();
}

const FitResult& ggx_result(const FitDocument& document) {
  for (const FitResult& fit : document.results) {
    if (fit.model != "ggx") continue;
    if (!fit.ok) fail("{}: the ggx fit failed ({}): nothing to export", document.path, fit.error);
    return fit;
  }
  fail("{}: has no ggx fit; export maps the ggx model (fit with --models including ggx)", document.path);
}

// Text that can stand inside an XML comment or attribute: escaped, and no "--" (which ends a comment).
std::string xml_text(const std::string& text) {
  std::string out;
  for (char c : escape_markup(text)) out += c == '-' && !out.empty() && out.back() == '-' ? " -" : std::string(1, c);
  return out;
}

std::string xml_id(const std::string& name) {
  std::string id = name;
  for (char& c : id)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
  return id.empty() || std::isdigit(static_cast<unsigned char>(id[0])) ? "m_" + id : id;
}

}  // namespace

MetallicRoughness metallic_roughness(const Rgb<double>& albedo, const Rgb<double>& f0, double roughness) {
  MetallicRoughness out;
  out.roughness = std::clamp(roughness, 0.0, 1.0);
  out.metallic = solve_metallic(rec709_luminance(albedo), rec709_luminance(f0));
  const double m = out.metallic, diffuse = (1.0 - m) * kDiffuseThrough;
  for (int c = 0; c < 3; ++c) {
    const double b = (diffuse * albedo[c] + m * (f0[c] - kDielectricF0 * (1.0 - m))) / (diffuse * diffuse + m * m);
    out.base_color[c] = std::clamp(b, 0.0, 1.0);
  }
  out.albedo = diffuse * out.base_color;
  out.f0 = (kDielectricF0 * (1.0 - m) + m * out.base_color.array()).matrix();
  return out;
}

MetallicRoughness metallic_roughness_of(const FitDocument& document) {
  const FitResult& fit = ggx_result(document);
  const Model& ggx = *find_model("ggx");
  const int albedo = ggx.offset_of("albedo"), f0 = ggx.offset_of("f0"), roughness = ggx.offset_of("roughness");
  if (static_cast<int>(fit.values.size()) != ggx.num_values())
    fail("{}: the ggx result has {} values, the model has {}", document.path, fit.values.size(), ggx.num_values());
  // Colours are per channel in `values` even for per-channel fits; the roughness is then the mean.
  double r = fit.values[roughness];
  if (fit.channel_values.size() == 3)
    r = (fit.channel_values[0][roughness] + fit.channel_values[1][roughness] + fit.channel_values[2][roughness]) / 3.0;
  const Rgb<double> a(fit.values[albedo], fit.values[albedo + 1], fit.values[albedo + 2]);
  const Rgb<double> f(fit.values[f0], fit.values[f0 + 1], fit.values[f0 + 2]);
  return metallic_roughness(a, f, r);
}

std::string gltf_material(const FitDocument& document) {
  const FitResult& fit = ggx_result(document);
  const MetallicRoughness mr = metallic_roughness_of(document);
  const Model& ggx = *find_model("ggx");
  const auto fitted = [&](const char* name) {
    const int offset = ggx.offset_of(name);
    return Rgb<double>(fit.values[offset], fit.values[offset + 1], fit.values[offset + 2]);
  };
  const nlohmann::json material = {
      {"name", material_name(document)},
      {"pbrMetallicRoughness",
       {{"baseColorFactor", {mr.base_color[0], mr.base_color[1], mr.base_color[2], 1.0}},
        {"metallicFactor", mr.metallic},
        {"roughnessFactor", mr.roughness}}},
      {"extras",
       {{"brdffit",
         {{"result", document.path},
          {"input", document.input_path},
          {"model", "ggx"},
          {"fitted", {{"albedo", json_array(fitted("albedo"))}, {"f0", json_array(fitted("f0"))}, {"roughness", mr.roughness}}},
          {"implied_at_normal_incidence", {{"albedo", json_array(mr.albedo)}, {"f0", json_array(mr.f0)}}},
          {"metrics", fit_result_json(fit)["metrics"]}}}}}};
  const nlohmann::json gltf = {{"asset", {{"version", "2.0"}, {"generator", "brdffit " BRDFFIT_VERSION}}},
                               {"materials", {material}}};
  return gltf.dump(2) + "\n";
}

std::string mitsuba_bsdf(const FitDocument& document) {
  const FitResult& fit = ggx_result(document);
  const MetallicRoughness mr = metallic_roughness_of(document);
  const std::string name = material_name(document);
  std::string xml = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n";
  xml += fmt::format(
      "<!-- brdffit {}: the ggx fit of {} ({} error {:.4g}) as Mitsuba 3's principled BSDF.\n"
      "     base_color, metallic and roughness as in brdffit's glTF export; specular 0.5 is a dielectric F0 of 0.04.\n"
      "     Implied at normal incidence: albedo {:.4f} {:.4f} {:.4f}, f0 {:.4f} {:.4f} {:.4f}.\n"
      "     Include this file in a scene and refer to the material as <ref id=\"{}\"/>. -->\n",
      BRDFFIT_VERSION, xml_text(document.input_path), xml_text(document.json.value("metric", "cosine")),
      fit.metrics.get(parse_metric(document.json.value("metric", "cosine")).value_or(Metric::Cosine)), mr.albedo[0],
      mr.albedo[1], mr.albedo[2], mr.f0[0], mr.f0[1], mr.f0[2], xml_text(xml_id(name)));
  xml += "<scene version=\"3.0.0\">\n";
  xml += fmt::format("    <bsdf type=\"principled\" id=\"{}\">\n", xml_text(xml_id(name)));
  xml += fmt::format("        <rgb name=\"base_color\" value=\"{:.6f}, {:.6f}, {:.6f}\"/>\n", mr.base_color[0],
                     mr.base_color[1], mr.base_color[2]);
  xml += fmt::format("        <float name=\"metallic\" value=\"{:.6f}\"/>\n", mr.metallic);
  xml += fmt::format("        <float name=\"roughness\" value=\"{:.6f}\"/>\n", mr.roughness);
  xml += "        <float name=\"specular\" value=\"0.5\"/>\n";
  xml += "    </bsdf>\n</scene>\n";
  return xml;
}

}  // namespace brdffit
