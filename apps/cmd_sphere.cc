// `brdffit sphere`: fit models to photographs of a sphere; `brdffit capture`: grab frames (and
// merge exposures into an HDR image) through OpenCV.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "brdffit/error.h"
#include "brdffit/imaging/capture.h"
#include "brdffit/imaging/image_io.h"
#include "brdffit/imaging/sphere_fit.h"
#include "brdffit/io.h"
#include "brdffit/registry.h"
#include "brdffit/result_json.h"
#include "cli_common.h"
#include "commands.h"
#include "fit_options.h"

namespace brdffit::cli {

namespace {

namespace fs = std::filesystem;

// Diffuse, a classic lobe and the microfacet models; those not in this build are skipped.
std::string default_models() { return model_list({"lambert", "blinn-phong", "ggx", "cook-torrance", "ward"}); }

struct SphereArgs {
  std::vector<std::string> inputs;
  std::string lights, intensities, exposures, mask, chrome_mask, normals;
  std::vector<std::string> chrome;
  double focal = 0.0;
  std::string gamma;
  bool linear = false;
  std::string models = default_models();
  std::string metric = "cosine";
  std::string loss = "huber";
  size_t max_samples = 200000;
  uint64_t seed = 1;
  int threads = 0;
  PixelRules rules;
  ConvergeArg converge;
  FixArg fix;
  std::string out, images_out, images_format = "png";
  bool json = false;
  uint64_t max_pixels = kDefaultMaxImagePixels;
};

SphereInput sphere_input(const SphereArgs& args) {
  SphereInput input;
  input.lights = args.lights;
  input.chrome = args.chrome;
  input.chrome_mask = args.chrome_mask;
  input.intensities = args.intensities;
  input.exposures = args.exposures;
  input.mask = args.mask;
  input.normals = args.normals;
  input.focal_px = args.focal;
  input.rules = args.rules;
  if (args.linear) input.decoding = Decoding{Transfer::Linear};
  if (!args.gamma.empty()) input.decoding = parse_gamma(args.gamma);
  std::error_code error;
  if (args.inputs.size() == 1 && fs::is_directory(args.inputs[0], error)) {
    if (!is_diligent_folder(args.inputs[0]))
      fail("{}: a folder given as input must be a DiLiGenT object folder (with filenames.txt)", args.inputs[0]);
    add_diligent_folder(args.inputs[0], input);
  } else {
    input.images = args.inputs;
  }
  return input;
}

// What the result document names as its input: the one path given, or the images' folder.
std::string input_path(const SphereArgs& args) {
  if (args.inputs.size() == 1) return args.inputs[0];
  const fs::path folder = fs::path(args.inputs[0]).parent_path();
  const bool one_folder = std::all_of(args.inputs.begin(), args.inputs.end(),
                                      [&](const std::string& p) { return fs::path(p).parent_path() == folder; });
  return one_folder && !folder.empty() ? folder.string() : args.inputs[0];
}

void print_observation(const SphereObservation& o) {
  const Circle& c = o.sphere.outline();
  const Camera& camera = o.sphere.camera();
  say("sphere: centre ({:.2f}, {:.2f}), radius {:.2f} px, {} camera; located by {}\n", c.x, c.y, c.radius,
      camera.perspective() ? fmt::format("perspective (focal {:g} px)", camera.focal_px) : "orthographic",
      o.located_by);
  if (const auto& n = o.normals)
    say("normals: against {}: median {:.2f}°, 90th percentile {:.2f}° over {} pixels\n", n->file, n->median_deg,
        n->p90_deg, n->pixels);
  if (o.chrome_ball) {
    const Circle& b = o.chrome_ball->outline();
    say("lights: {} estimated on the chrome ball at ({:.2f}, {:.2f}), radius {:.2f} px\n", o.images.size(), b.x, b.y,
        b.radius);
  } else {
    say("lights: {} from {}\n", o.images.size(), o.lights_from);
  }
  say("intensities: {}; exposures: {}\n",
      o.intensities_known ? "given" : fmt::format("unknown, values divided by {:.4g}", o.intensity_scale),
      o.exposures_from);
  const PixelCounts& p = o.pixels;
  say("pixels: {} on the sphere x {} images = {}: {} used, {} in shadow, {} grazing, {} saturated, {} too dark\n",
      o.sphere_pixels, o.images.size(), p.total(), p.used, p.shadow, p.grazing, p.saturated, p.dark);
}

// Models ranked by how well they reproduce the photographs.
void print_results(const std::vector<FitResult>& fits, const std::vector<PhotoError>& errors, Metric metric) {
  std::map<std::string, double> image_error;
  for (const PhotoError& e : errors) image_error[e.model] = e.relative_rms;
  std::vector<const FitResult*> order;
  for (const FitResult& f : fits) order.push_back(&f);
  const auto error_of = [&](const FitResult* f) { return f->ok ? image_error[f->model] : HUGE_VAL; };
  std::stable_sort(order.begin(), order.end(),
                   [&](const FitResult* a, const FitResult* b) { return error_of(a) < error_of(b); });
  say("{:<16} {:<7} {:>14} {:>10} {:>8}  parameters\n", "model", "verdict", "image rel. RMS", metric_name(metric),
      "seconds");
  for (const FitResult* f : order) {
    if (!f->ok) {
      say("{:<16} failed: {}\n", f->model, f->error);
      continue;
    }
    say("{:<16} {:<7} {:>14.4f} {:>10.4g} {:>8.1f}  {}\n", f->model, verdict_name(f->verdict), error_of(f),
        f->metrics.get(metric), f->seconds, format_parameters(*f));
    print_warnings(*f, "    ");
  }
}

void run_sphere(const SphereArgs& args) {
  set_max_image_pixels(args.max_pixels);
  FitOptions options = fit_options(args.metric, args.loss, false, args.threads, args.seed, args.converge, args.fix);
  if (args.images_format != "png" && args.images_format != "exr")
    fail_usage("--images-format: png or exr, not '{}'", args.images_format);
  const std::vector<const Model*> models = parse_model_list(args.models);
  const SphereInput input = sphere_input(args);
  const PanelOutput panels{args.images_out, args.images_format};
  // Before the work, not after it; the panels' folders are made as they are written.
  check_outputs(sphere_input_files(input), {args.out});
  check_outputs(sphere_input_files(input), panel_paths(panels, input, models), OutputFolders::Made);

  stage("reading {} and locating the sphere", count_of(input.images.size(), "photograph"));
  const SphereObservation observation = observe_sphere(input);
  if (!args.json && verbosity() != Verbosity::Quiet) print_observation(observation);
  SampleSet fitted = observation.samples;
  apply_sampling_options(fitted, SamplingOptions{90.0, args.max_samples, args.seed});
  if (!args.json)
    inform(stdout, "fitting {} of {} samples ({} loss)\n", fitted.size(), observation.samples.size(),
           args.loss == "none" ? "no robust" : args.loss);

  ModelProgress progress;
  progress.attach(options);
  const std::vector<FitResult> fits = fit_models(models, fitted, options);
  progress.clear();
  stage("comparing the fits with the photographs{}", panels.dir.empty() ? "" : ", writing images into " + panels.dir);
  const std::vector<PhotoError> errors = compare_with_photographs(observation, input, fits, panels);
  const std::string document =
      args.json || !args.out.empty()
          ? json_text(sphere_document_json(input_path(args), input, observation, fitted, options, fits, errors), 2) +
                "\n"
          : std::string();
  if (args.json) {
    say("{}", document);
  } else {
    print_results(fits, errors, options.metric);
    if (!args.images_out.empty()) say("images: measured | fit | error in {}/<model>/\n", args.images_out);
  }
  if (!args.out.empty()) write_file_atomic(args.out, document);
  if (std::none_of(fits.begin(), fits.end(), [](const FitResult& f) { return f.ok; }))
    fail("{}: every model failed to fit", input_path(args));
}

struct CaptureArgs {
  CaptureOptions options;
  std::string out, response;
};

void run_capture(const CaptureArgs& args) {
  check_outputs(capture_input_files(args.options.source), {args.out, args.response});
  check_exposure_times(args.options.exposures);
  const CaptureResult result = capture(args.options);
  write_image(args.out, result.image);
  if (!args.response.empty()) {
    std::string csv = "code,r,g,b\n";
    for (int code = 0; code < result.response.rows; ++code) {
      const cv::Vec3f& v = result.response.at<cv::Vec3f>(code, 0);
      csv += fmt::format("{},{:.9g},{:.9g},{:.9g}\n", code, v[0], v[1], v[2]);
    }
    write_file_atomic(args.response, csv);
  }
  say("{}: {} frames{}; wrote {} ({}x{})\n", args.options.source, result.frames,
      result.response.empty() ? ", one exposure (decoded as sRGB)"
                              : fmt::format(", {} exposures merged (Debevec)", args.options.exposures.size()),
      args.out, result.image.cols, result.image.rows);
}

}  // namespace

void add_sphere_commands(CLI::App& app) {
  auto args = std::make_shared<SphereArgs>();
  CLI::App* sphere = app.add_subcommand("sphere", imaging_summary("sphere"));
  sphere->add_option("input", args->inputs, "Photographs (EXR, HDR, TIFF, PNG, JPEG), or one DiLiGenT object folder")
      ->required();
  CLI::Option* lights = sphere->add_option(
      "--lights", args->lights, "Light directions, one 'x y z' per image (x right, y up, z toward the camera)");
  sphere->add_option("--intensities", args->intensities,
                     "Light intensities, one 'r g b' per image (pixels are divided by them)");
  sphere->add_option("--exposures", args->exposures, "Exposure times, one per image (default: the files' metadata)");
  sphere->add_option("--mask", args->mask, "Mask of the sphere (default: the sphere is detected)");
  sphere->add_option(
      "--normals", args->normals,
      "Ground-truth normal map, (n+1)/2 per pixel: report how far the located sphere's normals lie from it "
      "(a DiLiGenT folder's Normal_gt.png is used by default)");
  sphere
      ->add_option("--chrome", args->chrome, "Photographs of a chrome ball under the same lights: estimate the lights")
      ->excludes(lights);
  sphere->add_option("--chrome-mask", args->chrome_mask, "Mask of the chrome ball (default: detected)");
  sphere
      ->add_option("--focal", args->focal,
                   "Perspective camera with this focal length in pixels (default: orthographic)")
      ->check(CLI::PositiveNumber);
  CLI::Option* gamma = sphere->add_option(
      "--gamma", args->gamma, "Decode every image as value^GAMMA, or 'srgb' (default: 8-bit sRGB, deeper linear)");
  sphere->add_flag("--linear", args->linear, "Every image is linear, 8-bit ones too")->excludes(gamma);
  add_models_option(sphere, args->models,
                    "Comma-separated models, or 'all' (default: five that span diffuse to glossy; batch takes all, "
                    "fit six; a photograph set rarely pins down the many-parameter ones)");
  add_minimised_metric_option(sphere, args->metric);
  sphere->add_option("--loss", args->loss,
                     "Robust loss per sample: none, huber, cauchy (default huber, unlike fit and batch: photographs "
                     "hold outliers a table does not, e.g. interreflections, dust, a misjudged edge)");
  sphere
      ->add_option("--max-samples", args->max_samples,
                   "Fit a deterministic random subset of this many pixels (0: all; default 200000, unlike fit and "
                   "batch: photographs hold millions of pixels, mostly repeating the same angles)")
      ->check(kCountRange);
  sphere->add_option("--seed", args->seed, "Seed of the subset")->check(kSeedRange);
  sphere->add_option("--threads", args->threads, "Threads (0: every core)")->check(kThreadsRange);
  args->converge.add_to(sphere);
  args->fix.add_to(sphere);
  sphere
      ->add_option("--max-angle", args->rules.max_angle_deg,
                   "Leave out pixels with θi or θo above this (degrees; default 80, unlike fit and batch: a sphere's "
                   "rim has unreliable normals and blurred pixels)")
      ->check(CLI::Range(1.0, 90.0));
  sphere
      ->add_option("--saturation", args->rules.saturation,
                   "Leave out pixels with a channel at this fraction of full scale")
      ->check(CLI::Range(0.0, 1.0));
  sphere
      ->add_option("--dark", args->rules.dark,
                   "Leave out pixels whose brightest channel is below this fraction of full scale")
      ->check(CLI::Range(0.0, 1.0));
  sphere->add_option("--max-pixels", args->max_pixels, "Refuse photographs with more pixels than this (bounds memory)")
      ->check(kCountRange);
  sphere->add_option("-o,--out", args->out, "Write the result document (JSON)");
  sphere->add_flag("--json", args->json, "Print the result document on stdout instead of the tables");
  sphere->add_option("--images-out", args->images_out,
                     "Write measured | fit | error images per model and photograph here");
  sphere->add_option("--images-format", args->images_format, "png (sRGB, for viewing) or exr (linear values)");
  sphere->callback([args] { run_sphere(*args); });

  auto capture_args = std::make_shared<CaptureArgs>();
  CLI::App* capture_cmd = app.add_subcommand("capture", imaging_summary("capture"));
  capture_cmd
      ->add_option("source", capture_args->options.source,
                   "Camera index, video file, or image sequence pattern (shot_%02d.png)")
      ->required();
  capture_cmd
      ->add_option("--exposures", capture_args->options.exposures,
                   "Exposure time of each group of frames, in order (T1,T2,...)")
      ->delimiter(',');
  capture_cmd->add_option("--frames", capture_args->options.frames_per_exposure, "Frames averaged per exposure")
      ->check(kFramesRange);
  capture_cmd->add_option("-o,--out", capture_args->out, "Image to write (EXR keeps the linear values)")->required();
  capture_cmd->add_option("--response", capture_args->response,
                          "Write the recovered camera response (CSV: code,r,g,b)");
  capture_cmd->callback([capture_args] { run_capture(*capture_args); });
}

}  // namespace brdffit::cli
