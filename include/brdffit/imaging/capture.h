// Frames from a camera, a video file or an image sequence (cv::VideoCapture), merged into one
// linear image: with several exposures, OpenCV recovers the camera's response (Debevec &
// Malik 1997) and merges the exposures into a high-dynamic-range radiance map.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace brdffit {

struct CaptureOptions {
  // A camera index ("0"), a video file, or an image sequence as a printf pattern ("shot_%02d.png").
  std::string source;
  // Exposure time of each group of consecutive frames, in order; none or one: a single exposure.
  // For a camera each value is also requested through CAP_PROP_EXPOSURE, whose units depend on
  // the driver: the values must be proportional to the exposure times for the merge to be right.
  std::vector<double> exposures;
  int frames_per_exposure = 1;  // consecutive frames averaged for each exposure (less noise)
};

struct CaptureResult {
  cv::Mat image;     // linear RGB, CV_32FC3; relative radiance when merged
  cv::Mat response;  // the recovered response (256x1, CV_32FC3, RGB; linear value per code); empty for one exposure
  int frames = 0;    // frames read
};

// Exposure times brdffit accepts (seconds, or the driver's proportional units).
constexpr double kMinExposure = 1e-9, kMaxExposure = 1e6;

// Throws Error unless every exposure time is finite and within [kMinExposure, kMaxExposure] and
// no time is given twice (identical exposures leave the camera response undetermined).
void check_exposure_times(const std::vector<double>& exposures);

// The files a source reads: a video file itself, an image sequence's existing frames, none for a
// camera. For checking that an output is none of them.
std::vector<std::string> capture_input_files(const std::string& source);

// A single exposure is taken to be sRGB-encoded and decoded. Throws Error naming the source
// when it cannot be opened, runs out of frames or gives frames of different sizes.
CaptureResult capture(const CaptureOptions& options);

}  // namespace brdffit
