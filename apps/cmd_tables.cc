// `brdffit info`, `lookup`, `bake`: measured tables.
#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include <cmath>

#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/measured.h"
#include "brdffit/merl.h"
#include "brdffit/model.h"
#include "brdffit/result_json.h"
#include "cli_common.h"
#include "commands.h"

namespace brdffit::cli {

namespace {

void run_info(const std::string& path, bool json) {
  check_table_argument(path, "info");
  const TableInfo info = describe_measured(path);
  const bool checked = std::isfinite(info.reciprocity) || !info.albedo_by_incidence.empty();  // not for a CSV
  auto number = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); };
  if (json) {
    nlohmann::json out = {{"format", info.format},
                          {"resolution", info.resolution},
                          {"valid", info.valid},
                          {"invalid", info.invalid},
                          {"zero", info.zero},
                          {"min", json_array(info.min)},
                          {"max", json_array(info.max)},
                          {"albedo", info.albedo.allFinite() ? json_array(info.albedo) : nlohmann::json(nullptr)}};
    if (checked) {
      nlohmann::json albedo = nlohmann::json::array();
      for (const TableInfo::AlbedoAt& a : info.albedo_by_incidence)
        albedo.push_back({{"theta_deg", a.theta_deg}, {"albedo", json_array(a.albedo)}});
      out["albedo_by_incidence"] = albedo;
      out["reciprocity"] = {{"median_abs_log_ratio", number(info.reciprocity)},
                            {"cosine_share", number(info.reciprocity_cosine_share)}};
      out["isotropic"] = info.isotropic;
      out["isotropy"] = info.isotropy;
      out["anisotropy"] = number(info.anisotropy);
    }
    out["warnings"] = info.warnings;
    say("{}\n", json_text(out));
    return;
  }
  say("{}\n  format      {}\n  resolution  {}\n  valid       {}\n  invalid     {}\n", path, info.format,
      info.resolution, info.valid, info.invalid);
  if (info.valid > 0)
    say("  zero        {} ({:.1f}% of the valid entries)\n", info.zero, 100.0 * info.zero / info.valid);
  say("  min f       {:.6g} {:.6g} {:.6g} (1/sr)\n  max f       {:.6g} {:.6g} {:.6g} (1/sr)\n", info.min[0],
      info.min[1], info.min[2], info.max[0], info.max[1], info.max[2]);
  if (info.albedo.allFinite())
    say("  albedo      {:.6g} {:.6g} {:.6g} (directional, normal incidence)\n", info.albedo[0], info.albedo[1],
        info.albedo[2]);
  if (checked) {
    for (const TableInfo::AlbedoAt& a : info.albedo_by_incidence)
      say("  albedo {:>2g}°  {:.4g} {:.4g} {:.4g}\n", a.theta_deg, a.albedo[0], a.albedo[1], a.albedo[2]);
    say("  reciprocity {:.3g} (median |ln f(l,v)/f(v,l)|; share of ln(cosθv/cosθl) in it {:.2f})\n", info.reciprocity,
        info.reciprocity_cosine_share);
    say("  isotropic   {} (by its {}; turning about the normal changes f by {:.3g})\n", info.isotropic ? "yes" : "no",
        info.isotropy, info.anisotropy);
  }
  for (const std::string& warning : info.warnings) say("  warning: {}\n", warning);
}

struct LookupArgs {
  std::string path, light, view, interp;
  bool json = false;
};

void run_lookup(const LookupArgs& args) {
  check_table_argument(args.path, "lookup");
  const Vec3 l = normalized_or_zero(option_value([&] { return parse_vec3(args.light, "--light"); }));
  const Vec3 v = normalized_or_zero(option_value([&] { return parse_vec3(args.view, "--view"); }));
  if (l.isZero() || v.isZero()) fail_usage("--light and --view must be non-zero directions");
  const std::unique_ptr<MeasuredBrdf> table = open_measured(args.path);
  Rgb<double> f;
  if (const auto* merl = dynamic_cast<const MerlTable*>(table.get())) {
    f = merl->lookup(l, v, args.interp == "nearest" ? Interpolation::Nearest : Interpolation::Trilinear);
  } else {
    if (!args.interp.empty())
      fail_usage("--interp applies to MERL tables only ({} is not one; it is evaluated continuously)", args.path);
    f = table->eval(l, v);
  }
  if (args.json)
    say("{}\n", json_text(nlohmann::json({{"brdf", json_array(f)}})));
  else
    say("brdf {:.9g} {:.9g} {:.9g}\n", f[0], f[1], f[2]);
}

struct BakeArgs {
  std::string model, out;
  std::vector<std::string> params;
};

void run_bake(const BakeArgs& args) {
  const Model* model = &named_model(args.model, "bake");
  const std::vector<double> values = option_value([&] { return parameter_values(*model, args.params); });
  check_outputs({}, {args.out});
  write_merl(args.out, [&](const Vec3& l, const Vec3& v) -> Rgb<double> {
    // Stylised models have no BRDF: tabulate their shaded value divided by cosθi.
    if (const auto f = model->brdf(values.data(), l, v)) return *f;
    return model->shade(values.data(), l, v) / l.z();
  });
  say("wrote {} ({} as a 90x90x180 MERL table)\n", args.out, model->name());
}

}  // namespace

void add_table_commands(CLI::App& app) {
  auto info_path = std::make_shared<std::string>();
  auto info_json = std::make_shared<bool>(false);
  CLI::App* info = app.add_subcommand("info", "Describe a measured table (MERL, RGL, CSV)");
  info->add_option("file", *info_path, "Table")->required();
  info->add_flag("--json", *info_json, "Print JSON");
  info->callback([info_path, info_json] { run_info(*info_path, *info_json); });

  auto lookup_args = std::make_shared<LookupArgs>();
  CLI::App* lookup = app.add_subcommand(
      "lookup", "The measured BRDF f (1/sr) at one light/view pair (normal +z; directions need not be unit)");
  lookup->add_option("file", lookup_args->path, "Table (MERL or RGL)")->required();
  lookup->add_option("--light", lookup_args->light, "Light direction X,Y,Z (normal is +z)")->required();
  lookup->add_option("--view", lookup_args->view, "View direction X,Y,Z")->required();
  lookup->add_option("--interp", lookup_args->interp, "MERL: nearest bin or trilinear between bin centres (default)")
      ->check(CLI::IsMember({"nearest", "trilinear"}));
  lookup->add_flag("--json", lookup_args->json, "Print JSON");
  lookup->callback([lookup_args] { run_lookup(*lookup_args); });

  auto bake_args = std::make_shared<BakeArgs>();
  CLI::App* bake = app.add_subcommand("bake", "Write a model as a MERL table");
  add_models_option(bake, bake_args->model, "The model to tabulate");
  add_positional_model(bake, bake_args->model);
  bake->add_option("--param", bake_args->params, "NAME=VALUE (colours: one value or R,G,B); repeatable");
  bake->add_option("-o,--out", bake_args->out, "Output .binary file")->required();
  bake->callback([bake_args] { run_bake(*bake_args); });
}

}  // namespace brdffit::cli
