// One self-contained HTML page about a set of fitted materials, to read offline: the comparison
// of models (compare.h), and per material the measured pictures beside each model's: a sphere
// under a light and under an environment, the θh/θd slice with its axes, the error of sphere and
// slice both absolute and signed relative, and in-plane curves on polar plots. A sphere fit's
// section shows a few of its photographs, each beside the best model under the same light.
// Images are PNG data URIs, plots inline SVG; nothing is loaded from elsewhere. The library side
// of `brdffit report`.
//
// Every picture of a material shares one tone mapping (render.h's tone_map, its reference the
// 99th percentile of the measured picture, or of the best model's when the table cannot be read;
// for slices over the pixels whose light and view are within 80° of the normal, render.h's
// slice_mask), so brightness differences between measured and fitted pictures are real. The
// absolute error maps show the largest channel's |fit − measured|: the spheres' full colour at the
// largest 99th percentile of any model's error on that material, each slice's at its own 99th
// percentile within 80° (robust_error_panel: the grazing rows beyond, orders of magnitude larger
// in a table of f·cosθ, saturate), written under it. The relative ones show (fit − measured) /
// measured in luminance, full blue or red at ±50 %. The pictures of a row wrap, and the
// parameters and warnings go below them, so that the page never scrolls sideways.
// The page marks images that fail to load in #image-check (data-total, data-broken) once loaded,
// and how many boxes would scroll sideways (data-sideways: the page or a material's pictures).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "brdffit/imaging/render.h"
#include "brdffit/metric.h"
#include "brdffit/result_json.h"

namespace brdffit {

struct ReportOptions {
  std::optional<Metric> metric;  // ranking metric; default: the one the documents were fitted with
  SphereLighting lighting;
  int sphere_size = 160;  // pixels
  int slice_size = 128;
  int top = 0;                                             // picture the best `top` models of each material; 0: all
  std::vector<double> incidence_deg = {20.0, 45.0, 70.0};  // in-plane curves
  // Called after each material's pictures (index from 0), e.g. for progress lines.
  std::function<void(size_t index, size_t count, const std::string& material)> progress;
};

// The page. Materials whose table cannot be read (moved, or CSV samples that cannot be evaluated
// everywhere) get the models' pictures and a note saying why the measured ones are missing.
std::string report_html(const std::vector<FitDocument>& documents, const ReportOptions& options);

// An image (CV_32FC3 display values in [0, 1], linear light) as an sRGB PNG data URI.
std::string png_data_uri(const cv::Mat& display);

}  // namespace brdffit
