// Uses brdffit::imaging: the sphere of a 64-pixel picture has a radius of 31 pixels (a pixel's
// margin), so its mask covers about π·31² = 3019 pixels.
#include <cstdio>

#include <opencv2/core.hpp>

#include "brdffit/imaging/render.h"

int main() {
  const int covered = cv::countNonZero(brdffit::sphere_mask(64));
  std::printf("sphere mask %d pixels\n", covered);
  return covered > 2990 && covered < 3050 ? 0 : 1;
}
