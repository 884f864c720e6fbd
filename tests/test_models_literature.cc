// Values derived by hand from each literature model's formula (the derivation is in the comment
// above each expectation). Lambert and GGX are in test_models.cc, the other seed models in
// test_models_seed.cc.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/model.h"
#include "brdffit/published_fits.h"
#include "brdffit/registry.h"
#include "test_util.h"

namespace brdffit {
namespace {

using test::dir;

using test::kNormal;
using test::shade1;

const double kSqrtHalf = std::sqrt(0.5);
const Vec3 k45X = dir(1, 0, 1);    // 45° towards +x
const Vec3 k45mX = dir(-1, 0, 1);  // 45° towards -x: the mirror of k45X

TEST(CookTorrance, HandValues) {
  // l = v = n: h = n, D = 1/(π m²), G = min(1, 2, 2) = 1, F = f0 at l·h = 1:
  // f = albedo/π + specular·f0/(π m²)/π.
  EXPECT_NEAR(shade1("cook-torrance", {"albedo=0.1", "specular=0.5", "f0=0.04", "m=0.2"}, kNormal, kNormal),
              0.1 / kPi + 0.5 * 0.04 / (kPi * 0.04) / kPi, 1e-12);
  // Mirror pair at 45°: h = n, D = 1/(π m²), l·h = cos45, G = min(1, 2·1·cos45/cos45) = 1,
  // F = f0 + (1-f0)(1-cos45)^5; f_spec = D·F/(π·0.5); shade = f·cos45.
  {
    const double m = 0.3, f0 = 0.1, d = 1 / (kPi * m * m), f = f0 + (1 - f0) * std::pow(1 - kSqrtHalf, 5);
    EXPECT_NEAR(shade1("cook-torrance", {"albedo=0", "specular=1", "f0=0.1", "m=0.3"}, k45X, k45mX),
                d * f / (kPi * 0.5) * kSqrtHalf, 1e-12);
  }
  // l = n, v 60° away: h at 30°, n·h = cos30, l·h = cos30; G = min(1, 2cos30·1/cos30, 2cos30·0.5/cos30) = 1;
  // m = 1: D = e^(-1/3)/(π·9/16); F = 1 when f0 = 1: f_spec = D/(π·1·0.5).
  EXPECT_NEAR(shade1("cook-torrance", {"albedo=0", "specular=1", "f0=1", "m=1"}, kNormal, dir(std::sqrt(3), 0, 1)),
              std::exp(-1.0 / 3) / (kPi * 9.0 / 16) / (kPi * 0.5), 1e-12);
}

TEST(Ward, HandValues) {
  // l = v = n: tanθh = 0, f = albedo/π + specular/(4π α²).
  EXPECT_NEAR(shade1("ward", {"albedo=0.2", "specular=0.1", "alpha=0.5"}, kNormal, kNormal),
              0.2 / kPi + 0.1 / (4 * kPi * 0.25), 1e-12);
  // Mirror pair at 45°: θh = 0, √(n·l n·v) = 0.5·... = cos45: f_spec = s/(4πα²·cos45); shade·cos45.
  EXPECT_NEAR(shade1("ward", {"albedo=0", "specular=1", "alpha=0.2"}, k45X, k45mX), 1 / (4 * kPi * 0.04), 1e-12);
  // l = n, v 60° away: tan²θh = 1/3; α = 1: e^(-1/3)/(4π·√0.5).
  EXPECT_NEAR(shade1("ward", {"albedo=0", "specular=1", "alpha=1"}, kNormal, dir(std::sqrt(3), 0, 1)),
              std::exp(-1.0 / 3) / (4 * kPi * std::sqrt(0.5)), 1e-12);
}

TEST(AshikhminShirley, HandValues) {
  // l = v = n: n·h = 1, l·h = 1, F = f0, max(n·l,n·v) = 1: f_spec = (n+1)/(8π)·f0.
  EXPECT_NEAR(shade1("ashikhmin-shirley", {"albedo=0.3", "specular=1", "f0=0.05", "n=100"}, kNormal, kNormal),
              0.3 / kPi + 101 / (8 * kPi) * 0.05, 1e-12);
  // Mirror pair at 45°: n·h = 1, l·h = cos45, max = cos45: f_spec = (n+1)/(8π)·F/(0.5); shade·cos45.
  {
    const double f = 0.2 + 0.8 * std::pow(1 - kSqrtHalf, 5);
    EXPECT_NEAR(shade1("ashikhmin-shirley", {"albedo=0", "specular=1", "f0=0.2", "n=10"}, k45X, k45mX),
                11 / (8 * kPi) * f / 0.5 * kSqrtHalf, 1e-12);
  }
  // l = n, v 60° away: n·h = l·h = cos30, max(1, 0.5) = 1, f0 = 1: (n+1)/(8π)·cos30^n/cos30.
  {
    const double c = std::cos(kPi / 6);
    EXPECT_NEAR(
        shade1("ashikhmin-shirley", {"albedo=0", "specular=1", "f0=1", "n=4"}, kNormal, dir(std::sqrt(3), 0, 1)),
        5 / (8 * kPi) * std::pow(c, 4) / c, 1e-12);
  }
}

TEST(Lafortune, HandValues) {
  // Mirror pair at 45°, cxy = -cz = -0.5: dot = -0.5·(-0.5) + 0.5·0.5 = 0.5, c = 0.5 → (1)^n:
  // f_spec = (n+2)/(2π); shade = f·cos45.
  EXPECT_NEAR(shade1("lafortune", {"albedo=0", "specular=1", "cxy=-0.5", "cz=0.5", "n=20"}, k45X, k45mX),
              22 / (2 * kPi) * kSqrtHalf, 1e-12);
  // l = v = n: dot = cz, c = max(0.3, 0.6) = 0.6 → 1^n; plus albedo/π.
  EXPECT_NEAR(shade1("lafortune", {"albedo=0.3", "specular=0.5", "cxy=-0.3", "cz=0.6", "n=3"}, kNormal, kNormal),
              0.3 / kPi + 0.5 * 5 / (2 * kPi), 1e-12);
  // l = n, v 60° away: lx vx + ly vy = 0, lz vz = 0.5; cz = 1: (0.5)^2 with n = 2 → 4/(2π)·0.25.
  EXPECT_NEAR(
      shade1("lafortune", {"albedo=0", "specular=1", "cxy=-1", "cz=1", "n=2"}, kNormal, dir(std::sqrt(3), 0, 1)),
      4 / (2 * kPi) * 0.25, 1e-12);
}

TEST(Lafortune, HandValuesAtTheEdgesOfNgansFits) {
  // Ngan's fits reach cz ≈ 0 (ngan_lafortune.fit). Mirror pair at 45°, cxy = -0.5, cz = 0:
  // dot = -0.5·(0.7071·(-0.7071)) = 0.25, c = 0.5 → (0.5)^n; n = 2: f_spec = 4/(2π)·0.25; shade·cos45.
  EXPECT_NEAR(shade1("lafortune", {"albedo=0", "specular=1", "cxy=-0.5", "cz=0", "n=2"}, k45X, k45mX),
              4 / (2 * kPi) * 0.25 * kSqrtHalf, 1e-12);
  // cxy = cz = 0: the lobe has no axis and is 0; only albedo/π·cos45 remains.
  EXPECT_NEAR(shade1("lafortune", {"albedo=0.4", "specular=1", "cxy=0", "cz=0", "n=2"}, k45X, k45mX),
              0.4 / kPi * kSqrtHalf, 1e-15);
  // Ngan's largest published lobe scale (1.71) is inside the bounds: l = v = n, cz = 1, n = 1:
  // dot = 1, f_spec = 1.71·3/(2π).
  EXPECT_NEAR(shade1("lafortune", {"albedo=0", "specular=1.71", "cxy=-1", "cz=1", "n=1"}, kNormal, kNormal),
              1.71 * 3 / (2 * kPi), 1e-12);
}

// --- published fits in the BBM .fit format, mapped onto these models ----------------------

// A .fit file in the temporary directory, removed when the test ends.
struct TempFitFile {
  std::string path;
  TempFitFile(const std::string& tag, const std::string& text)
      : path(std::filesystem::temp_directory_path() /
             ("brdffit-literature-" + tag + "-" + std::to_string(::getpid()) + ".fit")) {
    write_file_atomic(path, text);
  }
  ~TempFitFile() { std::filesystem::remove(path); }
};

TEST(PublishedFits, ParsesTheBbmFormatAndMapsNgansTermsOneToOne) {
  const TempFitFile file(
      "parse",
      "# BSDF fits in BBM's syntax\n"
      "\n"
      "ct = Aggregate(Lambertian(albedo = [0.1, 0.2, 0.3]), NganCookTorrance(albedo = [0.5, 0.25, 0.125], "
      "eta = 0.117, roughness = 1.37e-2))\n"
      "  ward=Aggregate( Lambertian( albedo=[0.0138,0.0326,0.0636] ) ,NganWard(albedo = [0.00774, 0.00547, "
      "0.00339], roughness = 0.0162) )\r\n"
      "duer = Aggregate(Lambertian(albedo = [0.1, 0.1, 0.1]), NganWardDuer(albedo = [0.005, 0.004, 0.002], "
      "roughness = 0.0162))\n"
      "as = NganAshikhminShirley(albedo = [0.2, 0.1, 0.05], fresnelReflectance = 0.999, sharpness = 25.4)\n"
      "laf = Aggregate(Lambertian(albedo = [0.06, 0.03, 0.005]), NganLafortune(albedo = [1.71, 0.782, 0.525], "
      "Cxy = -0.596, Cz = 5.09e-08, sharpness = 12.8))\n"
      "two-lobes = Aggregate(Lambertian(albedo = [0.1, 0.1, 0.1]), NganLafortune(albedo = 0.1, Cxy = -0.6, Cz = "
      "0.5, sharpness = 10), NganLafortune(albedo = 0.2, Cxy = 0.3, Cz = 0.2, sharpness = 3))\n"
      "sgd = Aggregate(Lambertian(albedo = [0.1, 0.1, 0.1]), Bagher(eta = [[6.05, 0.23, 0.58], [5.05, 0.18, "
      "0.4]], K = 3.46))\n");
  const auto fits = read_published_fits(file.path);
  ASSERT_EQ(fits.size(), 7u);
  // Nested lists (Bagher's complex eta) are read flattened.
  EXPECT_EQ(fits.at("sgd")[1].parameters.at("eta"), (std::vector<double>{6.05, 0.23, 0.58, 5.05, 0.18, 0.4}));
  const std::vector<PublishedTerm>& ct_terms = fits.at("ct");
  ASSERT_EQ(ct_terms.size(), 2u);  // Aggregate is flattened into its terms
  EXPECT_EQ(ct_terms[0].model, "Lambertian");
  EXPECT_EQ(ct_terms[0].parameters.at("albedo"), (std::vector<double>{0.1, 0.2, 0.3}));
  EXPECT_EQ(ct_terms[1].model, "NganCookTorrance");
  EXPECT_EQ(ct_terms[1].parameters.at("roughness"), (std::vector<double>{0.0137}));

  const Model& ct = *find_model("cook-torrance");
  const Model& ward = *find_model("ward");
  const Model& as = *find_model("ashikhmin-shirley");
  const Model& laf = *find_model("lafortune");
  // Lambertian albedo → albedo; the lobe's albedo → specular; the rest by the table in published_fits.h.
  const auto ct_fit = find_published_fit(file.path, "ct", ct);
  ASSERT_TRUE(ct_fit.has_value());
  EXPECT_EQ(ct_fit->material, "ct");
  EXPECT_EQ(ct_fit->model, "cook-torrance");
  EXPECT_EQ(ct_fit->term, "NganCookTorrance");
  EXPECT_EQ(ct_fit->values, (std::vector<double>{0.1, 0.2, 0.3, 0.5, 0.25, 0.125, 0.117, 0.0137}));
  const auto ward_fit = find_published_fit(file.path, "ward", ward);
  ASSERT_TRUE(ward_fit.has_value());
  EXPECT_EQ(ward_fit->values, (std::vector<double>{0.0138, 0.0326, 0.0636, 0.00774, 0.00547, 0.00339, 0.0162}));
  // No Lambertian term: albedo 0.
  const auto as_fit = find_published_fit(file.path, "as", as);
  ASSERT_TRUE(as_fit.has_value());
  EXPECT_EQ(as_fit->values, (std::vector<double>{0, 0, 0, 0.2, 0.1, 0.05, 0.999, 25.4}));
  const auto laf_fit = find_published_fit(file.path, "laf", laf);
  ASSERT_TRUE(laf_fit.has_value());
  EXPECT_EQ(laf_fit->values, (std::vector<double>{0.06, 0.03, 0.005, 1.71, 0.782, 0.525, -0.596, 5.09e-08, 12.8}));

  // Not mappable: Ward-Duer is another lobe than our (original) Ward; two Lafortune lobes are more
  // than our one; a Cook-Torrance fit is not a Ward one; an absent material.
  EXPECT_FALSE(find_published_fit(file.path, "duer", ward).has_value());
  EXPECT_FALSE(find_published_fit(file.path, "two-lobes", laf).has_value());
  EXPECT_FALSE(find_published_fit(file.path, "ct", ward).has_value());
  EXPECT_FALSE(find_published_fit(file.path, "no-such-material", ct).has_value());
  EXPECT_FALSE(find_published_fit(file.path, "ct", *find_model("ggx")).has_value());

  // The mapped values give BBM's BRDF. Cook-Torrance at l = v = n: D = 1/(π m²), G = 1, F = eta,
  // f = albedo/π + albedo_s·eta/(π m²)/π per channel.
  const Rgb<double> f_ct = *ct.brdf(ct_fit->values.data(), kNormal, kNormal);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(f_ct[c], (0.1 * (c + 1)) / kPi + (0.5 / (1 << c)) * 0.117 / (kPi * 0.0137 * 0.0137) / kPi,
                1e-12 * f_ct[c]);
  // Ward at l = v = n: tanθh = 0, √(n·l n·v) = 1: f = albedo/π + albedo_s/(4π α²).
  const Rgb<double> f_ward = *ward.brdf(ward_fit->values.data(), kNormal, kNormal);
  EXPECT_NEAR(f_ward[0], 0.0138 / kPi + 0.00774 / (4 * kPi * 0.0162 * 0.0162), 1e-12 * f_ward[0]);
}

TEST(PublishedFits, MalformedFilesNameTheFileAndLine) {
  const std::vector<std::pair<std::string, std::string>> malformed = {
      {"m1 Aggregate(Lambertian(albedo = 1))\n", ":1:"},                       // no '='
      {"# ok\nm1 = Aggregate(Lambertian(albedo = [0.1, 0.2, 0.3])\n", ":2:"},  // unbalanced
      {"m1 = Aggregate(Lambertian(albedo = [0.1, x, 0.3]))\n", ":1:"},         // not a number
      {"m1 = Aggregate(Lambertian(albedo = 0.1abc))\n", ":1:"},                // trailing characters
      {"m1 = Aggregate(Lambertian(albedo = []))\n", ":1:"},                    // empty list
      {"m1 = Bagher(eta = [[1, 2], [3, 4])\n", ":1:"},                         // unclosed list
      {"m1 = Bagher(eta = " + std::string(100, '[') + "1" + std::string(100, ']') + ")\n", ":1:"},  // too deep
      {"m1 = Lambertian(albedo = 1e999)\n", ":1:"},                                                 // not finite
      {"m1 = Lambertian(albedo 0.5)\n", ":1:"},                                 // no '=' in the term
      {"m1 = Lambertian(albedo = 1, albedo = 2)\n", ":1:"},                     // parameter twice
      {"m1 = Lambertian(albedo = 1)\n\nm1 = Lambertian(albedo = 1)\n", ":3:"},  // material twice
      {"m1 = 42\n", ":1:"},                                                     // no term
      {"m1 = Aggregate()\n", ":1:"},                                            // no term
      {"m1 = Aggregate(albedo = 1)\n", ":1:"},                                  // Aggregate of a value
      {"m1 = Lambertian(NganWard(albedo = 1))\n", ":1:"},                       // term inside a term
      {"m1 = Lambertian(albedo = 1)) extra\n", ":1:"},                          // after the model
      {" = Lambertian(albedo = 1)\n", ":1:"},                                   // no material
  };
  for (const auto& [text, where] : malformed) {
    SCOPED_TRACE(text);
    const TempFitFile file("malformed", text);
    try {
      read_published_fits(file.path);
      ADD_FAILURE() << "expected an Error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(file.path + where), std::string::npos) << e.what();
    }
  }
  const std::string missing = std::filesystem::temp_directory_path() / "brdffit-no-such-file.fit";
  try {
    find_published_fit(missing, "m1", *find_model("ward"));
    ADD_FAILURE() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
}

// Bundled in data/ (BSD-3, data/published-fits/LICENSE.bbm): these checks run on every machine.
std::string published_fits_dir() { return std::string(BRDFFIT_SOURCE_DIR) + "/data/published-fits"; }

// Ngan 2005's file for each of our literature models.
const std::vector<std::pair<const char*, const char*>> kNganFiles = {{"cook-torrance", "ngan_cooktorrance.fit"},
                                                                     {"ward", "ngan_ward.fit"},
                                                                     {"ashikhmin-shirley", "ngan_ashikhminshirley.fit"},
                                                                     {"lafortune", "ngan_lafortune.fit"}};

void expect_inside_bounds(const Model& model, const std::vector<double>& values) {
  ASSERT_EQ(static_cast<int>(values.size()), model.num_values());
  int offset = 0;
  for (const ParamSpec& p : model.parameters())
    for (int c = 0; c < p.channels; ++c, ++offset) {
      EXPECT_TRUE(std::isfinite(values[offset])) << p.name;
      EXPECT_GE(values[offset], p.lower) << p.name;
      EXPECT_LE(values[offset], p.upper) << p.name;
    }
}

TEST(PublishedFits, NganFitsOfTheBenchmarkMaterialsMapToSaneValues) {
  const std::string fits_dir = published_fits_dir();
  ASSERT_TRUE(std::filesystem::exists(fits_dir + "/ngan_ward.fit")) << fits_dir;
  const Vec3 off_specular_l(0, 0, 1), off_specular_v = dir(std::sqrt(3), 0, 1);  // v 60° from l = n
  for (const char* material : {"gold-metallic-paint", "blue-acrylic", "red-fabric"}) {
    SCOPED_TRACE(material);
    std::vector<double> off_specular;  // π·f summed over channels, one per model
    for (const auto& [name, file] : kNganFiles) {
      SCOPED_TRACE(file);
      const Model& model = *find_model(name);
      const auto fit = find_published_fit(fits_dir + "/" + file, material, model);
      ASSERT_TRUE(fit.has_value());
      expect_inside_bounds(model, fit->values);
      // Finite, non-negative BRDF everywhere we look, positive (every fit has a diffuse part), and
      // finite derivatives for the fitter (exponents in the thousands; mirror pairs included).
      std::mt19937_64 rng(23);
      std::vector<double> jacobian(3 * model.num_values());
      for (int i = 0; i < 200; ++i) {
        const Vec3 l = test::random_upper_direction(rng, 0.01);
        const Vec3 v = i % 2 ? test::random_upper_direction(rng, 0.01) : Vec3(-l.x(), -l.y(), l.z());
        const Rgb<double> f = *model.brdf(fit->values.data(), l, v);
        ASSERT_TRUE(f.allFinite()) << l.transpose() << " / " << v.transpose();
        EXPECT_GT(f.minCoeff(), 0.0);
        model.shade_with_jacobian(fit->values.data(), l, v, jacobian.data());
        for (double d : jacobian) ASSERT_TRUE(std::isfinite(d)) << l.transpose() << " / " << v.transpose();
      }
      // Away from the highlight the reflectance π·f is a plausible albedo.
      const Rgb<double> rho = kPi * *model.brdf(fit->values.data(), off_specular_l, off_specular_v);
      EXPECT_LT(rho.maxCoeff(), 1.0);
      off_specular.push_back(rho.sum());
    }
    // The four fits are of one measurement: away from the highlight they agree within a factor 2
    // (a π or a 4/π mix-up in a mapping would not).
    const auto [lo, hi] = std::minmax_element(off_specular.begin(), off_specular.end());
    EXPECT_LT(*hi, 2 * *lo);
  }
}

TEST(PublishedFits, EveryNganFitMapsInsideOurBoundsAndEveryFileParses) {
  const std::string fits_dir = published_fits_dir();
  ASSERT_TRUE(std::filesystem::exists(fits_dir + "/ngan_ward.fit")) << fits_dir;
  for (const auto& [name, file] : kNganFiles) {
    const Model& model = *find_model(name);
    const auto fits = read_published_fits(fits_dir + "/" + file);
    EXPECT_GE(fits.size(), 86u) << file;  // Ngan fitted the MERL database
    for (const auto& [material, terms] : fits) {
      SCOPED_TRACE(std::string(file) + " " + material);
      const auto values = to_model_values(model, terms);
      ASSERT_TRUE(values.has_value());
      expect_inside_bounds(model, *values);
      EXPECT_TRUE(model.brdf(values->data(), dir(1, 0, 2), dir(-1, 0, 2))->allFinite());
    }
  }
  // The reader takes every file BBM publishes, including the models we do not map.
  for (const auto& entry : std::filesystem::directory_iterator(fits_dir))
    if (entry.path().extension() == ".fit") EXPECT_NO_THROW(read_published_fits(entry.path().string())) << entry.path();
  // Ngan's Ward-Duer fits are not fits of our (original) Ward.
  EXPECT_FALSE(
      to_model_values(*find_model("ward"), read_published_fits(fits_dir + "/ngan_wardduer.fit").at("red-fabric"))
          .has_value());
}

}  // namespace
}  // namespace brdffit
