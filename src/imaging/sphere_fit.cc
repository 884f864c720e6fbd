// From photographs of a sphere to samples, and from fits back to images (see sphere_fit.h).
#include "brdffit/imaging/sphere_fit.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/registry.h"
#include "brdffit/result_json.h"

namespace brdffit {

namespace {

namespace fs = std::filesystem;

// Without known intensities the values are scaled so that their 99th percentile is this.
constexpr double kUnknownIntensityLevel = 0.25;
// Panels: white at this multiple of the values' 99th percentile; the heatmap full at this fraction of white.
constexpr double kPanelWhite = 1.25;
constexpr double kHeatFullScale = 0.2;
constexpr uint8_t kOffSphere = 255;  // in a map of PixelFate values

// Names a set of pictures in messages: the file itself, or the first and last and how many.
std::string describe(const std::vector<std::string>& paths) {
  if (paths.size() == 1) return paths.front();
  return fmt::format("{} ... {} ({} images)", paths.front(), paths.back(), paths.size());
}

// Reads every header before any pixel: each file must exist, be an image and have the first's size.
std::vector<ImageInfo> survey(const std::vector<std::string>& paths) {
  std::vector<ImageInfo> infos;
  for (const std::string& path : paths) {
    infos.push_back(read_image_info(path));
    const ImageInfo& first = infos.front();
    if (infos.back().width != first.width || infos.back().height != first.height)
      fail("{}: is {}x{} pixels, but {} is {}x{}", path, infos.back().width, infos.back().height, paths.front(),
           first.width, first.height);
  }
  return infos;
}

// Each image's exposure time relative to the first image's.
std::vector<double> relative_exposures(const SphereInput& input, const std::vector<ImageInfo>& infos,
                                       std::string& from) {
  std::vector<double> times;
  if (!input.exposures.empty()) {
    times = read_exposures(input.exposures, infos.size());
    from = input.exposures;
  } else if (std::all_of(infos.begin(), infos.end(), [](const ImageInfo& i) { return i.exposure_time > 0.0; })) {
    for (const ImageInfo& info : infos) times.push_back(info.exposure_time);
    from = "metadata";
  } else {
    times.assign(infos.size(), 1.0);
    from = "none";
  }
  const double first = times.front();
  for (double& t : times) t /= first;
  return times;
}

// The light direction of every image: from the lights file, or estimated on the chrome ball.
std::vector<Vec3> light_directions(const SphereInput& input, SphereObservation& observation) {
  const size_t count = input.images.size();
  if (!input.lights.empty() && !input.chrome.empty())
    fail("give the light directions either as a file or as chrome-ball photographs, not both");
  if (!input.lights.empty()) {
    observation.lights_from = input.lights;
    return read_light_directions(input.lights, count);
  }
  if (input.chrome.empty())
    fail("no light directions: give a lights file or photographs of a chrome ball under the same lights");
  if (input.chrome.size() != count)
    fail("{} chrome-ball photographs for {} images: there must be one per image, in the same order",
         input.chrome.size(), count);
  const std::vector<ImageInfo> chrome_infos = survey(input.chrome);
  const cv::Size chrome_size(chrome_infos[0].width, chrome_infos[0].height);
  Circle outline;
  if (!input.chrome_mask.empty()) {
    const cv::Mat mask = read_mask(input.chrome_mask);
    if (mask.size() != chrome_size)
      fail("{}: is {}x{} pixels, but the chrome photographs are {}x{}", input.chrome_mask, mask.cols, mask.rows,
           chrome_size.width, chrome_size.height);
    outline = circle_from_mask(mask, input.chrome_mask);
  } else {
    outline = detect_sphere(brightest_of(input.chrome, input.decoding), describe(input.chrome) + " (chrome ball)");
  }
  const SphereView ball(outline, Camera::centred(input.focal_px, chrome_size));
  std::vector<Vec3> lights;
  for (const std::string& path : input.chrome)
    lights.push_back(light_from_chrome(read_image(path, input.decoding), ball, path));
  observation.chrome_ball = ball;
  observation.lights_from = "chrome";
  return lights;
}

void locate_sphere(const SphereInput& input, SphereObservation& observation) {
  const cv::Size size = observation.image_size;
  Circle outline;
  if (!input.mask.empty()) {
    observation.mask = read_mask(input.mask);
    if (observation.mask.size() != size)
      fail("{}: is {}x{} pixels, but the images are {}x{}", input.mask, observation.mask.cols, observation.mask.rows,
           size.width, size.height);
    outline = circle_from_mask(observation.mask, input.mask);
    observation.located_by = "mask " + input.mask;
  } else {
    outline = detect_sphere(brightest_of(input.images, input.decoding), describe(input.images));
    observation.located_by = "detection";
  }
  observation.sphere = SphereView(outline, Camera::centred(input.focal_px, size));
}

// Calls visit(x, y, normal, view) for every pixel that shows the sphere and lies in the mask.
template <class Visit>
void for_each_sphere_pixel(const SphereObservation& observation, Visit&& visit) {
  brdffit::for_each_sphere_pixel(observation.sphere, observation.image_size, observation.mask, visit);
}

// Where a float image has no clipping level, its brightest sphere pixel sets the scale "dark" is measured on.
double full_scale_of(const SphereObservation& observation, const SphereImage& image, const cv::Mat& photo) {
  if (image.clips) return 1.0;
  double brightest = 0.0;
  for_each_sphere_pixel(observation, [&](int x, int y, const Vec3&, const Vec3&) {
    const cv::Vec3f& p = photo.at<cv::Vec3f>(y, x);
    brightest = std::max<double>({brightest, p[0], p[1], p[2]});
  });
  return brightest > 0.0 ? brightest : 1.0;
}

// The fate of every pixel of the sphere's bounding box in one photograph (kOffSphere where the
// pixel does not show the sphere or lies outside the mask).
cv::Mat pixel_fates(const SphereObservation& observation, const SphereImage& image, const cv::Mat& photo,
                    const PixelRules& rules) {
  const cv::Rect box = observation.sphere.bounds(observation.image_size);
  cv::Mat fates(box.size(), CV_8U, cv::Scalar(kOffSphere));
  for_each_sphere_pixel(observation, [&](int x, int y, const Vec3& normal, const Vec3& view) {
    fates.at<uint8_t>(y - box.y, x - box.x) = static_cast<uint8_t>(
        classify_pixel(normal, view, image.light, photo.at<cv::Vec3f>(y, x), image.full_scale, image.clips, rules));
  });
  return fates;
}

Rgb<double> rgb_of(const cv::Vec3f& p) { return Rgb<double>(p[0], p[1], p[2]); }

// The largest channel of each sample's value, at the given quantile.
double value_quantile(const SampleSet& set, double quantile) {
  std::vector<double> brightest;
  brightest.reserve(set.size());
  for (const Sample& s : set.samples) brightest.push_back(s.value.maxCoeff());
  if (brightest.empty()) return 0.0;
  auto at = brightest.begin() + static_cast<std::ptrdiff_t>(quantile * static_cast<double>(brightest.size() - 1));
  std::nth_element(brightest.begin(), at, brightest.end());
  return *at;
}

void gather_samples(const SphereInput& input, const std::vector<ImageInfo>& infos, SphereObservation& observation) {
  const double candidates =
      static_cast<double>(observation.sphere_pixels) * static_cast<double>(observation.images.size());
  observation.grid_step =
      std::max(1, static_cast<int>(std::ceil(std::sqrt(candidates / static_cast<double>(input.max_gathered)))));
  const int step = observation.grid_step;
  const cv::Rect box = observation.sphere.bounds(observation.image_size);
  observation.samples.source = describe(input.images);
  observation.samples.weighting = "pixel";
  for (size_t i = 0; i < observation.images.size(); ++i) {
    SphereImage& image = observation.images[i];
    const cv::Mat photo = read_image(image.path, input.decoding);
    image.clips = infos[i].integer_codes;
    image.full_scale = full_scale_of(observation, image, photo);
    const cv::Mat fates = pixel_fates(observation, image, photo, input.rules);
    image.first_sample = observation.samples.size();
    for (int y = box.y; y < box.y + box.height; ++y)
      for (int x = box.x; x < box.x + box.width; ++x) {
        const uint8_t fate = fates.at<uint8_t>(y - box.y, x - box.x);
        if (fate == kOffSphere) continue;
        image.pixels.add(static_cast<PixelFate>(fate));
        if (fate != static_cast<uint8_t>(PixelFate::Used) || x % step != 0 || y % step != 0) continue;
        Vec3 normal, view;
        observation.sphere.surface_at(x, y, normal, view);
        const LocalFrame frame(normal);
        observation.samples.samples.push_back({frame.to_local(image.light), frame.to_local(view),
                                               rgb_of(photo.at<cv::Vec3f>(y, x)).cwiseProduct(image.gain), 1.0});
      }
    image.samples = observation.samples.size() - image.first_sample;
    observation.pixels += image.pixels;
  }
}

}  // namespace

bool is_diligent_folder(const std::string& path) {
  std::error_code error;
  return fs::is_directory(path, error) && fs::exists(fs::path(path) / "filenames.txt", error);
}

void add_diligent_folder(const std::string& folder, SphereInput& input) {
  const fs::path dir(folder);
  std::istringstream names(read_file((dir / "filenames.txt").string()));
  std::string name;
  while (names >> name) input.images.push_back((dir / name).string());
  if (input.images.empty()) fail("{}: lists no images", (dir / "filenames.txt").string());
  const auto fill = [&](std::string& field, const char* file) {
    std::error_code error;
    if (field.empty() && fs::exists(dir / file, error)) field = (dir / file).string();
  };
  if (input.chrome.empty()) fill(input.lights, "light_directions.txt");
  fill(input.intensities, "light_intensities.txt");
  fill(input.mask, "mask.png");
  fill(input.normals, "Normal_gt.png");
}

void PixelCounts::add(PixelFate fate) {
  switch (fate) {
    case PixelFate::Used: ++used; break;
    case PixelFate::Shadow: ++shadow; break;
    case PixelFate::Grazing: ++grazing; break;
    case PixelFate::Saturated: ++saturated; break;
    case PixelFate::Dark: ++dark; break;
  }
}

PixelCounts& PixelCounts::operator+=(const PixelCounts& other) {
  used += other.used;
  shadow += other.shadow;
  grazing += other.grazing;
  saturated += other.saturated;
  dark += other.dark;
  return *this;
}

SphereObservation observe_sphere(const SphereInput& input) {
  if (input.images.empty()) fail("no images given");
  // Headers and text files first: their mistakes show before the long part.
  const std::vector<ImageInfo> infos = survey(input.images);
  SphereObservation observation;
  observation.image_size = cv::Size(infos[0].width, infos[0].height);
  const size_t count = input.images.size();
  observation.intensities_known = !input.intensities.empty();
  const std::vector<Rgb<double>> intensities = observation.intensities_known
                                                   ? read_light_intensities(input.intensities, count)
                                                   : std::vector<Rgb<double>>(count, Rgb<double>::Ones());
  const std::vector<double> exposures = relative_exposures(input, infos, observation.exposures_from);
  const std::vector<Vec3> lights = light_directions(input, observation);

  locate_sphere(input, observation);
  for_each_sphere_pixel(observation, [&](int, int, const Vec3&, const Vec3&) { ++observation.sphere_pixels; });
  if (observation.sphere_pixels == 0) fail("{}: the sphere covers no pixel", describe(input.images));
  if (!input.normals.empty())
    observation.normals = check_normals(observation.sphere, input.normals, observation.image_size, observation.mask);

  for (size_t i = 0; i < count; ++i) {
    SphereImage image;
    image.path = input.images[i];
    image.light = lights[i];
    image.intensity = intensities[i];
    image.exposure = exposures[i];
    image.gain = (intensities[i] * exposures[i]).cwiseInverse();
    observation.images.push_back(image);
  }
  gather_samples(input, infos, observation);

  const PixelCounts& p = observation.pixels;
  if (observation.samples.empty())
    fail(
        "{}: no usable pixel: of {} sphere pixels over {} images, {} are in shadow, {} grazing, {} saturated and {} "
        "too dark",
        describe(input.images), p.total(), count, p.shadow, p.grazing, p.saturated, p.dark);
  if (!observation.intensities_known) {
    const double level = value_quantile(observation.samples, 0.99);
    if (level > 0.0) observation.intensity_scale = level / kUnknownIntensityLevel;
    for (Sample& s : observation.samples.samples) s.value /= observation.intensity_scale;
    for (SphereImage& image : observation.images) image.gain /= observation.intensity_scale;
  }
  return observation;
}

std::string panel_path(const PanelOutput& panels, const std::string& model, size_t index, const std::string& image) {
  const std::string name = fmt::format("{:03}_{}.{}", index + 1, fs::path(image).stem().string(), panels.format);
  return (fs::path(panels.dir) / model / name).string();
}

std::vector<std::string> panel_paths(const PanelOutput& panels, const SphereInput& input,
                                     const std::vector<const Model*>& models) {
  std::vector<std::string> paths;
  if (panels.dir.empty()) return paths;
  for (const Model* model : models)
    for (size_t i = 0; i < input.images.size(); ++i)
      paths.push_back(panel_path(panels, model->name(), i, input.images[i]));
  return paths;
}

std::vector<PhotoError> compare_with_photographs(const SphereObservation& observation, const SphereInput& input,
                                                 const std::vector<FitResult>& fits, const PanelOutput& panels) {
  struct Compared {
    const FitResult* fit;
    const Model* model;
    PhotoError error;
    double squared_difference = 0.0, squared_measured = 0.0;
  };
  std::vector<Compared> compared;
  for (const FitResult& fit : fits)
    if (const Model* model = find_model(fit.model); model && fit.ok)
      compared.push_back({&fit, model, {fit.model, NAN, {}}});

  const bool write_panels = !panels.dir.empty();
  const bool display = panels.format != "exr";
  const double white = kPanelWhite * value_quantile(observation.samples, 0.99);
  if (write_panels)
    for (const Compared& c : compared) {
      std::error_code error;
      fs::create_directories(fs::path(panels.dir) / c.model->name(), error);
      if (error)
        fail("{}: cannot create folder: {}", (fs::path(panels.dir) / c.model->name()).string(), error.message());
    }

  const cv::Rect box = observation.sphere.bounds(observation.image_size);
  for (size_t i = 0; i < observation.images.size(); ++i) {
    const SphereImage& image = observation.images[i];
    const cv::Mat photo = read_image(image.path, input.decoding);
    const cv::Mat fates = pixel_fates(observation, image, photo, input.rules);
    const cv::Mat used = fates == static_cast<uint8_t>(PixelFate::Used);
    cv::Mat measured;
    cv::multiply(photo(box), cv::Scalar(image.gain[0], image.gain[1], image.gain[2]), measured);
    for (Compared& c : compared) {
      const cv::Mat fitted = render_sphere(*c.model, c.fit->values, observation.sphere, image.light,
                                           observation.image_size, c.fit->channel_values)(box);
      cv::Mat difference = cv::abs(fitted - measured);
      const double squared_difference = cv::norm(difference, cv::NORM_L2SQR, used);
      const double squared_measured = cv::norm(measured, cv::NORM_L2SQR, used);
      c.error.per_image.push_back(squared_measured > 0.0 ? std::sqrt(squared_difference / squared_measured) : NAN);
      c.squared_difference += squared_difference;
      c.squared_measured += squared_measured;
      if (!write_panels) continue;

      // measured | fit | error, the error as a heatmap of the largest channel's difference.
      std::vector<cv::Mat> channels;
      cv::split(difference, channels);
      cv::Mat heat = heatmap(cv::max(cv::max(channels[0], channels[1]), channels[2]), kHeatFullScale * white);
      heat.setTo(cv::Scalar::all(0.2), fates != static_cast<uint8_t>(PixelFate::Used));
      heat.setTo(cv::Scalar::all(0.0), fates == kOffSphere);
      const double scale = display ? 1.0 / white : 1.0;
      cv::Mat panel;
      cv::hconcat(std::vector<cv::Mat>{measured * scale, fitted * scale, heat}, panel);
      write_image(panel_path(panels, c.model->name(), i, image.path), panel);
    }
  }
  std::vector<PhotoError> errors;
  for (Compared& c : compared) {
    c.error.relative_rms = c.squared_measured > 0.0 ? std::sqrt(c.squared_difference / c.squared_measured) : NAN;
    errors.push_back(c.error);
  }
  return errors;
}

namespace {

nlohmann::json json_of(const PixelCounts& p) {
  return {{"used", p.used}, {"shadow", p.shadow}, {"grazing", p.grazing}, {"saturated", p.saturated}, {"dark", p.dark}};
}

nlohmann::json json_of(const SphereView& view) {
  const Circle& c = view.outline();
  nlohmann::json camera = {{"model", "orthographic"}};
  if (view.camera().perspective())
    camera = {{"model", "perspective"},
              {"focal_px", view.camera().focal_px},
              {"principal_point", {view.camera().principal_x, view.camera().principal_y}}};
  return {{"center", {c.x, c.y}}, {"radius", c.radius}, {"camera", camera}};
}

}  // namespace

std::vector<std::string> sphere_input_files(const SphereInput& input) {
  std::vector<std::string> files = input.images;
  files.insert(files.end(), input.chrome.begin(), input.chrome.end());
  for (const std::string* file :
       {&input.lights, &input.chrome_mask, &input.intensities, &input.exposures, &input.mask, &input.normals})
    files.push_back(*file);  // empty ones are ignored by check_outputs
  return files;
}

nlohmann::json sphere_document_json(const std::string& input_path, const SphereInput& input,
                                    const SphereObservation& observation, const SampleSet& fitted,
                                    const FitOptions& options, const std::vector<FitResult>& fits,
                                    const std::vector<PhotoError>& errors) {
  nlohmann::json doc = fit_document_json(input_path, fitted, options, fits);
  doc["input"]["images"] = input.images;
  doc["sphere"] = json_of(observation.sphere);
  doc["sphere"]["located_by"] = observation.located_by;
  if (const auto& n = observation.normals)
    doc["sphere"]["normals_check"] = {
        {"file", n->file}, {"pixels", n->pixels}, {"median_deg", n->median_deg}, {"p90_deg", n->p90_deg}};
  if (observation.chrome_ball) doc["chrome_ball"] = json_of(*observation.chrome_ball);

  nlohmann::json pixels = json_of(observation.pixels);
  pixels["on_sphere"] = observation.sphere_pixels;  // per image
  pixels["images"] = observation.images.size();
  pixels["grid_step"] = observation.grid_step;
  pixels["gathered"] = observation.samples.size();
  pixels["fitted"] = fitted.size();
  doc["pixels"] = pixels;
  doc["pixel_rules"] = {
      {"max_angle_deg", input.rules.max_angle_deg}, {"saturation", input.rules.saturation}, {"dark", input.rules.dark}};
  doc["photometry"] = {
      {"value", "pixel / (intensity * exposure / first exposure * intensity_scale) = f cos(theta_i)"},
      {"intensities", observation.intensities_known ? nlohmann::json(input.intensities) : nlohmann::json(nullptr)},
      {"intensity_scale", observation.intensity_scale},
      {"exposures", observation.exposures_from}};

  doc["lights_from"] = observation.lights_from;
  nlohmann::json lights = nlohmann::json::array(), images = nlohmann::json::array();
  for (size_t i = 0; i < observation.images.size(); ++i) {
    const SphereImage& image = observation.images[i];
    lights.push_back(json_array(image.light));
    nlohmann::json relative_rms = nlohmann::json::object();
    for (const PhotoError& e : errors) relative_rms[e.model] = number_or_null(e.per_image[i]);
    images.push_back(
        {{"path", absolute_path(image.path)},
         {"light", json_array(image.light)},
         {"intensity", observation.intensities_known ? json_array(image.intensity) : nlohmann::json(nullptr)},
         {"exposure", image.exposure},
         {"pixels", json_of(image.pixels)},
         {"relative_rms", relative_rms}});
  }
  doc["lights"] = lights;
  doc["images"] = images;
  for (nlohmann::json& model : doc["models"])
    for (const PhotoError& e : errors)
      if (model["model"] == e.model) model["image_relative_rms"] = number_or_null(e.relative_rms);
  return doc;
}

}  // namespace brdffit
