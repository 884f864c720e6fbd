// Spheres in pictures: where a sphere is, what each of its pixels sees, light directions (from a
// file or a chrome ball), which pixels are fit to measure, and rendering a model onto a sphere.
// The photographs-to-fit pipeline built from these is in sphere_fit.h.
//
// Coordinates. Pixel (x, y) is column x, row y, with integer values at pixel centres (OpenCV's
// convention). Directions are in DiLiGenT's camera frame: x right, y up, z toward the camera.
// An orthographic camera looks along -z, so every pixel's view direction is +z; a perspective
// camera sits at the origin, its principal point usually at the image centre.
#pragma once

#include <cmath>
#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "brdffit/imaging/image_io.h"
#include "brdffit/math.h"
#include "brdffit/model.h"

namespace brdffit {

// The sphere's outline in the picture (for a perspective camera, whose silhouette of a sphere off
// the principal point is an ellipse: the circle of the same centre and area).
struct Circle {
  double x = 0.0, y = 0.0;  // centre, pixels
  double radius = 0.0;      // pixels
};

struct Camera {
  double focal_px = 0.0;                        // focal length in pixels; 0: orthographic
  double principal_x = 0.0, principal_y = 0.0;  // perspective only

  bool perspective() const { return focal_px > 0.0; }
  // A perspective camera with its principal point at the centre of an image of this size, or
  // an orthographic one when focal_px is 0.
  static Camera centred(double focal_px, cv::Size image);
};

// A sphere as a camera sees it: which pixels show it and, for each, the surface normal and the
// direction toward the camera.
class SphereView {
 public:
  SphereView() = default;  // no sphere: every pixel misses
  SphereView(const Circle& outline, const Camera& camera);
  // An orthographic sphere filling a square image of this size, less a one-pixel border.
  static SphereView centred(int size);

  // The unit normal and unit view direction (camera frame) of the sphere point seen through
  // pixel (x, y); false when that pixel's ray misses the sphere.
  bool surface_at(double x, double y, Vec3& normal, Vec3& view) const;
  // The pixels of an image of this size whose ray may meet the sphere.
  cv::Rect bounds(cv::Size image) const;

  const Circle& outline() const { return outline_; }
  const Camera& camera() const { return camera_; }

 private:
  Circle outline_;
  Camera camera_;
  Vec3 centre_ = Vec3::Zero();  // perspective: the sphere's centre in camera space, for a sphere of radius 1
};

// Calls visit(x, y, normal, view) for every pixel of an image of this size whose ray meets the
// sphere and that lies in `mask` (CV_8U, nonzero inside; every such pixel when it is empty).
template <class Visit>
void for_each_sphere_pixel(const SphereView& sphere, cv::Size size, const cv::Mat& mask, Visit&& visit) {
  const cv::Rect box = sphere.bounds(size);
  for (int y = box.y; y < box.y + box.height; ++y)
    for (int x = box.x; x < box.x + box.width; ++x) {
      if (!mask.empty() && !mask.at<uint8_t>(y, x)) continue;
      Vec3 normal, view;
      if (sphere.surface_at(x, y, normal, view)) visit(x, y, normal, view);
    }
}

// The pixels of an image of this size that show the sphere: CV_8U, 255 there, 0 elsewhere.
cv::Mat sphere_pixels(const SphereView& sphere, cv::Size size);

// The sphere's outline from a mask that covers its silhouette (nonzero pixels): the centroid of
// the mask and the radius of a disc of the same area (cv::moments), unbiased for a rasterised
// disc. Throws Error naming `what` when the mask is empty or clearly not a disc.
Circle circle_from_mask(const cv::Mat& mask, const std::string& what);

// Reads a mask image (any format OpenImageIO reads; a pixel is in the mask when its brightest
// channel is above half scale) as CV_8U 0/255; throws Error naming the file.
cv::Mat read_mask(const std::string& path);

// Finds one sphere in a picture (linear RGB): circles found by cv::HoughCircles on the
// gamma-compressed luminance are refined to sub-pixel precision on the silhouette edge (the
// steepest radial fall-off along rays from the centre, circle fitted by least squares), and
// the largest one whose edge holds up is returned. Throws Error naming `what` ("no sphere
// found") when none does.
Circle detect_sphere(const cv::Mat& rgb, const std::string& what);

// Per-pixel maximum over images, so a sphere lit from many sides shows its whole silhouette.
// Throws Error naming the image whose size differs from the first's.
cv::Mat brightest_of(const std::vector<std::string>& paths, const Decoding& decoding);

// Unit light directions, one "x y z" line per image (spaces or commas; '#' comments and blank
// lines skipped), e.g. DiLiGenT's light_directions.txt. Throws Error naming the file for a
// malformed line, a zero direction or a count other than `expected`. Every number in these files
// must be finite and, unless 0, between kMinLightNumber and kMaxLightNumber in size: beyond them
// directions overflow when normalised and gains (1/(intensity·exposure)) overflow the fitter.
constexpr double kMinLightNumber = 1e-100, kMaxLightNumber = 1e100;
std::vector<Vec3> read_light_directions(const std::string& path, size_t expected);
// Light intensities, one "r g b" line per image (e.g. DiLiGenT's light_intensities.txt), each
// positive; same rules.
std::vector<Rgb<double>> read_light_intensities(const std::string& path, size_t expected);
// Exposure times, one positive number per line per image; same rules.
std::vector<double> read_exposures(const std::string& path, size_t expected);

// The light direction a chrome ball shows: the centroid of its highlight (the pixels on the
// ball at least half as bright as the brightest, each weighted by how much brighter than that
// half it is) gives the normal n there, and the light is the mirror reflection of the view
// about n: l = 2(n·v)n - v. Throws Error naming `what` when the ball shows no highlight.
Vec3 light_from_chrome(const cv::Mat& rgb, const SphereView& ball, const std::string& what);

// How far the located sphere's normals lie from a ground-truth normal map such as DiLiGenT's
// Normal_gt.png (a camera-frame normal n stored as (n+1)/2 in any bit depth; pixels whose stored
// vector is far from unit length, as the background's zeros are, hold no normal): angular errors
// over the pixels that show the sphere, hold a normal and lie in `mask` (all when it is empty).
struct NormalCheck {
  std::string file;
  size_t pixels = 0;
  double median_deg = NAN, p90_deg = NAN;
};
// Throws Error naming the file when it cannot be read, differs in size from `size`, or shares
// no pixel with the sphere.
NormalCheck check_normals(const SphereView& sphere, const std::string& normal_map, cv::Size size, const cv::Mat& mask);

// A right-handed orthonormal frame around a normal; to_local maps camera-frame directions to
// the shading frame in which the normal is +z. The tangent runs along the sphere's longitude,
// ŷ × n normalised (y up in the camera frame), as a UV sphere's u does: an anisotropic model's
// x axis (ggx-aniso's phi0 0, gltf+anisotropy's rotation 0) is horizontal, the bitangent
// points up, as three.js draws an exported glTF on its SphereGeometry.
struct LocalFrame {
  explicit LocalFrame(const Vec3& normal);
  Vec3 to_local(const Vec3& d) const { return Vec3(tangent.dot(d), bitangent.dot(d), normal.dot(d)); }
  Vec3 tangent, bitangent, normal;
};

// Which pixels measure the BRDF well enough to fit. Checked in this order, each pixel counted
// under the first reason that applies.
struct PixelRules {
  double max_angle_deg = 80.0;  // grazing: θi or θo above this (Ngan et al. 2005 use 80°)
  double saturation = 0.98;     // integer files: a channel at or above this fraction of full scale is clipped
  double dark = 0.002;          // the brightest channel below this fraction of full scale (float files:
                                // of the image's brightest sphere pixel) is mostly noise
};

enum class PixelFate { Used, Shadow, Grazing, Saturated, Dark };
const char* pixel_fate_name(PixelFate fate);  // "used", "shadow", "grazing", "saturated", "dark"

// `pixel` is the stored linear value (before any exposure or intensity normalisation);
// `full_scale` is 1 for integer files and the image's brightest sphere pixel for float files;
// `clips` says whether the file's largest code means a clipped sensor (integer files).
PixelFate classify_pixel(const Vec3& normal, const Vec3& view, const Vec3& light, const cv::Vec3f& pixel,
                         double full_scale, bool clips, const PixelRules& rules);

// A shaded value f·max(n·l, 0) (1/sr) as a function of the light and view directions in the
// local frame, normal +z.
using ShadeFunction = std::function<Rgb<double>(const Vec3& l, const Vec3& v)>;

// The shaded value for a directional light of unit irradiance at every pixel of an image of this
// size that shows the sphere (0 elsewhere), each pixel in its own shading frame: linear RGB, CV_32FC3.
cv::Mat render_sphere(const ShadeFunction& shade, const SphereView& sphere, const Vec3& light, cv::Size size);
// The same for a model's values (shade_fitted).
cv::Mat render_sphere(const Model& model, const std::vector<double>& values, const SphereView& sphere,
                      const Vec3& light, cv::Size size,
                      const std::vector<std::vector<double>>& per_channel_values = {});

}  // namespace brdffit
