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
  const std::string path = std::filesystem::temp_directory_path() / ("published-" + std::to_string(::getpid()) + ".fit");
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

TEST(PublishedFits, NganFitsOfTheSharedMaterialsMapInsideOurBounds) {
  const std::string dir = std::string(BRDFFIT_SHARED_DIR) + "/reference/published-fits";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << "../shared/reference/published-fits is absent";
  const std::vector<std::pair<const char*, const char*>> files = {{"cook-torrance", "ngan_cooktorrance.fit"},
                                                                  {"ward", "ngan_ward.fit"},
                                                                  {"ashikhmin-shirley", "ngan_ashikhminshirley.fit"},
                                                                  {"lafortune", "ngan_lafortune.fit"}};
  for (const auto& [name, file] : files) {
    const Model& model = *find_model(name);
    const auto fits = read_published_fits(dir + "/" + file);
    EXPECT_GT(fits.size(), 80u) << file;  // Ngan fitted the whole MERL database
    for (const char* material : {"gold-metallic-paint", "blue-acrylic", "red-fabric"}) {
      SCOPED_TRACE(std::string(file) + " " + material);
      const auto values = to_model_values(model, fits.at(material));
      ASSERT_TRUE(values.has_value());
      int offset = 0;
      for (const ParamSpec& p : model.parameters())
        for (int c = 0; c < p.channels; ++c, ++offset) {
          EXPECT_GE((*values)[offset], p.lower) << p.name;
          EXPECT_LE((*values)[offset], p.upper) << p.name;
        }
      // The published BRDF is finite and positive at a few directions.
      for (const Vec3& l : {Vec3(0, 0, 1), Vec3(0.6, 0, 0.8)}) {
        const Rgb<double> f = *model.brdf(values->data(), l, Vec3(-0.6, 0, 0.8));
        EXPECT_TRUE(f.allFinite());
        EXPECT_GT(f.minCoeff(), 0.0);
      }
    }
  }
}

}  // namespace
}  // namespace brdffit
