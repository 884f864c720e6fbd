// Pictures of reflectance for people to judge: a sphere under a directional light, the θh/θd
// slice at φd = 90° and in-plane curves, each of a measured table or of a fitted model, and the
// tone mapping that shows measured and fitted pictures on one scale. The library side of
// `brdffit render` and of the report's images.
//
// Images are CV_32FC3 linear RGB, rows top to bottom (image_io.h's convention).
#pragma once

#include <functional>
#include <opencv2/core.hpp>
#include <vector>

#include "brdffit/fit.h"
#include "brdffit/math.h"
#include "brdffit/measured.h"
#include "brdffit/model.h"

namespace brdffit {

// f(l, v) in 1/sr for unit directions in the local frame (n = +z).
using BrdfFunction = std::function<Rgb<double>(const Vec3& l, const Vec3& v)>;

// A measured table's f (MeasuredBrdf::eval).
BrdfFunction measured_brdf(const MeasuredBrdf& table);
// A fitted model's f, as its shaded value / cosθi (stylised models have no other), with the
// per-channel values when the fit has them. Throws Error when the result's values do not fit
// the model (a document from another version).
BrdfFunction fitted_brdf(const Model& model, const FitResult& fit);

// A sphere photographed by an orthographic camera from `view`, lit by a directional light of unit
// irradiance from `light`; both directions in one world frame, towards the light and towards the
// camera. The picture's up is the world's +y (+z when the view is along y). The models are
// isotropic, so only the angle between light and view and the light's side matter.
struct SphereLighting {
  Vec3 light = Vec3(-1.0, 1.0, 2.0).normalized();  // upper left, 35° off the view
  Vec3 view = Vec3::UnitZ();
};

// The light in the camera frame of sphere.h (x right, y up, z toward the camera). Throws Error
// for a zero light or view.
Vec3 light_in_camera_frame(const SphereLighting& lighting);

// The shaded value f·cosθi at every pixel of a size x size picture that shows the sphere (zero
// elsewhere). The fitted one is sphere.h's render_sphere; both use SphereView::centred(size).
cv::Mat render_measured_sphere(const MeasuredBrdf& table, const SphereLighting& lighting, int size);
cv::Mat render_fitted_sphere(const Model& model, const FitResult& fit, const SphereLighting& lighting, int size);
// 255 on the pixels of that picture that show the sphere, 0 elsewhere (CV_8U).
cv::Mat sphere_mask(int size);

// The same sphere lit by an environment instead of one light: a sky brighter overhead than at the
// horizon, a warm key light from the upper left and a dim ground, stood in for by
// kEnvironmentLights directional lights spread evenly over every direction (a Fibonacci
// lattice), each carrying its share of the environment's radiance. Shows a material the way a
// renderer's scene would, for measured table and fits alike: f is only ever looked up, so a
// table and a model are rendered by the same sum.
constexpr int kEnvironmentLights = 256;
cv::Mat render_environment_sphere(const BrdfFunction& brdf, int size);

// f over the half/difference plane at φd = 90° (the MERL slice): column x is θh from 0 to 90°
// spaced like MERL's bins (θh ∝ u², u = (x+½)/size, so the specular peak gets room), row y is
// θd from 0 (top) to 90°. At φd = 90° both directions stay above the horizon (n·l = n·v =
// cosθh·cosθd), so every pixel has a value.
cv::Mat half_diff_slice(const BrdfFunction& brdf, int size);
// The pixels of half_diff_slice(size) whose light and view are both within max_angle_deg of the
// normal (CV_8U, 255 inside): at φd = 90° both are at arccos(cosθh·cosθd). Outside, near grazing,
// a table of f·cosθ divided by a vanishing cosine gives values orders of magnitude above the rest.
cv::Mat slice_mask(int size, double max_angle_deg);

// Luminance (Rec. 709) of f in the plane of incidence, light at theta_i_deg from the normal on
// the -x side: one value per outgoing angle θo = -89°..89° in `points` steps, negative θo on the
// light's side (the mirror direction is θo = +θi).
std::vector<double> in_plane_curve(const BrdfFunction& brdf, double theta_i_deg, int points);

// Linear values to display values in [0, 1] (still linear light; write_image or png_data_uri
// sRGB-encode them). Values are divided by `reference`, which then shows as about 75% grey in
// sRGB, and rolled off smoothly to white at 4x the reference (extended Reinhard), so that
// highlights keep their shape. The same reference for measured and fitted pictures keeps them
// comparable. NaN (no data) shows as dark grey.
cv::Mat tone_map(const cv::Mat& linear, double reference);
// The 99th percentile of the brightest channel over the pixels where mask is non-zero (every
// finite pixel when the mask is empty); 1 when that is not positive.
double tone_reference(const cv::Mat& linear, const cv::Mat& mask = cv::Mat());

// The q-quantile (0..1, nearest rank) of the finite values of a CV_32F image where mask is
// non-zero (every pixel when the mask is empty); 0 when there are none.
double quantile(const cv::Mat& values, double q, const cv::Mat& mask = cv::Mat());

// The signed relative error of `fit` against `measured` in luminance, (Y_fit − Y_measured) /
// max(Y_measured, floor) (CV_32F): positive where the fit is too bright. The floor keeps the
// nearly black pixels from dominating; NaN where either is NaN.
cv::Mat signed_relative_difference(const cv::Mat& fit, const cv::Mat& measured, double floor);
// A diverging map of signed values: blue where negative, white at 0, red where positive, full
// at ±full_scale; dark grey where mask is zero or the value is NaN.
cv::Mat signed_heatmap(const cv::Mat& values, double full_scale, const cv::Mat& mask = cv::Mat());

// The largest channel's |a - b| (CV_32F), NaN where either is NaN.
cv::Mat channel_max_difference(const cv::Mat& a, const cv::Mat& b);
// heatmap() of a difference, full at full_scale; dark grey where mask is zero or the difference is NaN.
cv::Mat error_heatmap(const cv::Mat& difference, double full_scale, const cv::Mat& mask = cv::Mat());
// An |error| panel on its own robust scale: error_heatmap of every pixel, full at the q-quantile of
// the finite values where scale_mask is non-zero (every pixel when it is empty), so that a few
// extreme pixels (a slice's grazing rows, see slice_mask) saturate instead of setting the scale and
// leaving every other pixel black. When that quantile is 0, the largest such value (1 when all are
// 0). With decades > 0 the colours follow log10 |error| over that many decades below the full
// scale (black at or below full scale·10^-decades), for errors that span orders of magnitude, as a
// glossy table's f does from head-on to grazing. The scale is returned with the picture, for its
// caption.
struct ErrorPanel {
  cv::Mat image;
  double full_scale = 1.0;
};
ErrorPanel robust_error_panel(const cv::Mat& difference, double q, const cv::Mat& scale_mask = cv::Mat(),
                              int decades = 0);

}  // namespace brdffit
