// export: the metallic-roughness mapping, and the glTF and Mitsuba files.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "batch_test_util.h"
#include "brdffit/error.h"
#include "brdffit/material_export.h"

namespace brdffit {
namespace {

// The albedo and f0 a glTF material has at normal incidence (see material_export.h).
void gltf_colours(const Rgb<double>& base, double metallic, Rgb<double>& albedo, Rgb<double>& f0) {
  albedo = (1.0 - metallic) * 0.96 * base;
  f0 = (0.04 * (1.0 - metallic) + metallic * base.array()).matrix();
}

TEST(ExportMapping, RecoversEveryGltfMaterial) {
  for (const double metallic : {0.0, 0.3, 0.75, 1.0}) {
    SCOPED_TRACE(metallic);
    const Rgb<double> base(0.8, 0.5, 0.2);  // luminance above 0.04: one match only
    Rgb<double> albedo, f0;
    gltf_colours(base, metallic, albedo, f0);
    const MetallicRoughness mr = metallic_roughness(albedo, f0, 0.35);
    EXPECT_NEAR(mr.metallic, metallic, 1e-9);
    EXPECT_TRUE(mr.base_color.isApprox(base, 1e-9)) << mr.base_color.transpose();
    EXPECT_EQ(mr.roughness, 0.35);  // both square it into α
    EXPECT_TRUE(mr.albedo.isApprox(albedo, 1e-9));
    EXPECT_TRUE(mr.f0.isApprox(f0, 1e-9));
  }
}

TEST(ExportMapping, ADarkDielectricStaysADielectric) {
  // Its colours are also matched by a half-metallic material; the least metallic one is chosen.
  const Rgb<double> base(0.03, 0.02, 0.01);
  Rgb<double> albedo, f0;
  gltf_colours(base, 0.0, albedo, f0);
  const MetallicRoughness mr = metallic_roughness(albedo, f0, 0.5);
  EXPECT_NEAR(mr.metallic, 0.0, 1e-9);
  EXPECT_TRUE(mr.base_color.isApprox(base, 1e-9)) << mr.base_color.transpose();
}

TEST(ExportMapping, ApproximatesWhatGltfCannotHold) {
  // A coloured dielectric f0 has no exact glTF form: a little metal, and the implied colours say so.
  const MetallicRoughness tinted = metallic_roughness({0.4, 0.3, 0.2}, {0.10, 0.05, 0.04}, 0.5);
  EXPECT_GT(tinted.metallic, 0.0);
  EXPECT_LT(tinted.metallic, 0.2);
  EXPECT_NEAR(rec709_luminance(tinted.albedo), rec709_luminance({0.4, 0.3, 0.2}), 1e-9);  // luminance is kept
  // f0 darker than any dielectric's: no root, so a plain dielectric.
  const MetallicRoughness dark = metallic_roughness({0.5, 0.5, 0.5}, {0.0, 0.0, 0.0}, 0.5);
  EXPECT_EQ(dark.metallic, 0.0);
  EXPECT_NEAR(dark.base_color[0], 0.5 / 0.96, 1e-9);
  // Out-of-range values are clamped into glTF's.
  EXPECT_LE(metallic_roughness({1.0, 1.0, 1.0}, {0.04, 0.04, 0.04}, 1.0).base_color.maxCoeff(), 1.0);
}

FitResult ggx_fit(const std::vector<std::string>& assignments) {
  FitResult fit = test::known_result("ggx", 0.0123);
  fit.values = parameter_values(*find_model("ggx"), assignments);
  return fit;
}

TEST(ExportCli, WritesGltfAndMitsuba) {
  const std::string dir = test::fresh_dir("export-cli");
  // A metal: base colour (0.9, 0.6, 0.3), metallic 1.
  const std::string doc = test::write_document(
      dir + "/gold.json", "/data/gold.binary",
      {test::known_result("lambert", 0.2), ggx_fit({"albedo=0", "roughness=0.3", "f0=0.9,0.6,0.3"})});

  const auto gltf = test::run_cli("export " + doc + " --format gltf --out " + dir + "/gold.gltf");
  ASSERT_EQ(gltf.exit_code, 0) << gltf.output;
  const nlohmann::json g = nlohmann::json::parse(read_file(dir + "/gold.gltf"));
  EXPECT_EQ(g["asset"]["version"], "2.0");
  ASSERT_EQ(g["materials"].size(), 1u);
  const nlohmann::json& material = g["materials"][0];
  EXPECT_EQ(material["name"], "gold");
  const nlohmann::json& pbr = material["pbrMetallicRoughness"];
  EXPECT_NEAR(pbr["metallicFactor"].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(pbr["roughnessFactor"].get<double>(), 0.3, 1e-12);
  const std::vector<double> base = pbr["baseColorFactor"].get<std::vector<double>>();
  ASSERT_EQ(base.size(), 4u);
  EXPECT_NEAR(base[0], 0.9, 1e-9);
  EXPECT_NEAR(base[2], 0.3, 1e-9);
  EXPECT_EQ(base[3], 1.0);
  EXPECT_NEAR(material["extras"]["brdffit"]["metrics"]["cosine"].get<double>(), 0.0123, 1e-12);

  // The format follows the extension when not given.
  const auto xml = test::run_cli("export " + doc + " --out " + dir + "/gold.xml");
  ASSERT_EQ(xml.exit_code, 0) << xml.output;
  const std::string text = read_file(dir + "/gold.xml");
  EXPECT_EQ(text.rfind("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n", 0), 0u);
  EXPECT_NE(text.find("<scene version=\"3.0.0\">"), std::string::npos) << text;
  EXPECT_NE(text.find("<bsdf type=\"principled\" id=\"gold\">"), std::string::npos) << text;
  EXPECT_NE(text.find("<rgb name=\"base_color\" value=\"0.900000, 0.600000, 0.300000\"/>"), std::string::npos) << text;
  EXPECT_NE(text.find("<float name=\"metallic\" value=\"1.000000\"/>"), std::string::npos) << text;
  EXPECT_NE(text.find("<float name=\"roughness\" value=\"0.300000\"/>"), std::string::npos) << text;
  EXPECT_NE(text.find("<float name=\"specular\" value=\"0.5\"/>"), std::string::npos) << text;
  EXPECT_NE(text.find("</bsdf>\n</scene>\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("--", text.find("<!--") + 4), text.find("-->"));  // a well-formed comment

  const std::string no_ggx = test::write_document(dir + "/plain.json", "/data/plain.binary", {test::known_result("lambert", 0.2)});
  FitResult failed = ggx_fit({"roughness=0.3"});
  failed.ok = false;
  failed.error = "diverged";
  const std::string failed_ggx = test::write_document(dir + "/failed.json", "/data/failed.binary", {failed});
  test::expect_cli_errors(
      {
          {"export " + no_ggx + " --out " + dir + "/x.gltf", "plain.json: has no ggx fit"},
          {"export " + failed_ggx + " --out " + dir + "/x.gltf", "failed.json: the ggx fit failed (diverged)"},
          {"export " + doc + " --model ward --out " + dir + "/x.gltf", "export maps the ggx fit only"},
          {"export " + doc + " --out " + dir + "/x.txt", "--format: gltf or mitsuba"},
          {"export " + dir + "/nothing.json --out " + dir + "/x.gltf", "nothing.json: cannot open"}},
      dir + "/x.gltf");
}

}  // namespace
}  // namespace brdffit
