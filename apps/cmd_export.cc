// `brdffit export`: a fit as a renderer's material, in any format of material_formats().
#include <string>
#include <vector>

#include "brdffit/io.h"
#include "brdffit/material_export.h"
#include "brdffit/registry.h"
#include "brdffit/result_json.h"
#include "cli_common.h"
#include "commands.h"

namespace brdffit::cli {

namespace {

struct ExportArgs {
  std::string result, model, format, out;
  bool force = false;
};

void run_export(const ExportArgs& args) {
  ExportRequest request;
  request.format = option_value([&] { return material_format(args.format, args.out); });
  request.model = args.model.empty() ? args.model : named_model(args.model, "export").name();
  request.force = args.force;
  check_document_arguments({args.result});
  check_outputs({args.result}, {args.out});
  const MaterialExport exported = export_material(read_fit_document(args.result), request);
  for (const std::string& warning : exported.warnings) say(stderr, "warning: {}\n", warning);
  write_file_atomic(args.out, exported.text);
  const Model& model = *find_model(exported.material.model);
  std::string values;
  size_t offset = 0;
  for (const ParamSpec& p : model.parameters()) {
    const std::vector<double> value(exported.material.values.begin() + offset,
                                    exported.material.values.begin() + offset + p.channels);
    values += " " + p.name + "=" + format_values(value, "{:.4g}");
    offset += p.channels;
  }
  say("wrote {}: the {} material{}\n", args.out, model.name(), values);
  if (!exported.converted) {
    say("  the {} fit unchanged ({} error {:.4g})\n", exported.source_model, exported.metric, exported.fit_error);
    return;
  }
  say("  converted from the {} fit {} ({} error {:.4g}); on the original data, all samples: converted {:.4g}, "
      "the {} fit {:.4g}; the converted material against the {} fit on fixed directions: {} {:.4g}\n",
      exported.source_model, exported.conversion, exported.metric, exported.fit_error, exported.converted_error,
      exported.source_model, exported.source_error_on_data, exported.source_model, exported.metric,
      exported.converted_vs_fit);
}

// The models each format writes unchanged, for -m's help: "gltf, gltf-specular or ..., openpbr, ...".
std::string native_models_help() {
  std::string text;
  for (const MaterialFormatInfo& info : material_formats())
    text += (text.empty() ? "" : ", ") + join_words(info.native_models, "or");
  return text;
}

}  // namespace

void add_export_command(CLI::App& app) {
  auto export_args = std::make_shared<ExportArgs>();
  CLI::App* export_cmd = app.add_subcommand(
      "export", "Write a fit as the renderer's material: " + material_format_list(&MaterialFormatInfo::title));
  export_cmd->add_option("result", export_args->result, "Result document (from fit or batch)")->required();
  add_models_option(export_cmd, export_args->model,
                    "The fit to export (default: the format's own: " + native_models_help() +
                        "; another fit is converted and its error reported)");
  export_cmd->add_option("--format", export_args->format,
                         material_format_list(&MaterialFormatInfo::name) + " (default: from --out's extension)");
  export_cmd
      ->add_option("-o,--out", export_args->out,
                   "File to write (" + material_format_list(&MaterialFormatInfo::extension) + ")")
      ->required();
  export_cmd->add_flag("--force", export_args->force, "Export a fit whose verdict is poor or failed (with a warning)");
  export_cmd->callback([export_args] { run_export(*export_args); });
}

}  // namespace brdffit::cli
