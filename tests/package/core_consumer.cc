// Uses brdffit::core alone: Lambert with albedo 0.5 lit and seen along the normal shades
// 0.5/π·cos0 = 0.1591549 in every channel.
#include <cmath>
#include <cstdio>

#include "brdffit/model.h"
#include "brdffit/registry.h"

int main() {
  const brdffit::Model* lambert = brdffit::find_model("lambert");
  if (!lambert) return 1;
  const double albedo[] = {0.5, 0.5, 0.5};
  const brdffit::Vec3 normal(0, 0, 1);
  const brdffit::Rgb<double> shade = lambert->shade(albedo, normal, normal);
  std::printf("lambert shade %.7f\n", shade[0]);
  return std::abs(shade[0] - 0.5 / M_PI) < 1e-12 ? 0 : 1;
}
