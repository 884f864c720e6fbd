#include "brdffit/imaging/image_io.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "brdffit/error.h"
#include "brdffit/io.h"

namespace brdffit {

namespace {

namespace fs = std::filesystem;

bool is_integer(OIIO::TypeDesc format) {
  return format.basetype == OIIO::TypeDesc::UINT8 || format.basetype == OIIO::TypeDesc::UINT16;
}

// An ImageBuf that reads and writes the pixels of a continuous CV_32FC3 matrix in place.
OIIO::ImageBuf wrap(cv::Mat& rgb) {
  if (rgb.type() != CV_32FC3 || !rgb.isContinuous()) fail("internal: images are continuous CV_32FC3 matrices");
  return OIIO::ImageBuf(OIIO::ImageSpec(rgb.cols, rgb.rows, 3, OIIO::TypeDesc::FLOAT), rgb.ptr<float>());
}

void convert_colours(cv::Mat& rgb, const char* from, const char* to) {
  OIIO::ImageBuf buf = wrap(rgb);
  if (!OIIO::ImageBufAlgo::colorconvert(buf, buf, from, to))
    fail("cannot convert colours from {} to {}: {}", from, to, buf.geterror());
}

// Opens an image file directly (not through OpenImageIO's shared cache, which could serve a
// file's old contents after it is rewritten).
std::unique_ptr<OIIO::ImageInput> open_image(const std::string& path) {
  std::error_code error;
  if (!fs::exists(path, error)) fail("{}: no such file", path);
  if (fs::is_directory(path, error)) fail("{}: is a folder, not an image", path);
  check_input_file(path, UINT64_MAX);  // a FIFO or a device would block or never end
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path);
  if (!in) fail("{}: cannot read image: {}", path, OIIO::geterror());
  return in;
}

}  // namespace

Decoding parse_gamma(const std::string& text) {
  if (text == "srgb" || text == "sRGB") return {Transfer::Srgb, 0.0};
  double gamma = 0.0;
  size_t used = 0;
  try {
    gamma = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !(gamma > 0.0) || !std::isfinite(gamma))
    fail("--gamma: expected a positive number or 'srgb', got '{}'", text);
  return {Transfer::Gamma, gamma};
}

ImageInfo read_image_info(const std::string& path) {
  const std::unique_ptr<OIIO::ImageInput> in = open_image(path);
  const OIIO::ImageSpec& spec = in->spec();
  ImageInfo info;
  info.width = spec.width;
  info.height = spec.height;
  info.channels = spec.nchannels;
  info.integer_codes = is_integer(spec.format);
  info.bits = static_cast<int>(spec.format.size() * 8);
  info.exposure_time = spec.get_float_attribute("ExposureTime", 0.0f);
  return info;
}

namespace {
std::atomic<uint64_t> max_image_pixels{kDefaultMaxImagePixels};
}

void set_max_image_pixels(uint64_t pixels) { max_image_pixels = pixels; }

uint64_t get_max_image_pixels() { return max_image_pixels; }

uint64_t max_image_bytes() {
  const uint64_t per_pixel = kMaxBudgetChannels * sizeof(float), pixels = max_image_pixels;
  return pixels > UINT64_MAX / per_pixel ? UINT64_MAX : pixels * per_pixel;
}

cv::Mat read_image(const std::string& path, const Decoding& decoding) {
  const std::unique_ptr<OIIO::ImageInput> in = open_image(path);
  const OIIO::ImageSpec& spec = in->spec();
  const int channels = spec.nchannels;
  // Checked on the header, before the pixels are allocated: the pixels, and the bytes they
  // decode to (a float per channel), so that 64 channels cannot ask for 16 times the memory.
  const uint64_t pixels =
      static_cast<uint64_t>(std::max(spec.width, 0)) * static_cast<uint64_t>(std::max(spec.height, 0));
  if (pixels > max_image_pixels)
    fail("{}: {}x{} pixels, more than the limit of {} pixels (raise it with --max-pixels)", path, spec.width,
         spec.height, max_image_pixels.load());
  if (spec.depth > 1 || channels < 1 || channels > 64) fail("{}: not a 2D image with 1 to 64 channels", path);
  const uint64_t bytes = pixels * static_cast<uint64_t>(channels) * sizeof(float);
  if (bytes > max_image_bytes())
    fail(
        "{}: {}x{} pixels of {} channels decode to {} bytes, more than the limit of {} bytes ({} pixels of {} "
        "channels; raise it with --max-pixels)",
        path, spec.width, spec.height, channels, bytes, max_image_bytes(), max_image_pixels.load(), kMaxBudgetChannels);
  OIIO::ImageBuf file(OIIO::ImageSpec(spec.width, spec.height, channels, OIIO::TypeDesc::FLOAT));
  if (!file.localpixels()) fail("{}: cannot allocate {} bytes for the pixels", path, bytes);
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, file.localpixels()))
    fail("{}: cannot read image: {}", path, in->geterror());
  // Grey (with or without alpha) is spread over R, G, B; alpha and further channels are dropped.
  const int order[3] = {0, channels >= 3 ? 1 : 0, channels >= 3 ? 2 : 0};
  OIIO::ImageBuf rgb = OIIO::ImageBufAlgo::channels(file, 3, order);

  Transfer transfer = decoding.transfer;
  if (transfer == Transfer::Auto)
    transfer = spec.format.basetype == OIIO::TypeDesc::UINT8 ? Transfer::Srgb : Transfer::Linear;
  if (transfer == Transfer::Srgb) rgb = OIIO::ImageBufAlgo::colorconvert(rgb, "sRGB", "linear");
  if (transfer == Transfer::Gamma) {
    // Negative stored values (possible in float files) have no power; they are black.
    rgb = OIIO::ImageBufAlgo::max(rgb, 0.0f);
    rgb = OIIO::ImageBufAlgo::pow(rgb, static_cast<float>(decoding.gamma));
  }
  if (rgb.has_error()) fail("{}: cannot decode image: {}", path, rgb.geterror());

  const OIIO::ROI roi = rgb.roi();
  cv::Mat out(roi.height(), roi.width(), CV_32FC3);
  if (!rgb.get_pixels(roi, OIIO::TypeDesc::FLOAT, out.ptr<float>()))
    fail("{}: cannot read image: {}", path, rgb.geterror());
  if (!cv::checkRange(out)) fail("{}: has NaN or infinite pixel values", path);
  return out;
}

bool stores_linear_values(const std::string& path) {
  std::string extension = fs::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".exr" || extension == ".hdr";
}

void write_image(const std::string& path, const cv::Mat& rgb, Encoding encoding) {
  if (rgb.type() != CV_32FC3) fail("{}: internal: images to write are CV_32FC3", path);
  const fs::path target(path);
  if (encoding == Encoding::Auto) encoding = stores_linear_values(path) ? Encoding::Float : Encoding::Srgb8;

  cv::Mat pixels = rgb.clone();
  if (encoding != Encoding::Float) pixels = cv::min(cv::max(pixels, 0.0), 1.0);
  if (encoding == Encoding::Srgb8) linear_to_srgb(pixels);
  OIIO::ImageBuf buf = wrap(pixels);
  buf.specmod().attribute("oiio:ColorSpace", encoding == Encoding::Srgb8 ? "sRGB" : "Linear");
  const OIIO::TypeDesc stored = encoding == Encoding::Srgb8      ? OIIO::TypeDesc::UINT8
                                : encoding == Encoding::Linear16 ? OIIO::TypeDesc::UINT16
                                                                 : OIIO::TypeDesc::FLOAT;

  // The temporary name keeps the extension, which tells OpenImageIO the format.
  replace_file_atomic(path, target.extension().string(), [&](const std::string& temporary) {
    return buf.write(temporary, stored) ? std::string() : buf.geterror();
  });
}

void srgb_to_linear(cv::Mat& rgb) { convert_colours(rgb, "sRGB", "linear"); }
void linear_to_srgb(cv::Mat& rgb) { convert_colours(rgb, "linear", "sRGB"); }

cv::Mat heatmap(const cv::Mat& magnitude, double full_scale) {
  cv::Mat codes, bgr, rgb;
  magnitude.convertTo(codes, CV_8U, 255.0 / full_scale);  // saturates at full scale
  cv::applyColorMap(codes, bgr, cv::COLORMAP_INFERNO);
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  rgb.convertTo(rgb, CV_32FC3, 1.0 / 255.0);
  srgb_to_linear(rgb);  // the map's colours are display colours
  return rgb;
}

}  // namespace brdffit
