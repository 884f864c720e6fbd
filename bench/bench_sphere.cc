// Photographed-sphere figures on synthetic photographs rendered by brdffit with known values:
// parameter recovery (16-bit linear with a mask, 8-bit sRGB with a detected sphere; 1% noise)
// and light directions estimated from a rendered chrome ball. The fitter's own flags (a parameter
// at its bound or not identifiable) are printed beside the errors: with lights within 50° of the
// view, l·h stays near 1 and Cook-Torrance's specular and f0 act only through their product.
//
//   bench_sphere [--dir SCRATCH] [--models ggx,ward,...]
//
// For the DiLiGenT ball itself, run the command users run:
//   brdffit sphere ../shared/data/diligent-ball --models lambert,blinn-phong,ggx,cook-torrance,ward
// which prints the normals' error against Normal_gt.png and each model's image error.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <filesystem>

#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/imaging/sphere_fit.h"
#include "brdffit/registry.h"
#include "sphere_scenes.h"

using namespace brdffit;

namespace {

// Known values for each model the bench renders: mid-range, away from the bounds.
const std::map<std::string, std::vector<std::string>> kTruth = {
    {"lambert", {"albedo=0.6,0.4,0.25"}},
    {"blinn-phong", {"albedo=0.15,0.1,0.06", "specular=0.3,0.3,0.3", "gloss=60"}},
    {"ggx", {"albedo=0.5,0.35,0.2", "roughness=0.3", "f0=0.04,0.05,0.06"}},
    {"ward", {"albedo=0.5,0.35,0.2", "specular=0.08,0.08,0.09", "alpha=0.15"}},
    {"cook-torrance", {"albedo=0.4,0.3,0.2", "specular=0.6,0.6,0.6", "f0=0.3", "m=0.2"}},
};

struct Encoded {
  const char* name;
  Encoding encoding;
  bool use_mask;
};
const Encoded kEncodings[] = {{"16-bit linear, mask", Encoding::Linear16, true},
                              {"8-bit sRGB, detected", Encoding::Srgb8, false}};

void recovery(const std::string& dir, const std::string& model_name) {
  const Model* model = find_model(model_name);
  if (!model || !kTruth.count(model_name)) fail("bench_sphere: no known values for model '{}'", model_name);
  const std::vector<double> truth = parameter_values(*model, kTruth.at(model_name));
  for (const Encoded& e : kEncodings) {
    test::SceneOptions scene_options;
    scene_options.encoding = e.encoding;
    const test::SphereScene scene =
        test::write_sphere_scene(dir + "/" + model_name, "s", *model, truth, test::dome_lights(8), scene_options);
    SphereInput input;
    input.images = scene.images;
    input.lights = scene.lights;
    input.intensities = scene.intensities;
    if (e.use_mask) input.mask = scene.mask;
    const auto start = std::chrono::steady_clock::now();
    const SphereObservation observation = observe_sphere(input);
    FitOptions options;
    options.loss = LossKind::Huber;
    const FitResult fit = fit_model(*model, observation.samples, options);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!fit.ok) fail("{}: the fit failed: {}", model_name, fit.error);
    double worst = 0.0;
    std::string detail;
    for (size_t i = 0; i < truth.size(); ++i) {
      const double error = std::abs(fit.values[i] / truth[i] - 1.0);
      worst = std::max(worst, error);
      detail += fmt::format(" {:.4g}/{:.4g}", fit.values[i], truth[i]);
    }
    std::string flags;
    for (const ParameterEstimate& p : fit.parameters) {
      if (!p.identifiable) flags += " " + p.name + " not identifiable;";
      if (p.at_bound) flags += " " + p.name + " at its bound;";
    }
    fmt::print("{:<14} {:<22} {:>8} samples {:>6.2f} s  worst parameter error {:>6.2f}%  (fitted/true:{}){}\n",
               model_name, e.name, observation.samples.size(), seconds, 100.0 * worst, detail, flags);
  }
}

void chrome(const std::string& dir) {
  const std::vector<Vec3> lights = test::dome_lights(12, 60.0);
  for (const Encoded& e : kEncodings) {
    const test::SphereScene scene = test::write_chrome_scene(dir + "/chrome", lights, e.encoding);
    const SphereView ball(e.use_mask ? circle_from_mask(read_mask(scene.mask), scene.mask)
                                     : detect_sphere(brightest_of(scene.images, {}), "chrome ball"),
                          Camera{});
    std::vector<double> errors;
    for (size_t i = 0; i < lights.size(); ++i)
      errors.push_back(
          test::angle_deg(light_from_chrome(read_image(scene.images[i]), ball, scene.images[i]), lights[i]));
    std::sort(errors.begin(), errors.end());
    fmt::print("chrome ball    {:<22} {} lights up to 60°: median {:.3f}°, worst {:.3f}°\n", e.name, lights.size(),
               errors[errors.size() / 2], errors.back());
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"brdffit photographed-sphere benchmark"};
  std::string dir = (std::filesystem::temp_directory_path() / "brdffit-bench-sphere").string();
  std::string models = "lambert,blinn-phong,ggx,ward,cook-torrance";
  app.add_option("--dir", dir, "Scratch folder for the rendered photographs");
  app.add_option("--models", models, "Models to render and fit back");
  CLI11_PARSE(app, argc, argv);
  try {
    std::stringstream names(models);
    for (std::string name; std::getline(names, name, ',');) recovery(dir, name);
    chrome(dir);
  } catch (const Error& e) {
    fmt::print(stderr, "bench_sphere: {}\n", e.what());
    return 1;
  }
  return 0;
}
