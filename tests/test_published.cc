// The reader of published fits (BBM format) and its mapping onto our models.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/published_fits.h"

namespace brdffit {
namespace {

TEST(PublishedFits, ParsesAndMapsNganTerms) {
  const std::string path =
      std::filesystem::temp_directory_path() / ("published-" + std::to_string(::getpid()) + ".fit");
  write_file_atomic(path,
                    "# comment\n"
                    "m1 = Aggregate(Lambertian(albedo = [0.1, 0.2, 0.3]), NganWard(albedo = [0.01, 0.02, 0.03], "
                    "roughness = 0.25))\n"
                    "m2 = Aggregate(Lambertian(albedo = [0.5, 0.5, 0.5]), NganCookTorrance(albedo = [1, 2, 3], eta = "
                    "0.5, roughness = 1e-2))\n");
  const auto fits = read_published_fits(path);
  ASSERT_EQ(fits.size(), 2u);
  const Model& ward = *find_model("ward");
  const auto values = to_model_values(ward, fits.at("m1"));
  ASSERT_TRUE(values.has_value());
  EXPECT_EQ(*values, (std::vector<double>{0.1, 0.2, 0.3, 0.01, 0.02, 0.03, 0.25}));
  const Model& ct = *find_model("cook-torrance");
  const auto ct_values = to_model_values(ct, fits.at("m2"));
  ASSERT_TRUE(ct_values.has_value());
  EXPECT_EQ((*ct_values)[ct.offset_of("f0")], 0.5);
  EXPECT_EQ((*ct_values)[ct.offset_of("m")], 0.01);
  EXPECT_FALSE(to_model_values(ward, fits.at("m2")).has_value());  // not a Ward fit

  write_file_atomic(path, "m1 Aggregate(Lambertian(albedo = 1))\n");
  try {
    read_published_fits(path);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":1"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace brdffit
