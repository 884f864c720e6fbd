// The HTML report (see report.h).
#include "brdffit/imaging/report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "brdffit/base64.h"
#include "brdffit/compare.h"
#include "brdffit/error.h"
#include "brdffit/imaging/image_io.h"
#include "brdffit/imaging/sphere.h"
#include "brdffit/io.h"
#include "brdffit/measured.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"

namespace brdffit {

namespace {

// Signed relative error maps are full (deep blue, deep red) at ±50 %; below this fraction of the
// tone reference the measured value is floored, so that black pixels do not dominate them.
constexpr double kRelativeFullScale = 0.5;
constexpr double kRelativeFloor = 0.05;
// Slice axes: θh ticks (the columns are √-spaced) and θd ticks, in degrees.
constexpr double kThetaHTicks[] = {0, 2, 10, 30, 60, 90};
constexpr double kThetaDTicks[] = {0, 30, 60, 90};
// Sphere fits: at most this many of the photographs are shown.
constexpr int kPhotographsShown = 4;
// Polar plots: the radius is log10 f over this many decades below the top one.
constexpr int kPolarDecades = 3;
constexpr int kCurvePoints = 179;  // θo = -89°..89° in 1° steps
constexpr const char* kIncidenceColours[] = {"#1f77b4", "#2ca02c", "#d62728", "#9467bd", "#ff7f0e"};
constexpr int kPolarWidth = 220, kPolarHeight = 122;
constexpr int kSliceAxisWidth = 26;  // the θd axis left of a slice
// A slice's tone reference and each slice |error| panel's full scale are 99th percentiles over the
// pixels whose light and view are within 80° of the normal (Ngan's cut-off, fit's --max-angle):
// beyond, where a table of f·cosθ is divided by a vanishing cosine, a few rows are orders of
// magnitude brighter and would otherwise set the scale; they saturate instead. Within 80° a glossy
// table's f still spans decades from head-on to grazing (on the bundled vinyl the median |error| of
// a GGX fit is 1/400 of its 99th percentile), so the |error| colours follow log10 over 3 decades.
constexpr double kSliceScaleQuantile = 0.99;
constexpr double kSliceScaleMaxAngle = 80.0;
constexpr int kSliceErrorDecades = 3;

std::string html(const std::string& text) { return escape_markup(text); }

std::string anchor(const std::string& material) {
  std::string id = "m-";
  for (char c : material) id += std::isalnum(static_cast<unsigned char>(c)) ? c : '-';
  return id;
}

std::string parameters_html(const FitResult& fit) {
  std::string out;
  for (const ParameterEstimate& p : fit.parameters) {
    out += fmt::format("<div>{} {}{}{}</div>", html(p.name), format_values(p.value),
                       p.at_bound ? " <i>at bound</i>" : "", p.identifiable ? "" : " <i>not identifiable</i>");
  }
  return out;
}

std::string image_tag(const cv::Mat& display, const std::string& alt) {
  return fmt::format("<img src=\"{}\" alt=\"{}\" width=\"{}\" height=\"{}\">", png_data_uri(display), html(alt),
                     display.cols, display.rows);
}

// A θh/θd slice (half_diff_slice's layout) with its axes: θh along the bottom, θd down the left.
std::string slice_with_axes(const cv::Mat& display, const std::string& alt) {
  const int size = display.cols, axis = kSliceAxisWidth;
  std::string left = fmt::format("<svg width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\">", axis, size);
  for (double t : kThetaDTicks) {
    const double y = std::clamp(t / 90.0 * size, 0.5, size - 0.5);
    left += fmt::format(
        "<line x1=\"{0}\" y1=\"{1:.1f}\" x2=\"{2}\" y2=\"{1:.1f}\" stroke=\"#666\"/>"
        "<text x=\"{3}\" y=\"{4:.1f}\" font-size=\"8\" text-anchor=\"end\" fill=\"#555\">{5:g}°</text>",
        axis - 4, y, axis, axis - 5, std::clamp(y + 3, 7.0, size - 1.0), t);
  }
  // The axis name between the first two ticks, clear of their labels.
  left += fmt::format("<text x=\"2\" y=\"{}\" font-size=\"9\" fill=\"#333\">θd</text></svg>", size / 6 + 3);
  std::string bottom = fmt::format("<svg width=\"{0}\" height=\"20\" viewBox=\"0 0 {0} 20\">", size);
  for (double t : kThetaHTicks) {
    // Column x holds θh = u²·90° at u = (x + ½)/size.
    const double x = std::clamp(std::sqrt(t / 90.0) * size, 0.5, size - 0.5);
    bottom += fmt::format(
        "<line x1=\"{0:.1f}\" y1=\"0\" x2=\"{0:.1f}\" y2=\"4\" stroke=\"#666\"/>"
        "<text x=\"{1:.1f}\" y=\"12\" font-size=\"8\" text-anchor=\"middle\" fill=\"#555\">{2:g}</text>",
        x, std::clamp(x, 5.0, size - 8.0), t);
  }
  bottom += fmt::format(
      "<text x=\"{}\" y=\"20\" font-size=\"9\" text-anchor=\"middle\" fill=\"#333\">θh °</text></svg>", size / 2);
  return fmt::format("<div class=\"axes\">{}{}<span></span>{}</div>", left, image_tag(display, alt), bottom);
}

// A colour bar of the signed relative error, −full to +full.
std::string signed_colour_bar() {
  cv::Mat ramp(12, 160, CV_32F);
  for (int x = 0; x < ramp.cols; ++x) ramp.col(x).setTo(2.0 * (x + 0.5) / ramp.cols - 1.0);
  return image_tag(signed_heatmap(ramp, 1.0), "signed relative error colour scale");
}

// One row of pictures: the measured table's or one model's.
struct Row {
  std::string label;
  const FitResult* fit = nullptr;           // null for the measured row
  double error = NAN;                       // under the ranking metric
  std::string note;                         // why the row has no pictures
  cv::Mat sphere, environment, slice;       // linear
  std::vector<std::vector<double>> curves;  // luminance of f, one per incidence angle
  cv::Mat sphere_error, slice_error;        // largest channel's |fit − measured|, models only
};

void draw_row(Row& row, const BrdfFunction& brdf, const cv::Mat& sphere, const ReportOptions& options) {
  row.sphere = sphere;
  row.environment = render_environment_sphere(brdf, options.sphere_size);
  row.slice = half_diff_slice(brdf, options.slice_size);
  for (double theta_i : options.incidence_deg) row.curves.push_back(in_plane_curve(brdf, theta_i, kCurvePoints));
}

// The radius of a polar plot: log10 f over kPolarDecades decades, the top one just above the
// largest measured value.
struct PolarScale {
  double top = 0.0;  // log10 of the value at the rim
  double radius(double f) const {
    if (!(f > 0.0)) return 0.0;
    return std::clamp((std::log10(f) - (top - kPolarDecades)) / kPolarDecades, 0.0, 1.08);
  }
};

PolarScale polar_scale(const std::vector<const Row*>& rows) {
  double largest = 0.0;
  for (const Row* row : rows)
    for (const auto& curve : row->curves)
      for (double f : curve)
        if (std::isfinite(f)) largest = std::max(largest, f);
  return {largest > 0.0 ? std::ceil(std::log10(largest)) : 0.0};
}

std::string polyline(const std::vector<double>& curve, const PolarScale& scale, double cx, double cy, double r,
                     const char* colour, bool dashed) {
  std::string points;
  for (size_t k = 0; k < curve.size(); ++k) {
    const double theta = (-89.0 + 178.0 * k / (curve.size() - 1)) * kPi / 180.0;
    const double rho = scale.radius(curve[k]) * r;
    points += fmt::format("{:.1f},{:.1f} ", cx + rho * std::sin(theta), cy - rho * std::cos(theta));
  }
  return fmt::format("<polyline points=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\"{}/>", points, colour,
                     dashed ? " stroke-dasharray=\"4 3\"" : "");
}

// The plane of incidence, normal up, light on the left: dashed the measured curves, solid the model's.
std::string polar_svg(const Row* measured, const Row* model, const PolarScale& scale, const ReportOptions& options) {
  const double width = kPolarWidth, height = kPolarHeight, cx = 110, cy = 114, r = 100;
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} {}\" class=\"polar\">",
      width, height, width, height);
  svg += fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#bbb\"/>", cx - r, cy, cx + r, cy);
  svg += fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#ddd\"/>", cx, cy, cx, cy - r);
  for (int decade = 1; decade <= kPolarDecades; ++decade) {
    const double ring = r * decade / kPolarDecades;
    svg +=
        fmt::format("<path d=\"M {:.1f} {:.1f} A {:.1f} {:.1f} 0 0 1 {:.1f} {:.1f}\" fill=\"none\" stroke=\"#ddd\"/>",
                    cx - ring, cy, ring, ring, cx + ring, cy);
    svg += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" font-size=\"8\" fill=\"#888\">1e{}</text>", cx + ring - 10,
                       cy + 7, static_cast<int>(scale.top) - kPolarDecades + decade);
  }
  for (size_t i = 0; i < options.incidence_deg.size(); ++i) {
    const char* colour = kIncidenceColours[i % std::size(kIncidenceColours)];
    const double theta = options.incidence_deg[i] * kPi / 180.0;  // the light, on the -x side
    svg +=
        fmt::format("<line x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"{}\" stroke-width=\"3\"/>",
                    cx - r * 1.0 * std::sin(theta), cy - r * 1.0 * std::cos(theta), cx - r * 1.08 * std::sin(theta),
                    cy - r * 1.08 * std::cos(theta), colour);
    if (measured) svg += polyline(measured->curves[i], scale, cx, cy, r, colour, true);
    if (model) svg += polyline(model->curves[i], scale, cx, cy, r, colour, false);
  }
  return svg + "</svg>";
}

// A horizontal colour bar of the error heatmap, shared by every legend.
std::string colour_bar() {
  cv::Mat ramp(12, 160, CV_32F);
  for (int x = 0; x < ramp.cols; ++x) ramp.col(x).setTo((x + 0.5) / ramp.cols);
  return image_tag(heatmap(ramp, 1.0), "error colour scale");
}

const char* kStyle = R"(
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 1560px; padding: 0 1em; color: #222; }
h1 { margin-bottom: 0.2em; } h2 { margin-top: 2em; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; margin: 0.8em 0; }
th, td { padding: 3px 8px; border-bottom: 1px solid #eee; vertical-align: middle; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
.scroll { overflow-x: auto; }
.matrix td.best { background: #d9f0d3; font-weight: bold; }
.matrix td.failed, .failed { color: #999; font-style: italic; }
.matrix td.poor { background: #fde2c8; color: #8a3b00; }
.poor-verdict, .warning { color: #8a3b00; }
.matrix td.poor::after { content: " poor"; font-size: 0.8em; }
.pictures { margin: 0.8em 0; }
.pictures .row { display: flex; flex-wrap: wrap; align-items: flex-start; gap: 4px 6px; padding: 4px 0;
  border-bottom: 1px solid #eee; }
.pictures .head { font-weight: bold; border-bottom: 1px solid #ccc; }
.pictures .row > div { flex: 0 0 auto; }
.pictures .row > .label { flex: 0 0 9em; }
.pictures .row > .params { flex: 1 1 20em; min-width: 16em; overflow-wrap: anywhere; }
.pictures img { display: block; background: #000; }
.caption { font-size: 0.75em; color: #555; }
img.slice { image-rendering: pixelated; }
.params { font-size: 0.8em; color: #555; }
.meta, .legend { color: #555; font-size: 0.9em; }
.legend img { display: inline-block; vertical-align: middle; margin: 0 0.4em; }
.note { background: #fff4ce; padding: 0.4em 0.8em; }
.axes { display: grid; grid-template-columns: auto auto; align-items: start; }
.axes svg { display: block; }
.photographs figure { display: inline-block; margin: 0 0.6em 0.4em 0; font-size: 0.8em; color: #555; }
#image-check[data-broken]:not([data-broken="0"]) { background: #fdd; padding: 0.4em; }
)";

// Marks images that did not load, and counts boxes whose content is wider than they are, for people
// and for the headless-browser test.
const char* kImageCheck = R"(<script>
window.addEventListener('load', function () {
  var images = Array.prototype.slice.call(document.images);
  var broken = images.filter(function (i) { return !(i.complete && i.naturalWidth > 0); });
  var status = document.getElementById('image-check');
  status.setAttribute('data-total', images.length);
  status.setAttribute('data-broken', broken.length);
  // Content wider than its box (the page, or a material's pictures) would scroll sideways.
  var boxes = [document.documentElement].concat(Array.prototype.slice.call(document.querySelectorAll('.pictures')));
  status.setAttribute('data-sideways', boxes.filter(function (b) { return b.scrollWidth > b.clientWidth + 1; }).length);
  if (broken.length) status.textContent = broken.length + ' of ' + images.length + ' images failed to load';
});
</script>)";

std::string comparison_html(const Comparison& c) {
  const std::string metric = metric_name(c.metric);
  std::string out = "<section id=\"comparison\"><h2>Models over all materials</h2>";
  out += fmt::format(
      "<table class=\"summary\"><tr><th>model</th><th>fitted</th><th>failed</th><th>mean {0}</th><th>median {0}</th>"
      "<th>mean rank</th><th>best on</th></tr>",
      metric);
  const auto number = [](double x) { return std::isfinite(x) ? fmt::format("{:.4g}", x) : std::string("–"); };
  for (const ModelSummary& m : c.models)
    out += fmt::format(
        "<tr><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td "
        "class=\"num\">{}</td>"
        "<td class=\"num\">{:.2f}</td><td class=\"num\">{}</td></tr>",
        html(m.model), m.materials - m.failed, m.failed, number(m.mean_error), number(m.median_error), m.mean_rank,
        m.wins);
  // Wide with many models: the matrix scrolls sideways inside its own box, the page does not.
  out +=
      "</table><h3>Error per material (rank)</h3><div class=\"scroll\"><table class=\"matrix\"><tr><th>material</th>";
  for (const ModelSummary& m : c.models) out += "<th>" + html(m.model) + "</th>";
  out += "</tr>";
  for (const MaterialRanking& material : c.materials) {
    out += fmt::format("<tr><td><a href=\"#{}\">{}</a></td>", anchor(material.material), html(material.material));
    for (const ModelSummary& m : c.models) {
      const RankedModel* r = material.find(m.model);
      if (!r)
        out += "<td></td>";
      else if (!r->ok)
        out += "<td class=\"failed\">failed</td>";
      else
        out +=
            fmt::format("<td class=\"num{}{}\"{}>{:.4g} ({})</td>", material.is_best_usable(*r) ? " best" : "",
                        r->verdict == Verdict::Poor ? " poor" : "",
                        r->verdict == Verdict::Poor ? " title=\"poor fit: see its warnings\"" : "", r->error, r->rank);
    }
    out += "</tr>";
  }
  return out + "</table></div></section>\n";
}

// A sphere fit's camera and sphere, as its document records them.
SphereView recorded_sphere_view(const nlohmann::json& sphere) {
  const Circle outline{sphere.at("center").at(0).get<double>(), sphere.at("center").at(1).get<double>(),
                       sphere.at("radius").get<double>()};
  Camera camera;
  const nlohmann::json& recorded = sphere.at("camera");
  if (recorded.value("model", "") == "perspective")
    camera = {recorded.at("focal_px").get<double>(), recorded.at("principal_point").at(0).get<double>(),
              recorded.at("principal_point").at(1).get<double>()};
  return SphereView(outline, camera);
}

Vec3 json_vec3(const nlohmann::json& j, const Vec3& otherwise) {
  return j.is_array() && j.size() == 3 ? Vec3(j[0].get<double>(), j[1].get<double>(), j[2].get<double>()) : otherwise;
}

// A sphere fit's photographs (a few, evenly spread over the set), cropped to the sphere, each beside
// the best model rendered under its light with the document's photometry (pixel = f·cosθi ·
// intensity · exposure · intensity_scale) and the same tone mapping: what the fits were made from,
// and how the best one reproduces it. Empty for other documents.
std::string photographs_html(const FitDocument& document, const MaterialRanking& ranking,
                             const ReportOptions& options) {
  const nlohmann::json& doc = document.json;
  if (!doc.contains("images") || !doc["images"].is_array() || doc["images"].empty() || !doc.contains("sphere"))
    return "";
  const nlohmann::json& images = doc["images"];
  // The best usable fit; when every fit is poor, the best-ranked one (the caption says which).
  const FitResult* best = find_result(document.results, ranking.best_usable);
  for (const RankedModel& ranked : ranking.models)
    if (ranked.ok && !best) best = find_result(document.results, ranked.model);
  const Model* best_model = best ? find_model(best->model) : nullptr;
  const double intensity_scale = doc.value("/photometry/intensity_scale"_json_pointer, 1.0);

  std::string out = fmt::format(
      "<div class=\"photographs\"><p class=\"legend\">Photographs the fits were made from{}, each tone-mapped on "
      "its own; light direction in the camera frame (x right, y up, z toward the camera):</p>",
      best_model ? ", beside the best model (" + html(best->model) + ") under the same light on the same scale" : "");
  const size_t count = images.size(), shown = std::min<size_t>(count, kPhotographsShown);
  for (size_t k = 0; k < shown; ++k) {
    const nlohmann::json& image = images[k * count / shown];
    const std::string path = image.value("path", "");
    const Vec3 light = json_vec3(image.value("light", nlohmann::json()), Vec3::UnitZ());
    out += "<figure>";
    try {
      const SphereView view = recorded_sphere_view(doc["sphere"]);
      const Circle& c = view.outline();
      const cv::Mat photo = read_image(path);
      const cv::Rect crop = cv::Rect(cvRound(c.x - 1.1 * c.radius), cvRound(c.y - 1.1 * c.radius),
                                     cvRound(2.2 * c.radius), cvRound(2.2 * c.radius)) &
                            cv::Rect(0, 0, photo.cols, photo.rows);
      if (crop.empty()) fail("{}: the sphere is outside the picture", path);
      const double zoom = static_cast<double>(options.sphere_size) / std::max(crop.width, crop.height);
      const auto shrink = [&](const cv::Mat& full) {
        cv::Mat small;
        cv::resize(full(crop), small, cv::Size(), zoom, zoom, cv::INTER_AREA);
        return small;
      };
      const cv::Mat photo_small = shrink(photo);
      const double reference = tone_reference(photo_small);
      out += image_tag(tone_map(photo_small, reference), "photograph " + path);
      if (best_model) {
        const Rgb<double> intensity = json_vec3(image.value("intensity", nlohmann::json()), Vec3::Ones());
        const double gain = image.value("exposure", 1.0) * intensity_scale;
        cv::Mat rendered = render_sphere(*best_model, best->values, view, light, photo.size(), best->channel_values);
        cv::multiply(rendered, cv::Scalar(intensity[0] * gain, intensity[1] * gain, intensity[2] * gain), rendered);
        out += image_tag(tone_map(shrink(rendered), reference), best->model + " under the light of " + path);
      }
    } catch (const std::exception& e) {
      out += fmt::format("<p class=\"failed\">{}</p>", html(e.what()));
    }
    out += fmt::format("<figcaption>{} · light ({:.2f}, {:.2f}, {:.2f})</figcaption></figure>",
                       html(std::filesystem::path(path).filename().string()), light.x(), light.y(), light.z());
  }
  return out + fmt::format("<p class=\"meta\">{} of {} photographs shown.</p></div>", shown, count);
}

std::string material_html(const FitDocument& document, const MaterialRanking& ranking, const ReportOptions& options,
                          const std::string& bar, const std::string& signed_bar) {
  std::string notes;
  std::unique_ptr<MeasuredBrdf> table;
  const bool from_photographs = document.json.contains("images") && document.json.contains("sphere");
  if (from_photographs) {
    notes += "<p class=\"meta\">Fitted from photographs: no measured table to picture; the photographs are below.</p>";
  } else
    try {
      table = open_measured(document.input_path);
      const nlohmann::json* recorded = json_field(document.json, {"input", "sha256"});
      if (recorded && recorded->is_string() && recorded->get<std::string>() != sha256_file(document.input_path))
        notes +=
            "<p class=\"note\">The table has changed since it was fitted: the pictures show its current contents.</p>";
    } catch (const Error& e) {
      notes += fmt::format("<p class=\"note\">No measured pictures: {}</p>", html(e.what()));
    }

  // Rows: the measured table, then the models best first (failed ones only listed).
  std::vector<Row> rows;
  rows.reserve(ranking.models.size() + 1);
  const int size = options.sphere_size;
  if (table) {
    rows.emplace_back();
    rows.back().label = "measured";
    draw_row(rows.back(), measured_brdf(*table), render_measured_sphere(*table, options.lighting, size), options);
  }
  std::string failures;
  int pictured = 0;
  for (const RankedModel& ranked : ranking.models) {
    const FitResult* fit = find_result(document.results, ranked.model);
    if (!ranked.ok) {
      const std::string why = fit && !fit->error.empty() ? fit->error : "no error value";
      failures += fmt::format("<li>{}: {}</li>", html(ranked.model), html(why));
      continue;
    }
    if (options.top > 0 && pictured >= options.top) continue;
    ++pictured;
    Row row;
    row.label = fmt::format("{}. {}", ranked.rank, ranked.model);
    row.fit = fit;
    row.error = ranked.error;
    const Model* model = find_model(ranked.model);
    try {
      if (!model) fail("not a model of this version of brdffit");
      draw_row(row, fitted_brdf(*model, *fit), render_fitted_sphere(*model, *fit, options.lighting, size), options);
    } catch (const Error& e) {
      row.note = e.what();
    }
    rows.push_back(std::move(row));
  }

  // One tone mapping and one polar scale for the material: the measured pictures', else the best model's.
  const cv::Mat mask = sphere_mask(size);
  const auto pictured_row = std::find_if(rows.begin(), rows.end(), [](const Row& r) { return !r.sphere.empty(); });
  const Row* measured = table ? &rows.front() : nullptr;
  const double sphere_reference = pictured_row == rows.end() ? 1.0 : tone_reference(pictured_row->sphere, mask);
  const cv::Mat slice_scale_mask = slice_mask(options.slice_size, kSliceScaleMaxAngle);
  const double slice_reference =
      pictured_row == rows.end() ? 1.0 : tone_reference(pictured_row->slice, slice_scale_mask);
  const double environment_reference =
      pictured_row == rows.end() ? 1.0 : tone_reference(pictured_row->environment, mask);
  // The spheres' absolute error maps share one scale per material, full at the largest 99th
  // percentile of any model's error: the worst fit's worst pixels saturate, every other shade is
  // readable. Each slice's map has its own (robust_error_panel), written under it.
  double sphere_error_scale = 0.0;
  if (measured)
    for (Row& row : rows) {
      if (&row == measured || row.sphere.empty()) continue;
      row.sphere_error = channel_max_difference(row.sphere, measured->sphere);
      row.slice_error = channel_max_difference(row.slice, measured->slice);
      sphere_error_scale = std::max(sphere_error_scale, quantile(row.sphere_error, 0.99, mask));
    }
  if (!(sphere_error_scale > 0.0)) sphere_error_scale = sphere_reference;
  std::vector<const Row*> scale_rows;
  for (const Row& row : rows)
    if (!row.curves.empty() && (!measured || &row == measured)) scale_rows.push_back(&row);
  const PolarScale scale = polar_scale(scale_rows);

  std::string out = fmt::format("<section class=\"material\" id=\"{}\"><h2>{}</h2>", anchor(ranking.material),
                                html(ranking.material));
  out +=
      fmt::format("<p class=\"meta\">{} · {} samples ({} weights) · result {}</p>", html(document.input_path),
                  document.json.value("samples", 0), html(document.json.value("weighting", "?")), html(document.path));
  out += notes;
  std::string incidence;
  for (size_t i = 0; i < options.incidence_deg.size(); ++i)
    incidence += fmt::format("{}<span style=\"color:{}\">θi = {:g}°</span>", i ? ", " : "",
                             kIncidenceColours[i % std::size(kIncidenceColours)], options.incidence_deg[i]);
  const Vec3& l = options.lighting.light;
  const Vec3& v = options.lighting.view;
  out += fmt::format(
      "<p class=\"legend\">Spheres: light from ({:.2g}, {:.2g}, {:.2g}), seen from ({:.2g}, {:.2g}, {:.2g}); f·cosθi "
      "tone-mapped with reference {:.4g} ({}). Environment: the sphere under a sky with a warm key light from the "
      "upper left, {} directional lights (reference {:.4g}). Slices: f at φd = 90°, θh → right (√-spaced), θd ↓, "
      "reference {:.4g} (99th percentile where θi, θo ≤ {:g}°).<br>",
      l.x(), l.y(), l.z(), v.x(), v.y(), v.z(), sphere_reference,
      measured ? "99th percentile of the measured sphere" : "the best model's, no measured data", kEnvironmentLights,
      environment_reference, slice_reference, kSliceScaleMaxAngle);
  if (measured)
    out += fmt::format(
        "|fit − measured| (largest channel): spheres 0 {} {:.3g} (the largest 99th percentile of any model's); "
        "slices log10 over {} decades {} up to each panel's own {:g}th percentile of |error| where θi, θo ≤ {:g}°, "
        "written under it (the grazing pixels beyond saturate rather than set the scale).<br>"
        "(fit − measured) / measured in luminance (measured floored at {:g} % of the reference): −{:g} % {} +{:g} %: "
        "blue where the fit is too dark, red where it is too bright.<br>",
        bar, sphere_error_scale, kSliceErrorDecades, bar, 100 * kSliceScaleQuantile, kSliceScaleMaxAngle,
        100 * kRelativeFloor, 100 * kRelativeFullScale, signed_bar, 100 * kRelativeFullScale);
  out +=
      fmt::format("In-plane curves, log10 f over {} decades, light on the left: {}; dashed measured, solid model.</p>",
                  kPolarDecades, incidence);
  out += photographs_html(document, ranking, options);

  // A row per picture set: fixed-width boxes, so that when the window is narrow they wrap at the
  // same place in every row and in the heading; the parameters and warnings take what is left of
  // the row or a line of their own below the pictures (no sideways scrolling).
  const auto box = [](const char* kind, const std::string& content) {
    return fmt::format("<div class=\"{}\">{}</div>", kind, content);
  };
  out += "<div class=\"pictures\"><div class=\"row head\">" + box("label", "") + box("c-sphere", "sphere") +
         box("c-sphere", "environment") + box("c-sphere", "|error|") + box("c-sphere", "relative error") +
         box("c-axes", "θh/θd slice") + box("c-slice", "|error|") + box("c-slice", "relative error") +
         box("c-polar", "in plane") + "</div>";
  for (const Row& row : rows) {
    const bool is_measured = &row == measured;
    std::string label = html(row.label);
    if (!is_measured)
      label += fmt::format("<br><span class=\"params\">{} {:.4g}</span>", metric_name(*options.metric), row.error);
    if (row.fit && row.fit->verdict == Verdict::Poor) label += "<br><span class=\"poor-verdict\">poor fit</span>";
    out += "<div class=\"row\">" + box("label", label);
    if (!row.note.empty()) {
      out += box("failed", html(row.note)) + "</div>";
      continue;
    }
    const bool compared = measured && !is_measured;
    out += box("c-sphere", image_tag(tone_map(row.sphere, sphere_reference), row.label + " sphere"));
    out += box("c-sphere", image_tag(tone_map(row.environment, environment_reference), row.label + " environment"));
    out += box("c-sphere", compared ? image_tag(error_heatmap(row.sphere_error, sphere_error_scale, mask),
                                                row.label + " sphere error")
                                    : "");
    out += box("c-sphere", compared
                               ? image_tag(signed_heatmap(signed_relative_difference(row.sphere, measured->sphere,
                                                                                     kRelativeFloor * sphere_reference),
                                                          kRelativeFullScale, mask),
                                           row.label + " sphere relative error")
                               : "");
    out += box("c-axes", slice_with_axes(tone_map(row.slice, slice_reference), row.label + " slice"));
    if (compared) {
      const ErrorPanel panel =
          robust_error_panel(row.slice_error, kSliceScaleQuantile, slice_scale_mask, kSliceErrorDecades);
      out += box("c-slice",
                 image_tag(panel.image, row.label + " slice error") +
                     fmt::format("<div class=\"caption\" title=\"log10 |error| over {3} decades, full at the {0:g}th "
                                 "percentile of this panel's |error| where θi, θo ≤ {1:g}°\">log {2:.2g} – {4:.3g} "
                                 "(p{0:g}, θ ≤ {1:g}°)</div>",
                                 100 * kSliceScaleQuantile, kSliceScaleMaxAngle,
                                 panel.full_scale * std::pow(10.0, -kSliceErrorDecades), kSliceErrorDecades,
                                 panel.full_scale));
      out += box("c-slice", image_tag(signed_heatmap(signed_relative_difference(row.slice, measured->slice,
                                                                                kRelativeFloor * slice_reference),
                                                     kRelativeFullScale),
                                      row.label + " slice relative error"));
    } else {
      out += box("c-slice", "") + box("c-slice", "");
    }
    out += box("c-polar", polar_svg(measured, is_measured ? nullptr : &row, scale, options));
    std::string warnings;
    if (row.fit)
      for (const std::string& w : row.fit->warnings) warnings += "<br><span class=\"warning\">⚠ " + html(w) + "</span>";
    if (row.fit) out += box("params", parameters_html(*row.fit) + warnings);
    out += "</div>";
  }
  out += "</div>";
  if (!failures.empty()) out += "<p class=\"failed\">Fits that failed:</p><ul class=\"failed\">" + failures + "</ul>";
  return out + "</section>\n";
}

}  // namespace

std::string png_data_uri(const cv::Mat& display) {
  cv::Mat srgb = display.clone();
  linear_to_srgb(srgb);
  cv::Mat codes, bgr;
  srgb.convertTo(codes, CV_8UC3, 255.0);  // rounds and saturates
  cv::cvtColor(codes, bgr, cv::COLOR_RGB2BGR);
  std::vector<uchar> png;
  if (!cv::imencode(".png", bgr, png)) fail("internal: cannot encode a PNG image");
  return "data:image/png;base64," + base64(png);
}

std::string report_html(const std::vector<FitDocument>& documents, const ReportOptions& given) {
  ReportOptions options = given;
  if (!options.metric) options.metric = common_metric(documents);
  const Comparison comparison = compare_results(documents, *options.metric);
  const std::string bar = colour_bar(), signed_bar = signed_colour_bar();

  std::string page = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>brdffit report</title>";
  // The picture boxes' widths, from the picture sizes.
  const std::string widths = fmt::format(
      ".c-sphere {{ width: {}px; }} .c-axes {{ width: {}px; }} .c-slice {{ width: {}px; }} .c-polar {{ width: {}px; }}",
      options.sphere_size, options.slice_size + kSliceAxisWidth, options.slice_size, kPolarWidth);
  page += fmt::format("<style>{}{}</style></head><body>\n", kStyle, widths);
  page += fmt::format(
      "<header><h1>brdffit report</h1><p class=\"meta\">{}, {}, ranked by the {} metric · brdffit "
      "{}</p>"
      "<p id=\"image-check\"></p></header>\n",
      count_of(documents.size(), "material"), count_of(comparison.models.size(), "model"), metric_name(*options.metric),
      BRDFFIT_VERSION);
  page += comparison_html(comparison);
  for (size_t i = 0; i < documents.size(); ++i) {
    page += material_html(documents[i], comparison.materials[i], options, bar, signed_bar);
    if (options.progress) options.progress(i, documents.size(), comparison.materials[i].material);
  }
  page += kImageCheck;
  return page + "\n</body></html>\n";
}

}  // namespace brdffit
