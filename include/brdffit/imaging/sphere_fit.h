// Photographs of a sphere to samples for the fitter, and fitted models back to images: the
// library side of `brdffit sphere` (the geometry it uses is in sphere.h).
//
// Photometric convention. A directional light of irradiance E (RGB, measured at normal
// incidence) makes the surface send radiance L = f(l,v)·cosθi·E toward the camera, and a linear
// pixel records L times the exposure. A pixel therefore gives the sample value
//     value = pixel / (E · t/t₀ · s)  =  f·cosθi        (the convention of Sample)
// where t/t₀ is the image's exposure time relative to the first image's (1 when unknown) and s
// one global scale. With the intensities given, s = 1 and colour parameters are in units of E.
// Without them, E = 1 and s is chosen so that the 99th percentile of the values is 0.25, which
// keeps colour parameters inside their bounds (a white diffuse sphere fits albedo ≈ 0.8): fitted
// colours (albedo, specular) are then relative, shape parameters (roughness, gloss) unaffected.
//
// Weights. Every used pixel is one sample of weight 1 ("pixel" weighting): the fit weighs the
// sphere's normals as the camera sees them, densest where the sphere faces the camera.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "brdffit/fit.h"
#include "brdffit/imaging/sphere.h"
#include "brdffit/samples.h"

namespace brdffit {

// What the pipeline reads; file names empty when not given.
struct SphereInput {
  std::vector<std::string> images;
  std::string lights;               // light directions, one per image
  std::vector<std::string> chrome;  // or photographs of a chrome ball under the same lights, in the same order
  std::string chrome_mask;          // where the chrome ball is (detected when empty)
  std::string intensities;          // light intensities (RGB), one per image; unknown when empty
  std::string exposures;            // exposure times, one per image; else the files' metadata when every
                                    // image has it; else all equal
  std::string mask;                 // where the sphere is, and which pixels may be used (detected when empty)
  std::string normals;              // a ground-truth normal map to check the located sphere against (optional)
  Decoding decoding;
  double focal_px = 0.0;  // perspective camera with this focal length in pixels; 0: orthographic
  PixelRules rules;
  size_t max_gathered = 2000000;  // at most about this many samples are gathered: larger spheres are
                                  // sampled on a coarser regular pixel grid (all pixels are still counted)
};

// Every file `input` names (images, chrome photographs, lights, masks, ...), for checking that
// no output is one of them.
std::vector<std::string> sphere_input_files(const SphereInput& input);

// True for a DiLiGenT object folder (one with a filenames.txt).
bool is_diligent_folder(const std::string& path);
// Reads a DiLiGenT object folder: its filenames.txt lists the images, and light_directions.txt,
// light_intensities.txt, mask.png and Normal_gt.png fill whatever `input` leaves empty.
void add_diligent_folder(const std::string& folder, SphereInput& input);

struct PixelCounts {
  size_t used = 0, shadow = 0, grazing = 0, saturated = 0, dark = 0;

  void add(PixelFate fate);
  PixelCounts& operator+=(const PixelCounts& other);
  size_t total() const { return used + shadow + grazing + saturated + dark; }
};

struct SphereImage {
  std::string path;
  Vec3 light = Vec3::UnitZ();                   // unit, camera frame
  Rgb<double> intensity = Rgb<double>::Ones();  // E (ones when unknown)
  double exposure = 1.0;                        // t/t₀
  Rgb<double> gain = Rgb<double>::Ones();       // value = pixel · gain = pixel / (E · t/t₀ · s)
  bool clips = false;                           // integer file: full scale means clipped
  double full_scale = 1.0;                      // see classify_pixel
  PixelCounts pixels;
  size_t first_sample = 0, samples = 0;  // this image's range in SphereObservation::samples
};

struct SphereObservation {
  SphereView sphere;
  std::string located_by;  // "mask FILE" or "detection"
  cv::Size image_size;
  cv::Mat mask;              // CV_8U, empty when none was given
  size_t sphere_pixels = 0;  // pixels that show the sphere (and lie in the mask)
  int grid_step = 1;         // samples were gathered from every grid_step-th pixel in x and y
  std::vector<SphereImage> images;
  std::string lights_from;  // the lights file, or "chrome"
  std::optional<SphereView> chrome_ball;
  std::optional<NormalCheck> normals;  // when SphereInput::normals was given
  bool intensities_known = false;
  std::string exposures_from;    // the exposures file, "metadata" or "none"
  double intensity_scale = 1.0;  // s
  PixelCounts pixels;            // over every image
  SampleSet samples;             // the used pixels, image after image
};

// Reads everything, locates the sphere, gets the lights and turns every used pixel into a
// sample. Throws Error naming the file and the problem for missing or unreadable images, images
// of different sizes, NaN pixels, no sphere found, light files that do not match the images, or
// no usable pixel at all.
SphereObservation observe_sphere(const SphereInput& input);

// How well a fitted model reproduces the photographs, on every used pixel (not only those fitted):
// relative RMS = sqrt(Σ (fit - measured)² / Σ measured²) over pixels and channels.
struct PhotoError {
  std::string model;
  double relative_rms = NAN;
  std::vector<double> per_image;
};

// Where compare_with_photographs writes, for every image and model, the measured values, the
// fitted model's rendering and a heatmap of their difference side by side, cropped to the sphere.
struct PanelOutput {
  std::string dir;             // empty: no images; else dir/<model>/<index>_<image name>.<format>
  std::string format = "png";  // png: sRGB, white at 1.25× the 99th percentile of the values;
                               // exr: the values themselves. The heatmap is full at 20% of that white;
                               // grey marks pixels left out, black lies off the sphere.
};

// Where compare_with_photographs writes the panel of `model` for image `index` (0-based) at
// `image`, and every panel it may write for `models`: the one list the command checks against
// its inputs (check_outputs) before any work and the writer uses.
std::string panel_path(const PanelOutput& panels, const std::string& model, size_t index, const std::string& image);
std::vector<std::string> panel_paths(const PanelOutput& panels, const SphereInput& input,
                                     const std::vector<const Model*>& models);

// One entry per successful fit, in the order of `fits`. Rereads the photographs (one at a time).
std::vector<PhotoError> compare_with_photographs(const SphereObservation& observation, const SphereInput& input,
                                                 const std::vector<FitResult>& fits, const PanelOutput& panels = {});

// The result document: fit_document_json's, plus the sphere, pixel counts, lights, photometric
// normalisation and per-image errors.
nlohmann::json sphere_document_json(const std::string& input_path, const SphereInput& input,
                                    const SphereObservation& observation, const SampleSet& fitted,
                                    const FitOptions& options, const std::vector<FitResult>& fits,
                                    const std::vector<PhotoError>& errors);

}  // namespace brdffit
