// Image files, through OpenImageIO, and the few pixel conversions around them.
//
// In memory an image is a cv::Mat of type CV_32FC3 holding LINEAR RGB values in that order (not
// OpenCV's usual BGR), rows top to bottom: OpenCV does the geometry on it, OpenImageIO reads and
// writes the files. Integer files are read normalised to [0, 1] (the largest code is 1).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

namespace brdffit {

// How a file's stored values become linear values.
enum class Transfer {
  Auto,    // 8-bit files are sRGB-encoded and decoded; 16-bit, half and float files are linear
  Linear,  // the stored values are linear (--linear)
  Srgb,    // the sRGB curve, whatever the bit depth
  Gamma,   // linear = stored^gamma (--gamma G)
};

struct Decoding {
  Transfer transfer = Transfer::Auto;
  double gamma = 2.2;  // for Transfer::Gamma
};

// Parses a --gamma value: a positive number, or "srgb". Throws Error naming the option.
Decoding parse_gamma(const std::string& text);

// What the file's header says, without reading the pixels.
struct ImageInfo {
  int width = 0, height = 0, channels = 0;
  bool integer_codes = false;  // 8- or 16-bit integers: the largest code is where the sensor clipped
  int bits = 0;                // bits per stored channel value
  double exposure_time = 0.0;  // seconds, from the file's metadata (EXIF ExposureTime); 0 when absent
};

// Throws Error naming the file when it is missing or not an image OpenImageIO reads.
ImageInfo read_image_info(const std::string& path);

// The most pixels read_image reads from one file (a bound on memory: each pixel takes 12 bytes
// and more while decoding); larger files are refused with an error naming the limit. Process-wide,
// set from the command line (--max-pixels).
constexpr uint64_t kDefaultMaxImagePixels = uint64_t{100} << 20;  // about 10000x10000
void set_max_image_pixels(uint64_t pixels);
uint64_t get_max_image_pixels();
// And the most bytes its pixels may decode to (a float per channel): those of the pixel limit
// at kMaxBudgetChannels channels (RGBA), so that a small file declaring many channels cannot
// ask for many times the memory the pixel limit means to allow.
constexpr uint64_t kMaxBudgetChannels = 4;
uint64_t max_image_bytes();

// Reads an image as linear RGB (grey images are spread over the three channels, alpha and any
// further channels are dropped). Throws Error naming the file when it cannot be read or holds
// NaN or infinite values.
cv::Mat read_image(const std::string& path, const Decoding& decoding = {});

// How write_image stores the linear values.
enum class Encoding {
  Auto,      // by extension: .exr and .hdr linear float, everything else 8-bit sRGB
  Srgb8,     // clamped to [0, 1], sRGB-encoded, 8 bits (for viewing: PNG, JPEG)
  Linear16,  // clamped to [0, 1], linear, 16 bits (PNG, TIFF)
  Float,     // linear 32-bit float (EXR, TIFF)
};

// Whether a file name's extension is that of a format write_image stores linear float values in
// (.exr, .hdr, any case); the others get 8-bit sRGB by default.
bool stores_linear_values(const std::string& path);

// Writes an RGB image (CV_32FC3, linear) whole or not at all: to a temporary file beside `path`,
// renamed over it once complete. The format follows the extension. Throws Error naming the file.
void write_image(const std::string& path, const cv::Mat& rgb, Encoding encoding = Encoding::Auto);

// The sRGB transfer curve in either direction, in place, on a CV_32FC3 image (OpenImageIO's colour
// conversion).
void srgb_to_linear(cv::Mat& rgb);
void linear_to_srgb(cv::Mat& rgb);

// A scalar image (CV_32F) shown in colour: 0 dark purple through to bright yellow at
// `full_scale` and above (OpenCV's inferno map), as linear RGB ready for write_image.
cv::Mat heatmap(const cv::Mat& magnitude, double full_scale);

}  // namespace brdffit
