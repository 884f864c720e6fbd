// `brdffit render`: a sphere of a table or of a fitted model; `brdffit report`: one HTML page
// about fitted materials. Commands of brdffit-imaging (they need the image libraries).
#include <fmt/format.h>

#include <filesystem>

#include "brdffit/error.h"
#include "brdffit/imaging/image_io.h"
#include "brdffit/imaging/render.h"
#include "brdffit/imaging/report.h"
#include "brdffit/io.h"
#include "brdffit/measured.h"
#include "brdffit/registry.h"
#include "brdffit/result_json.h"
#include "cli_common.h"
#include "commands.h"
#include "fit_options.h"

namespace brdffit::cli {

namespace {

namespace fs = std::filesystem;

struct LightingArgs {
  std::string light, view;

  void add_to(CLI::App* command) {
    command->add_option("--light", light,
                        "Direction towards the light X,Y,Z (picture: x right, y up, z toward you; default -1,1,2)");
    command->add_option("--view", view, "Direction towards the camera X,Y,Z (default 0,0,1)");
  }
  SphereLighting lighting() const {
    SphereLighting lighting;
    if (!light.empty()) lighting.light = parse_vec3(light, "--light");
    if (!view.empty()) lighting.view = parse_vec3(view, "--view");
    light_in_camera_frame(lighting);  // rejects zero directions before any work
    return lighting;
  }
};

struct RenderArgs {
  std::string input, model, out;
  LightingArgs lighting;
  int size = 256;
  double reference = 0.0;
};

// render's picture without -o: beside the input, named after it (and the model): ggx fitted to
// red.json is red-ggx.png, the table red.binary is red.png.
std::string default_picture(const std::string& input, const std::string& model) {
  const fs::path path(input);
  return (path.parent_path() / (path.stem().string() + (model.empty() ? "" : "-" + model) + ".png")).string();
}

void run_render(RenderArgs args) {
  const bool document_input = fs::path(args.input).extension() == ".json";
  if (document_input && args.model.empty()) {
    std::string names;
    for (const FitResult& r : read_fit_document(args.input).results) names += (names.empty() ? "" : ", ") + r.model;
    fail_usage("{}: choose the model to render with -m ({})", args.input, names);
  }
  if (!document_input && !args.model.empty())
    fail_usage("-m applies to result documents (.json); {} is a table", args.input);
  if (!args.model.empty()) args.model = named_model(args.model, "render").name();
  if (args.out.empty()) args.out = default_picture(args.input, args.model);
  check_outputs({args.input}, {args.out});
  const SphereLighting lighting = option_value([&] { return args.lighting.lighting(); });
  cv::Mat sphere;
  std::string what, reference_from = "the sphere's 99th percentile";
  const cv::Mat mask = sphere_mask(args.size);
  double reference = args.reference;
  if (reference > 0.0) reference_from = "--reference";
  if (document_input) {
    const FitDocument document = read_fit_document(args.input);
    std::string names;
    for (const FitResult& r : document.results) names += (names.empty() ? "" : ", ") + r.model;
    const FitResult* fit = find_result(document.results, args.model);
    if (!fit) fail_usage("{}: has no {} result (it has {})", args.input, args.model, names);
    if (!fit->ok) fail("{}: the {} fit failed ({}): nothing to render", args.input, args.model, fit->error);
    const Model* model = find_model(args.model);
    if (!model) fail("{}: {} is not a model of this version of brdffit", args.input, args.model);
    sphere = render_fitted_sphere(*model, *fit, lighting, args.size);
    what = args.model + " fitted to " + document.input_path;
    // The fitted table's own reference, so that `render TABLE` and `render FIT` pictures compare.
    if (!(reference > 0.0) && !stores_linear_values(args.out)) try {
        reference =
            tone_reference(render_measured_sphere(*open_measured(document.input_path), lighting, args.size), mask);
        reference_from = "the measured table's, as `brdffit render " + document.input_path + "` uses";
      } catch (const Error&) {
        // Not a readable table (samples, photographs, a moved file): the fit's own sphere.
      }
  } else {
    sphere = render_measured_sphere(*open_measured(args.input), lighting, args.size);
    what = args.input;
  }
  if (stores_linear_values(args.out)) {
    write_image(args.out, sphere, Encoding::Float);
    say("wrote {} ({}, {}x{} linear f·cosθi)\n", args.out, what, args.size, args.size);
    return;
  }
  if (!(reference > 0.0)) reference = tone_reference(sphere, mask);
  write_image(args.out, tone_map(sphere, reference), Encoding::Srgb8);
  say("wrote {} ({}, {}x{}, tone reference {:.6g}: {})\n", args.out, what, args.size, args.size, reference,
      reference_from);
}

struct ReportArgs {
  std::vector<std::string> results;
  std::string out, metric;
  LightingArgs lighting;
  int top = 0, size = 160;
};

void run_report(const ReportArgs& args) {
  check_document_arguments(args.results);
  check_outputs(args.results, {args.out});
  const std::vector<FitDocument> documents = read_fit_documents(args.results);
  std::vector<std::string> inputs = document_paths(documents);
  for (const FitDocument& document : documents) inputs.push_back(document.input_path);
  check_outputs(inputs, {args.out});
  ReportOptions options;
  if (!args.metric.empty()) options.metric = metric_from_name(args.metric, "--metric");
  options.lighting = option_value([&] { return args.lighting.lighting(); });
  options.top = args.top;
  options.sphere_size = args.size;
  options.progress = [](size_t index, size_t count, const std::string& material) {
    inform(stderr, "[{}/{}] {}\n", index + 1, count, material);
  };
  const std::string page = report_html(documents, options);
  write_file_atomic(args.out, page);
  say("wrote {} ({}, {:.1f} MB)\n", args.out, count_of(documents.size(), "material"), page.size() / 1e6);
}

}  // namespace

void add_render_commands(CLI::App& app) {
  auto render = std::make_shared<RenderArgs>();
  CLI::App* render_cmd = app.add_subcommand("render", imaging_summary("render"));
  render_cmd->add_option("input", render->input, "Measured table (MERL, RGL), or a result document with -m")
      ->required();
  add_models_option(render_cmd, render->model, "The fitted model to render from a result document");
  render->lighting.add_to(render_cmd);
  render_cmd->add_option("--size", render->size, "Picture size in pixels")->check(CLI::Range(8, 8192));
  render_cmd
      ->add_option("--reference", render->reference,
                   "PNG: the f·cosθi shown at about 75% grey (default: the 99th percentile of the measured table's "
                   "sphere, for a fit too, so that pictures of a table and of its fits compare; a fit's own "
                   "when its table cannot be read)")
      ->check(CLI::PositiveNumber);
  render_cmd->add_option("-o,--out", render->out,
                         "Picture: .png (tone-mapped sRGB) or .exr (linear); default: beside the input, named after "
                         "it and the model (red.json -m ggx: red-ggx.png; red.binary: red.png)");
  render_cmd->callback([render] { run_render(*render); });

  auto report = std::make_shared<ReportArgs>();
  CLI::App* report_cmd = app.add_subcommand("report", imaging_summary("report"));
  report_cmd->add_option("results", report->results, "Result documents, or folders of them (a batch's --out)")
      ->required();
  report_cmd->add_option("-o,--out", report->out, "The page to write (.html)")->required();
  add_ranking_metric_option(report_cmd, report->metric);
  report_cmd->add_option("--top", report->top, "Picture only the best N models of each material (0: all)")
      ->check(kCountRange);
  report_cmd->add_option("--size", report->size, "Sphere size in pixels")->check(CLI::Range(16, 1024));
  report->lighting.add_to(report_cmd);
  report_cmd->callback([report] { run_report(*report); });
}

}  // namespace brdffit::cli
