#include "brdffit/imaging/capture.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>
#include <opencv2/videoio.hpp>
#include <regex>

#include "brdffit/error.h"
#include "brdffit/imaging/image_io.h"
#include "brdffit/io.h"

namespace brdffit {

namespace {

bool is_camera_index(const std::string& source) {
  return !source.empty() && std::all_of(source.begin(), source.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// shot_%02d.png: prefix, zero flag, width, suffix.
const std::regex& sequence_pattern() {
  static const std::regex pattern(R"(([^%]*)%(0?)([0-9]{0,3})d([^%]*))");
  return pattern;
}

bool is_sequence(const std::string& source) { return std::regex_match(source, sequence_pattern()); }

// Where frames come from: a camera or a video file through OpenCV, an image sequence as the
// files capture_input_files lists, read in that order. The pattern is expanded once, so the
// frames read are exactly the files checked against the outputs.
class FrameSource {
 public:
  explicit FrameSource(const std::string& source) : camera_(is_camera_index(source)) {
    if (camera_) {
      video_.open(std::stoi(source));
    } else if (is_sequence(source)) {
      files_ = capture_input_files(source);
      if (files_.empty()) fail("{}: no frame of this image sequence exists (numbered from 0 or 1)", source);
      return;
    } else {
      video_.open(source);
    }
    if (!video_.isOpened())
      fail(
          "{}: cannot open: not a camera index, a video file or an image sequence (e.g. shot_%02d.png) OpenCV can "
          "read",
          source);
  }

  bool camera() const { return camera_; }
  void set_exposure(double seconds) { video_.set(cv::CAP_PROP_EXPOSURE, seconds); }

  bool read(cv::Mat& frame) {
    if (!files_.empty()) {
      if (next_ >= files_.size()) return false;
      check_input_file(files_[next_]);
      frame = cv::imread(files_[next_++], cv::IMREAD_COLOR);
      return !frame.empty();
    }
    return video_.read(frame);
  }

 private:
  bool camera_;
  cv::VideoCapture video_;
  std::vector<std::string> files_;
  size_t next_ = 0;
};

// The mean of the next `count` frames (8-bit BGR), as float codes 0..255.
cv::Mat mean_of_frames(FrameSource& video, int count, const std::string& source, int& frames_read) {
  cv::Mat sum, frame;
  for (int k = 0; k < count; ++k) {
    if (!video.read(frame) || frame.empty())
      fail("{}: ran out of frames after {} (the exposures and --frames ask for more)", source, frames_read);
    if (frame.type() != CV_8UC3) fail("{}: frame {} is not 8-bit colour", source, frames_read + 1);
    if (!sum.empty() && frame.size() != sum.size())
      fail("{}: frame {} is {}x{} pixels, earlier frames {}x{}", source, frames_read + 1, frame.cols, frame.rows,
           sum.cols, sum.rows);
    ++frames_read;
    if (sum.empty()) sum = cv::Mat::zeros(frame.size(), CV_32FC3);
    cv::accumulate(frame, sum);
  }
  return sum / count;
}

cv::Mat bgr_to_rgb(const cv::Mat& bgr) {
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  return rgb;
}

}  // namespace

void check_exposure_times(const std::vector<double>& exposures) {
  for (double t : exposures)
    if (!(t > 0.0))
      fail("--exposures: exposure times must be positive, not {}", t);
    else if (!(std::isfinite(t) && t >= kMinExposure && t <= kMaxExposure))
      fail("--exposures: exposure time {} is not between {:g} and {:g} seconds", t, kMinExposure, kMaxExposure);
  std::vector<double> sorted = exposures;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
    fail("--exposures: exposure time {} is given twice: merging needs a different time per group of frames",
         *std::adjacent_find(sorted.begin(), sorted.end()));
}

std::vector<std::string> capture_input_files(const std::string& source) {
  std::vector<std::string> files;
  if (source.empty() || is_camera_index(source)) return files;
  if (source.find('%') == std::string::npos) return {source};
  // An image sequence: the frames a "%0Nd" pattern names, numbered from 0 or 1. The pattern is
  // expanded here, as printf would, never handed to printf (nor to OpenCV: FrameSource reads
  // these files).
  std::smatch parts;
  if (!std::regex_match(source, parts, sequence_pattern())) return {source};
  const bool zero_padded = parts[2].length() > 0;
  const size_t width = parts[3].length() > 0 ? std::min<size_t>(std::stoul(parts[3].str()), 32) : 0;
  for (int i = 0; i < 100000; ++i) {
    std::string number = std::to_string(i);
    if (number.size() < width) number.insert(0, width - number.size(), zero_padded ? '0' : ' ');
    const std::string name = parts[1].str() + number + parts[4].str();
    std::error_code error;
    if (std::filesystem::exists(name, error))
      files.push_back(name);
    else if (i > 1)
      break;
  }
  return files;
}

CaptureResult capture(const CaptureOptions& options) {
  if (options.frames_per_exposure < 1) fail("--frames: at least one frame per exposure");
  check_exposure_times(options.exposures);
  FrameSource video(options.source);
  const bool camera = video.camera();
  CaptureResult result;

  if (options.exposures.size() <= 1) {
    if (camera && options.exposures.size() == 1) video.set_exposure(options.exposures[0]);
    result.image =
        bgr_to_rgb(mean_of_frames(video, options.frames_per_exposure, options.source, result.frames) / 255.0);
    srgb_to_linear(result.image);
    return result;
  }

  std::vector<cv::Mat> exposures;
  std::vector<float> times;
  for (double t : options.exposures) {
    if (camera) {
      video.set_exposure(t);
      cv::Mat settling;
      video.read(settling);  // the frame in flight still has the previous exposure
    }
    cv::Mat codes;
    mean_of_frames(video, options.frames_per_exposure, options.source, result.frames).convertTo(codes, CV_8UC3);
    exposures.push_back(codes);
    times.push_back(static_cast<float>(t));
  }
  cv::Mat response, radiance;
  cv::createCalibrateDebevec()->process(exposures, response, times);
  cv::createMergeDebevec()->process(exposures, radiance, times, response);
  result.image = bgr_to_rgb(radiance);
  result.response = bgr_to_rgb(response);
  if (!cv::checkRange(result.image)) fail("{}: the merged image has NaN or infinite values", options.source);
  return result;
}

}  // namespace brdffit
