// export: the metallic-roughness mapping; each format written from its own model's fit and read
// back to the same numbers; conversions with their error; verdicts; the files checked by their
// ecosystems' tools (Khronos glTF-Validator, xmllint) where installed; score --material.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <tuple>

#include "batch_test_util.h"
#include "brdffit/error.h"
#include "brdffit/material_convert.h"
#include "brdffit/material_export.h"
#include "brdffit/model.h"
#include "brdffit/models/gltf.h"
#include "brdffit/registry.h"

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

using test::fit_of;

const std::vector<std::string> kGltfSpecular = {
    "baseColor=0.8,0.5,0.25", "metallic=0.3", "roughness=0.45", "ior=1.7", "specular=0.8", "specularColor=1,0.9,0.7"};
const std::vector<std::string> kGltfClearcoat = {"baseColor=0.8,0.5,0.25", "metallic=0.3", "roughness=0.45",
                                                 "clearcoatFactor=0.7", "clearcoatRoughnessFactor=0.15"};
const std::vector<std::string> kGltfSheen = {"baseColor=0.8,0.5,0.25", "metallic=0.3", "roughness=0.45",
                                             "sheenColorFactor=0.6,0.3,0.2", "sheenRoughnessFactor=0.35"};
const std::vector<std::string> kGltfClearcoatSheen = {"baseColor=0.8,0.5,0.25",
                                                      "metallic=0.3",
                                                      "roughness=0.45",
                                                      "clearcoatFactor=0.7",
                                                      "clearcoatRoughnessFactor=0.15",
                                                      "sheenColorFactor=0.6,0.3,0.2",
                                                      "sheenRoughnessFactor=0.35"};
const std::vector<std::string> kGltfAnisotropy = {"baseColor=0.8,0.5,0.25", "metallic=0.9", "roughness=0.35",
                                                  "anisotropyStrength=0.6", "anisotropyRotation=1.25"};
const std::vector<std::string> kOpenPbr = {"base_color=0.7,0.4,0.2",     "base_metalness=0.2",
                                           "base_diffuse_roughness=0.3", "specular_color=1,0.8,0.6",
                                           "specular_roughness=0.35",    "specular_ior=1.6"};
const std::vector<std::string> kOpenPbrCoat = {"coat_weight=0.6", "coat_color=0.9,0.8,0.7", "coat_roughness=0.2",
                                               "coat_ior=1.7"};
const std::vector<std::string> kOpenPbrFuzz = {"fuzz_weight=0.5", "fuzz_color=0.7,0.5,0.4", "fuzz_roughness=0.6"};
std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}
const std::vector<std::string> kPrincipled = {
    "baseColor=0.6,0.3,0.1", "metallic=0.1", "subsurface=0.2", "specular=0.6",      "roughness=0.4",
    "specularTint=0.3",      "sheen=0.25",   "clearcoat=0.5",  "clearcoatGloss=0.7"};
const std::vector<std::string> kMitsubaPrincipled = {
    "base_color=0.6,0.3,0.1", "metallic=0.1", "flatness=0.2",  "specular=0.6",       "roughness=0.4",
    "spec_tint=0.3",          "sheen=0.25",   "clearcoat=0.5", "clearcoat_gloss=0.7"};

// Writes `doc` in `format`, reads the file back and expects the model's values (to `tolerance`).
void expect_round_trip(const std::string& doc, const std::string& out, const std::string& model,
                       const std::vector<std::string>& assignments, double tolerance, const std::string& extra = "") {
  const auto run = test::run_cli("export " + doc + " --out " + out + extra);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("the " + model + " fit unchanged"), std::string::npos) << run.output;
  std::vector<std::string> warnings;
  const Material material = read_material(out, "", warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(material.model, model);
  EXPECT_EQ(material.name, "gold");
  const std::vector<double> expected = parameter_values(*find_model(model), assignments);
  ASSERT_EQ(material.values.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(material.values[i], expected[i], tolerance) << i;
}

TEST(ExportCli, EachFormatWritesItsModelsFitUnchangedAndReadsBack) {
  const std::string dir = test::fresh_dir("export-round-trip");
  const std::string doc =
      test::write_document(dir + "/gold.json", "/data/gold.binary",
                           {fit_of("ggx", {"albedo=0.1", "roughness=0.3", "f0=0.9,0.6,0.3"}),
                            fit_of("gltf", {"baseColor=0.9,0.6,0.3", "metallic=0.85", "roughness=0.3"}),
                            fit_of("gltf-specular", kGltfSpecular), fit_of("gltf+clearcoat", kGltfClearcoat),
                            fit_of("gltf+sheen", kGltfSheen), fit_of("gltf+clearcoat+sheen", kGltfClearcoatSheen),
                            fit_of("gltf+anisotropy", kGltfAnisotropy), fit_of("openpbr", kOpenPbr),
                            fit_of("principled", kPrincipled), fit_of("mitsuba-principled", kMitsubaPrincipled)});
  // glTF: core by default (what most viewers read), the KHR extensions from the gltf-specular fit.
  expect_round_trip(doc, dir + "/gold.gltf", "gltf", {"baseColor=0.9,0.6,0.3", "metallic=0.85", "roughness=0.3"}, 0.0);
  const nlohmann::json core = nlohmann::json::parse(read_file(dir + "/gold.gltf"));
  EXPECT_FALSE(core.contains("extensionsUsed"));
  EXPECT_EQ(core["meshes"][0]["primitives"][0]["material"], 0);  // a sphere using the material
  EXPECT_NEAR(core["materials"][0]["extras"]["brdffit"]["metrics"]["cosine"].get<double>(), 0.0123, 1e-12);
  expect_round_trip(doc, dir + "/gold-specular.gltf", "gltf-specular", kGltfSpecular, 0.0, " -m gltf-specular");
  const nlohmann::json ext = nlohmann::json::parse(read_file(dir + "/gold-specular.gltf"));
  EXPECT_EQ(ext["extensionsUsed"], nlohmann::json({"KHR_materials_ior", "KHR_materials_specular"}));
  EXPECT_EQ(ext["materials"][0]["extensions"]["KHR_materials_ior"]["ior"], 1.7);
  // The second lobe: KHR_materials_clearcoat's two factors, exactly, and nothing else.
  expect_round_trip(doc, dir + "/gold-clearcoat.gltf", "gltf+clearcoat", kGltfClearcoat, 0.0, " -m gltf+clearcoat");
  const nlohmann::json coat = nlohmann::json::parse(read_file(dir + "/gold-clearcoat.gltf"));
  EXPECT_EQ(coat["extensionsUsed"], nlohmann::json({"KHR_materials_clearcoat"}));
  EXPECT_EQ(coat["materials"][0]["extensions"],
            nlohmann::json::parse(
                R"({"KHR_materials_clearcoat": {"clearcoatFactor": 0.7, "clearcoatRoughnessFactor": 0.15}})"));
  // The former name still picks the coat's fit.
  expect_round_trip(doc, dir + "/gold-coat-alias.gltf", "gltf+clearcoat", kGltfClearcoat, 0.0, " -m gltf-clearcoat");
  // The sheen: KHR_materials_sheen's colour and roughness, exactly; with the coat, both extensions.
  expect_round_trip(doc, dir + "/gold-sheen.gltf", "gltf+sheen", kGltfSheen, 0.0, " -m gltf+sheen");
  const nlohmann::json sheen = nlohmann::json::parse(read_file(dir + "/gold-sheen.gltf"));
  EXPECT_EQ(sheen["extensionsUsed"], nlohmann::json({"KHR_materials_sheen"}));
  EXPECT_EQ(sheen["materials"][0]["extensions"],
            nlohmann::json::parse(
                R"({"KHR_materials_sheen": {"sheenColorFactor": [0.6, 0.3, 0.2], "sheenRoughnessFactor": 0.35}})"));
  expect_round_trip(doc, dir + "/gold-both.gltf", "gltf+clearcoat+sheen", kGltfClearcoatSheen, 0.0,
                    " -m gltf+sheen+clearcoat");
  const nlohmann::json both = nlohmann::json::parse(read_file(dir + "/gold-both.gltf"));
  EXPECT_EQ(both["extensionsUsed"], nlohmann::json({"KHR_materials_clearcoat", "KHR_materials_sheen"}));
  EXPECT_EQ(
      both["materials"][0]["extensions"],
      nlohmann::json::parse(R"({"KHR_materials_clearcoat": {"clearcoatFactor": 0.7, "clearcoatRoughnessFactor": 0.15},
                                "KHR_materials_sheen": {"sheenColorFactor": [0.6, 0.3, 0.2],
                                                        "sheenRoughnessFactor": 0.35}})"));
  // The stretch: KHR_materials_anisotropy's strength and rotation, exactly, on a mesh with the TANGENT the
  // extension requires, along the sphere's longitude (sphere.h's LocalFrame): (-sin φ, 0, -cos φ), w = 1.
  expect_round_trip(doc, dir + "/gold-anisotropy.gltf", "gltf+anisotropy", kGltfAnisotropy, 0.0, " -m gltf+anisotropy");
  const nlohmann::json stretched = nlohmann::json::parse(read_file(dir + "/gold-anisotropy.gltf"));
  EXPECT_EQ(stretched["extensionsUsed"], nlohmann::json({"KHR_materials_anisotropy"}));
  EXPECT_EQ(stretched["materials"][0]["extensions"],
            nlohmann::json::parse(
                R"({"KHR_materials_anisotropy": {"anisotropyStrength": 0.6, "anisotropyRotation": 1.25}})"));
  EXPECT_EQ(stretched["meshes"][0]["primitives"][0]["attributes"]["TANGENT"], 3);
  EXPECT_EQ(stretched["accessors"][3]["type"], "VEC4");
  EXPECT_FALSE(core["meshes"][0]["primitives"][0]["attributes"].contains("TANGENT"));  // only where needed
  // OpenPBR and Mitsuba: nine significant digits in the files, so these short decimals come back exactly.
  expect_round_trip(doc, dir + "/gold.mtlx", "openpbr", kOpenPbr, 0.0);
  // Mitsuba: the mitsuba-principled fit (what the plugin evaluates), not Burley's principled one.
  expect_round_trip(doc, dir + "/gold.xml", "mitsuba-principled", kMitsubaPrincipled, 0.0);
  const std::string mitsuba = read_file(dir + "/gold.xml");
  EXPECT_NE(mitsuba.find("<float name=\"flatness\" value=\"0.2\"/>"), std::string::npos) << mitsuba;
  EXPECT_NE(mitsuba.find("<float name=\"spec_tint\" value=\"0.3\"/>"), std::string::npos) << mitsuba;
}

TEST(ExportCli, SmallValuesSurviveTheXmlFormatsToNineDigits) {
  // A nearly black albedo and a nearly smooth diffuse or a faint clearcoat: six decimals ("%.6f")
  // wrote 3e-7 as 0.000000 and 1.23456789e-4 as 0.000123 (three digits). %.9g keeps nine
  // significant digits of any magnitude: relative error at most 5e-9.
  const std::string dir = test::fresh_dir("export-small-values");
  const std::vector<std::string> openpbr = {"base_color=3e-7,1.23456789e-4,0.5",    "base_metalness=2.5e-6",
                                            "base_diffuse_roughness=1.23456789e-4", "specular_color=1,7.654321e-5,1",
                                            "specular_roughness=0.0123456789",      "specular_ior=1.00001234"};
  const std::vector<std::string> mitsuba = {"base_color=3e-7,1.23456789e-4,0.5",
                                            "metallic=2.5e-6",
                                            "flatness=1.23456789e-4",
                                            "specular=0.00123456789",
                                            "roughness=0.0456789",
                                            "spec_tint=9.87654321e-8",
                                            "sheen=1e-9",
                                            "clearcoat=3.3e-5",
                                            "clearcoat_gloss=0.999999999"};
  const std::string doc = test::write_document(dir + "/gold.json", "/data/gold.binary",
                                               {fit_of("openpbr", openpbr), fit_of("mitsuba-principled", mitsuba)});
  for (const auto& [out, model, assignments] :
       {std::tuple{"/gold.mtlx", "openpbr", openpbr}, std::tuple{"/gold.xml", "mitsuba-principled", mitsuba}}) {
    SCOPED_TRACE(out);
    const auto run = test::run_cli("export " + doc + " --out " + dir + out);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    std::vector<std::string> warnings;
    const Material material = read_material(dir + out, "", warnings);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    const std::vector<double> expected = parameter_values(*find_model(model), assignments);
    ASSERT_EQ(material.values.size(), expected.size());
    for (size_t i = 0; i < expected.size(); ++i) {
      EXPECT_GT(material.values[i], 0.0) << i;  // nothing rounded away
      EXPECT_NEAR(material.values[i], expected[i], 5e-9 * expected[i]) << i;
    }
  }
  // As written: 3e-7 in the exponent form, the nine digits of 1.23456789e-4.
  const std::string mtlx = read_file(dir + "/gold.mtlx");
  EXPECT_NE(mtlx.find("name=\"base_color\" type=\"color3\" value=\"3e-07, 0.000123456789, 0.5\""), std::string::npos)
      << mtlx;
}

TEST(ExportCli, ConvertsAnotherFitAndReportsTheConvertedError) {
  const std::string dir = test::fresh_dir("export-convert");
  // Data from a gltf material: its ggx fit converted back to gltf is close, and both errors are printed.
  const std::string data =
      test::write_model_csv(dir + "/plastic.csv", "gltf", {"baseColor=0.6,0.3,0.2", "metallic=0", "roughness=0.5"});
  const std::string doc = test::write_document(dir + "/plastic.json", data,
                                               {fit_of("ggx", {"albedo=0.55,0.28,0.18", "roughness=0.5", "f0=0.04"})});
  const auto run = test::run_cli("export " + doc + " -m ggx --out " + dir + "/plastic.gltf");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::smatch m = [&] {
    std::smatch match;
    std::regex_search(run.output, match,
                      std::regex("converted from the ggx fit .*converted ([0-9.e-]+), the ggx fit ([0-9.e-]+)"));
    return match;
  }();
  ASSERT_EQ(m.size(), 3u) << run.output;
  // The converted material is the generating one up to the mapping (albedo/0.96 → baseColor): tiny error,
  // and computed on the data, not copied from the document's 0.0123.
  EXPECT_LT(std::stod(m[1]), 0.05) << run.output;
  EXPECT_NE(std::stod(m[2]), 0.0123);
  std::vector<std::string> warnings;
  const Material converted = read_material(dir + "/plastic.gltf", "", warnings);
  EXPECT_EQ(converted.model, "gltf");
  EXPECT_NEAR(converted.values[0], 0.55 / 0.96, 1e-9);
  EXPECT_NEAR(converted.values[3], 0.0, 1e-12);  // a dielectric
  // Into OpenPBR and Mitsuba too.
  for (const char* out : {"/plastic.mtlx", "/plastic.xml"}) {
    const auto again = test::run_cli("export " + doc + " -m ggx --out " + dir + out);
    EXPECT_EQ(again.exit_code, 0) << again.output;
    EXPECT_NE(again.output.find("converted from the ggx fit"), std::string::npos) << again.output;
  }
}

// A parameter of a material by name (the first channel of a colour).
double value_of(const Material& material, const std::string& param, int channel = 0) {
  return material.values[find_model(material.model)->offset_of(param) + channel];
}

// ((η-1)/(η+1))²: a dielectric's reflectance at normal incidence.
double reflectance_of_ior(double eta) { return std::pow((eta - 1) / (eta + 1), 2); }

TEST(ExportConversion, EveryTargetKeepsTheDielectricReflectionItCanHold) {
  const Model& gltf_specular = *find_model("gltf-specular");
  // specular 0: no dielectric reflection whatever the ior. Carried as an ior it was F0 0.25 at
  // ior 3, principled specular 0.25/0.08 clamped to 1; it is F0 0 in every target.
  const std::vector<double> unreflecting = parameter_values(
      gltf_specular,
      {"baseColor=0.8,0.5,0.25", "metallic=0.3", "roughness=0.45", "ior=3", "specular=0", "specularColor=1,0.9,0.7"});
  EXPECT_EQ(value_of(convert_material("gltf-specular", unreflecting, "principled"), "specular"), 0.0);
  EXPECT_EQ(value_of(convert_material("gltf-specular", unreflecting, "mitsuba-principled"), "specular"),
            0.001);  // the model's floor (the plugin skips the lobe at 0)
  EXPECT_EQ(value_of(convert_material("gltf-specular", unreflecting, "openpbr"), "specular_ior"), 1.0);

  // A weight between: F0 = 0.5·((1.7-1)/(1.7+1))² = 0.0336 is what every target reflects at normal
  // incidence; openpbr (specular_weight held at 1) folds the weight into its ior; the tint goes to
  // openpbr's specular_color.
  const std::vector<double> half =
      parameter_values(gltf_specular, {"baseColor=0.8,0.5,0.25", "metallic=0.3", "roughness=0.45", "ior=1.7",
                                       "specular=0.5", "specularColor=1,0.9,0.7"});
  const double f0 = 0.5 * (0.7 / 2.7) * (0.7 / 2.7);
  EXPECT_NEAR(0.08 * value_of(convert_material("gltf-specular", half, "principled"), "specular"), f0, 1e-15);
  EXPECT_NEAR(0.08 * value_of(convert_material("gltf-specular", half, "mitsuba-principled"), "specular"), f0, 1e-15);
  const Material openpbr = convert_material("gltf-specular", half, "openpbr");
  EXPECT_NEAR(reflectance_of_ior(value_of(openpbr, "specular_ior")), f0, 1e-15);
  for (int c = 0; c < 3; ++c)
    EXPECT_EQ(value_of(openpbr, "specular_color", c), half[gltf_specular.offset_of("specularColor") + c]);

  // The other way: openpbr's ior and tint become gltf-specular's, with specular weight 1; the
  // principled models' specular becomes the ior of the same F0.
  const Material from_openpbr =
      convert_material("openpbr", parameter_values(*find_model("openpbr"), kOpenPbr), "gltf-specular");
  EXPECT_EQ(value_of(from_openpbr, "ior"), 1.6);
  EXPECT_EQ(value_of(from_openpbr, "specular"), 1.0);
  EXPECT_EQ(value_of(from_openpbr, "specularColor", 1), 0.8);
  EXPECT_EQ(value_of(from_openpbr, "specularColor", 2), 0.6);
  const Material from_principled =
      convert_material("principled", parameter_values(*find_model("principled"), kPrincipled), "gltf-specular");
  EXPECT_NEAR(reflectance_of_ior(value_of(from_principled, "ior")), 0.08 * 0.6, 1e-15);
  EXPECT_EQ(value_of(from_principled, "specular"), 1.0);

  // Through the command: the gltf-specular fit with specular 0, exported to OpenPBR.
  const std::string dir = test::fresh_dir("export-dielectric");
  const std::string doc =
      test::write_document(dir + "/clear.json", "/nowhere/clear.binary",
                           {fit_of("gltf-specular", {"baseColor=0.8,0.5,0.25", "metallic=0.3", "roughness=0.45",
                                                     "ior=3", "specular=0", "specularColor=1,0.9,0.7"})});
  const auto run = test::run_cli("export " + doc + " -m gltf-specular -o " + dir + "/clear.mtlx");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::vector<std::string> warnings;
  EXPECT_EQ(value_of(read_material(dir + "/clear.mtlx", "", warnings), "specular_ior"), 1.0);

  // Into glTF: an openpbr fit whose ior and tint are not the core's becomes gltf-specular (its
  // KHR_materials_ior and KHR_materials_specular hold them); one with the core's stays core glTF.
  const std::string openpbr_doc = test::write_document(
      dir + "/pbr.json", "/nowhere/pbr.binary",
      {fit_of("openpbr", kOpenPbr), fit_of("ggx", {"albedo=0.5", "roughness=0.3", "f0=0.04"})});  // ior 1.5: core glTF
  const auto tinted = test::run_cli("export " + openpbr_doc + " -m openpbr -o " + dir + "/tinted.gltf");
  ASSERT_EQ(tinted.exit_code, 0) << tinted.output;
  EXPECT_NE(tinted.output.find("the gltf-specular material"), std::string::npos) << tinted.output;
  const nlohmann::json gltf = nlohmann::json::parse(read_file(dir + "/tinted.gltf"));
  EXPECT_EQ(gltf["materials"][0]["extensions"]["KHR_materials_ior"]["ior"], 1.6);
  EXPECT_EQ(gltf["materials"][0]["extensions"]["KHR_materials_specular"]["specularColorFactor"],
            nlohmann::json({1.0, 0.8, 0.6}));
  const auto plain = test::run_cli("export " + openpbr_doc + " -m ggx -o " + dir + "/plain.gltf");
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  EXPECT_NE(plain.output.find("the gltf material"), std::string::npos) << plain.output;
  EXPECT_FALSE(nlohmann::json::parse(read_file(dir + "/plain.gltf")).contains("extensionsUsed"));
}

// The number after `label` in `text` (NaN when absent).
double number_after(const std::string& text, const std::string& label) {
  std::smatch match;
  if (!std::regex_search(text, match, std::regex(label + " ([0-9.e+-]+|nan)"))) return NAN;
  return std::stod(match[1]);
}

TEST(ExportCli, PrincipledToMitsubaIsAConversionWithItsError) {
  // Data from Burley's principled BRDF, fitted exactly: Mitsuba's plugin, given the same
  // parameters by name, draws another BRDF; the export says so and prints by how much.
  const std::string dir = test::fresh_dir("export-principled-mitsuba");
  const std::string data = test::write_model_csv(dir + "/coated.csv", "principled", kPrincipled);
  const std::string doc = test::write_document(dir + "/coated.json", data, {fit_of("principled", kPrincipled)});
  const auto run = test::run_cli("export " + doc + " -m principled --out " + dir + "/coated.xml");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("converted from the principled fit parameter by parameter"), std::string::npos)
      << run.output;
  const double on_data = number_after(run.output, "all samples: converted");
  const double source_on_data = number_after(run.output, "the principled fit");
  const double vs_fit = number_after(run.output, "on fixed directions: cosine");
  EXPECT_LT(source_on_data, 1e-9) << run.output;  // the fit is the data
  // The plugin's BRDF is not Burley's: on the data (directions up to 84°) and on the fixed
  // directions (the whole hemisphere, where the grazing clearcoat differs most).
  EXPECT_GT(on_data, 0.003) << run.output;
  EXPECT_GT(vs_fit, on_data) << run.output;
  // The values are Burley's, carried over by name.
  std::vector<std::string> warnings;
  const Material material = read_material(dir + "/coated.xml", "", warnings);
  EXPECT_EQ(material.model, "mitsuba-principled");
  const Model& mitsuba = *find_model("mitsuba-principled");
  EXPECT_NEAR(material.values[mitsuba.offset_of("flatness")], 0.2, 5e-7);
  EXPECT_NEAR(material.values[mitsuba.offset_of("clearcoat_gloss")], 0.7, 5e-7);
  EXPECT_NEAR(material.values[mitsuba.offset_of("base_color") + 2], 0.1, 5e-7);
  // With no principled conversion asked for, the document has no mitsuba-principled fit to export.
  test::expect_cli_errors({{"export " + doc + " --out " + dir + "/x.xml",
                            "coated.json: has no mitsuba-principled fit; fit with -m mitsuba-principled"}},
                          dir + "/x.xml");
}

TEST(ExportCli, ABareMetalIsTheSameInBurleysAndMitsubasFormulas) {
  // Metallic 1 without clearcoat: both are Schlick's F of the base colour times GGX D and the
  // separable Smith G over 4 n·l n·v, so the parameter-by-parameter conversion is exact and its
  // difference from the fit on the fixed directions vanishes.
  const std::string dir = test::fresh_dir("export-bare-metal");
  const std::string doc =
      test::write_document(dir + "/metal.json", "/nowhere/metal.binary",
                           {fit_of("principled", {"baseColor=0.9,0.6,0.3", "metallic=1", "roughness=0.35",
                                                  "clearcoat=0", "sheen=0.4", "subsurface=0.3", "specularTint=0.5"})});
  const auto run = test::run_cli("export " + doc + " -m principled --out " + dir + "/metal.xml");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("converted from the principled fit parameter by parameter"), std::string::npos)
      << run.output;
  EXPECT_LT(number_after(run.output, "on fixed directions: cosine"), 1e-12) << run.output;
}

TEST(ExportCli, TheOutputsExtensionPicksTheFormatAndAConflictingFormatIsAUsageError) {
  const std::string dir = test::fresh_dir("export-extension");
  const std::string doc =
      test::write_document(dir + "/gold.json", "/data/gold.binary",
                           {fit_of("gltf", {"baseColor=0.9,0.6,0.3", "metallic=1", "roughness=0.3"}),
                            fit_of("openpbr", kOpenPbr), fit_of("mitsuba-principled", kMitsubaPrincipled)});
  // From the extension alone: each file is its format's document of its format's own fit.
  for (const auto& [out, opening, model] :
       {std::tuple{"/m.mtlx", "<materialx", "openpbr"}, std::tuple{"/m.xml", "<scene", "mitsuba-principled"},
        std::tuple{"/m.gltf", "{", "gltf"}}) {
    const auto run = test::run_cli("export " + doc + " -o " + dir + out);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find(std::string("the ") + model + " fit unchanged"), std::string::npos) << run.output;
    EXPECT_NE(read_file(dir + out).find(opening), std::string::npos) << out;
  }
  // An explicit --format that agrees, or names an output without a known extension, is taken.
  EXPECT_EQ(test::run_cli("export " + doc + " --format openpbr -o " + dir + "/agree.mtlx").exit_code, 0);
  const auto named = test::run_cli("export " + doc + " --format mitsuba -o " + dir + "/bsdf.include");
  ASSERT_EQ(named.exit_code, 0) << named.output;
  EXPECT_NE(read_file(dir + "/bsdf.include").find("<bsdf type=\"principled\""), std::string::npos);
  // One that contradicts the extension is a usage error, and nothing is written.
  test::expect_cli_errors(
      {{"export " + doc + " --format gltf -o " + dir + "/x.mtlx",
        "--format gltf conflicts with the output " + dir + "/x.mtlx, whose extension .mtlx is the openpbr format's", 2},
       {"export " + doc + " --format openpbr -o " + dir + "/x.mtlx.xml", "extension .xml is the mitsuba format's", 2}},
      dir + "/x.mtlx");
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.mtlx.xml"));
}

// The table of formats (material_formats()): each entry is found by its key, its name and its
// extension; its writer writes every native model (values inside the bounds, none the default)
// and refuses the other formats' models; the file, read back through the table by its extension,
// is the same material. The conversion of a ggx or principled fit lands on a native model.
TEST(MaterialFormats, EachEntryWritesItsNativeModelsAndReadsThemBackThroughTheTable) {
  const std::string dir = test::fresh_dir("material-formats");
  std::set<std::string> names, extensions;
  for (const MaterialFormatInfo& info : material_formats()) {
    SCOPED_TRACE(info.name);
    EXPECT_TRUE(names.insert(info.name).second);
    EXPECT_TRUE(extensions.insert(info.extension).second);
    EXPECT_EQ(&material_format_info(info.format), &info);
    EXPECT_EQ(material_format(info.name, ""), info.format);
    EXPECT_EQ(material_format("", dir + "/m" + info.extension), info.format);
    EXPECT_EQ(material_format(info.name, dir + "/m" + info.extension), info.format);
    for (const std::string& model_name : info.native_models) {
      SCOPED_TRACE(model_name);
      const Model& model = *find_model(model_name);
      Material material{"m", model_name, {}};
      for (const ParamSpec& p : model.parameters())
        for (int c = 0; c < p.channels; ++c)
          material.values.push_back(p.lower + (0.31 + 0.1 * c) * (p.upper - p.lower));
      const std::string path = dir + "/" + model_name + info.extension;
      write_file_atomic(path, info.write(material, {nlohmann::json::object(), "a comment"}));
      std::vector<std::string> warnings;
      const std::vector<Material> read = read_materials(path, warnings);
      EXPECT_TRUE(warnings.empty()) << warnings.front();
      ASSERT_EQ(read.size(), 1u);
      EXPECT_EQ(read[0].name, "m");
      EXPECT_EQ(read[0].model, model_name);
      ASSERT_EQ(read[0].values.size(), material.values.size());
      for (size_t i = 0; i < material.values.size(); ++i)
        EXPECT_NEAR(read[0].values[i], material.values[i], 5e-9 * std::abs(material.values[i])) << i;
    }
    for (const MaterialFormatInfo& other : material_formats())
      if (&other != &info) {
        const Model& foreign = *find_model(other.native_models.front());
        EXPECT_THROW(info.write({"m", foreign.name(), foreign.default_values()}, {}), Error) << foreign.name();
      }
    for (const auto& [source, assignments] :
         {std::pair{"ggx", std::vector<std::string>{"albedo=0.3", "f0=0.04"}}, std::pair{"principled", kPrincipled}}) {
      const std::vector<double> values = parameter_values(*find_model(source), assignments);
      const std::string target =
          info.conversion_target ? info.conversion_target(source, values) : info.native_models.front();
      EXPECT_NE(std::find(info.native_models.begin(), info.native_models.end(), target), info.native_models.end())
          << source << " -> " << target;
    }
  }
  EXPECT_EQ(material_format_list(&MaterialFormatInfo::name), "gltf, openpbr or mitsuba");
}

TEST(ExportCli, RefusesPoorOrFailedVerdictsWithoutForce) {
  const std::string dir = test::fresh_dir("export-verdict");
  FitResult poor = fit_of("gltf", {"baseColor=0.5", "metallic=0", "roughness=0.5"});
  poor.verdict = Verdict::Poor;
  poor.warnings = {"worse than the Lambert baseline"};
  const std::string doc = test::write_document(dir + "/poor.json", "/data/poor.binary", {poor});
  test::expect_cli_errors({{"export " + doc + " --out " + dir + "/poor.gltf",
                            "poor.json: the gltf fit's verdict is poor (worse than the Lambert baseline)"}},
                          dir + "/poor.gltf");
  const auto forced = test::run_cli("export " + doc + " --force --out " + dir + "/poor.gltf");
  ASSERT_EQ(forced.exit_code, 0) << forced.output;
  EXPECT_NE(forced.output.find("warning: the gltf fit's verdict is poor"), std::string::npos) << forced.output;
  EXPECT_TRUE(std::filesystem::exists(dir + "/poor.gltf"));
  // The reason given is the "poor fit" warning, not a note before it (an isotropic form's).
  FitResult noted = fit_of("gltf+anisotropy", {"baseColor=0.5"});
  noted.verdict = Verdict::Poor;
  noted.warnings = {"isotropic data: gltf+anisotropy was fitted in its isotropic form, gltf",
                    "poor fit: a typical sample is off by 101% of its own value"};
  const std::string noted_doc = test::write_document(dir + "/noted.json", "/data/noted.binary", {noted});
  test::expect_cli_errors({{"export " + noted_doc + " -m gltf+anisotropy --out " + dir + "/noted.gltf",
                            "the gltf+anisotropy fit's verdict is poor (poor fit: a typical sample is off by 101%"}},
                          dir + "/noted.gltf");

  FitResult failed = fit_of("openpbr", {});
  failed.ok = false;
  failed.error = "diverged";
  const std::string failed_doc = test::write_document(dir + "/failed.json", "/data/failed.binary", {failed});
  const std::string plain = test::write_document(dir + "/plain.json", "/data/plain.binary", {fit_of("lambert", {})});
  test::expect_cli_errors(
      {{"export " + failed_doc + " --force --out " + dir + "/x.mtlx", "failed.json: the openpbr fit failed (diverged)"},
       {"export " + plain + " --out " + dir + "/x.mtlx",
        "plain.json: has no openpbr fit; fit with -m openpbr to export it unchanged, or convert another fit with -m"},
       {"export " + plain + " -m lambert --out " + dir + "/x.mtlx", "no conversion from the lambert model"},
       {"export " + plain + " -m ward --out " + dir + "/x.mtlx", "plain.json: has no ward fit"},
       {"export " + plain + " --out " + dir + "/x.txt", "--format: gltf, openpbr or mitsuba"},
       {"export " + dir + "/nothing.json --out " + dir + "/x.mtlx", "nothing.json: cannot open"}},
      dir + "/x.mtlx");
}

// The input names of OpenPBR Surface (specification's parameter reference) and of Mitsuba 3's
// principled plugin.
const std::set<std::string> kOpenPbrInputs = {"base_weight",
                                              "base_color",
                                              "base_metalness",
                                              "base_diffuse_roughness",
                                              "specular_weight",
                                              "specular_color",
                                              "specular_roughness",
                                              "specular_roughness_anisotropy",
                                              "specular_ior",
                                              "transmission_weight",
                                              "coat_weight",
                                              "fuzz_weight",
                                              "thin_film_weight",
                                              "emission_luminance",
                                              "geometry_opacity",
                                              "subsurface_weight",
                                              "coat_color",
                                              "coat_roughness",
                                              "coat_ior",
                                              "coat_darkening",
                                              "coat_roughness_anisotropy",
                                              "fuzz_color",
                                              "fuzz_roughness"};
const std::set<std::string> kMitsubaPrincipledInputs = {"base_color",
                                                        "roughness",
                                                        "anisotropic",
                                                        "metallic",
                                                        "spec_trans",
                                                        "eta",
                                                        "specular",
                                                        "spec_tint",
                                                        "sheen",
                                                        "sheen_tint",
                                                        "flatness",
                                                        "clearcoat",
                                                        "clearcoat_gloss",
                                                        "diffuse_reflectance_sampling_rate",
                                                        "specular_reflectance_sampling_rate",
                                                        "spec_trans_sampling_rate",
                                                        "diffuse_transmittance_sampling_rate"};

std::set<std::string> names_in(const std::string& text, const std::string& element) {
  std::set<std::string> names;
  const std::regex pattern("<" + element + " name=\"([a-z_]+)\"");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), pattern); it != std::sregex_iterator(); ++it)
    names.insert((*it)[1]);
  return names;
}

// A name and input path with markup, "--" and control characters: the XML must stay well-formed.
const std::string kHostileInput = "/data/a<b>&c--d\x01\x1b.binary";

TEST(ExportTools, XmlIsWellFormedWithThePluginsNames) {
  REQUIRE_TOOL(test::have_tool("xmllint"), "xmllint (Debian libxml2-utils)");
  const std::string dir = test::fresh_dir("export-xml");
  const std::string doc =
      test::write_document(dir + "/hostile.json", kHostileInput,
                           {fit_of("openpbr", kOpenPbr), fit_of("mitsuba-principled", kMitsubaPrincipled)});
  for (const char* out : {"/m.mtlx", "/m.xml"}) {
    const auto run = test::run_cli("export " + doc + " --out " + dir + out);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const auto lint = test::run_command("xmllint --noout " + dir + out);
    EXPECT_EQ(lint.exit_code, 0) << lint.output << read_file(dir + out);
  }
  const std::string mtlx = read_file(dir + "/m.mtlx"), mitsuba = read_file(dir + "/m.xml");
  EXPECT_NE(mtlx.find("<open_pbr_surface name=\""), std::string::npos);
  for (const std::string& name : names_in(mtlx, "input"))
    if (name != "surfaceshader") EXPECT_TRUE(kOpenPbrInputs.count(name)) << name;
  EXPECT_EQ(names_in(mtlx, "input").size(), 10u);  // nine inputs and the material's surfaceshader
  std::set<std::string> mitsuba_names = names_in(mitsuba, "float");
  mitsuba_names.merge(names_in(mitsuba, "rgb"));
  for (const std::string& name : mitsuba_names) EXPECT_TRUE(kMitsubaPrincipledInputs.count(name)) << name;
  EXPECT_EQ(mitsuba_names.size(), 11u);
  // The hostile bytes survive as visible escapes.
  EXPECT_NE(mitsuba.find("a&lt;b&gt;&amp;c- -d\\x01\\x1B.binary"), std::string::npos) << mitsuba;
}

// MaterialX's own definition of OpenPBR Surface, as the npm package @needle-tools/materialx
// (pinned in scripts/install-deps.sh: MaterialX 1.39.4) ships its standard library: the
// Emscripten file package bin/JsMaterialXGenShader.data.txt holds libraries/bxdf/open_pbr_surface.mtlx
// at the byte range bin/JsMaterialXGenShader.js lists for it. Read at test time, never copied.
const std::string kMaterialXPackage = "/@needle-tools/materialx";

std::string materialx_library_file(const std::string& library_path) {
  const std::string bin = test::npm_modules() + kMaterialXPackage + "/bin/";
  const std::string loader = read_file(bin + "JsMaterialXGenShader.js");
  std::smatch range;
  if (!std::regex_search(loader, range, std::regex("filename:\"" + library_path + "\",start:([0-9]+),end:([0-9]+)")))
    return "";
  const size_t start = std::stoul(range[1]), end = std::stoul(range[2]);
  return read_file(bin + "JsMaterialXGenShader.data.txt").substr(start, end - start);
}

// The attributes of each element `tag` in `xml` (attribute values hold no quotes in these files).
std::vector<std::map<std::string, std::string>> elements_of(const std::string& xml, const std::string& tag) {
  std::vector<std::map<std::string, std::string>> elements;
  const std::regex element("<" + tag + "\\s([^>]*)>"), attribute("([a-zA-Z_]+)=\"([^\"]*)\"");
  for (auto e = std::sregex_iterator(xml.begin(), xml.end(), element); e != std::sregex_iterator(); ++e) {
    const std::string body = (*e)[1];
    std::map<std::string, std::string>& attributes = elements.emplace_back();
    for (auto a = std::sregex_iterator(body.begin(), body.end(), attribute); a != std::sregex_iterator(); ++a)
      attributes[(*a)[1]] = (*a)[2];
  }
  return elements;
}

// "0.5" or "0.1, 0.2, 0.3" (MaterialX writes color3 with commas, with or without spaces).
std::vector<double> numbers_in(const std::string& text) {
  std::vector<double> numbers;
  std::string spaced = text;
  std::replace(spaced.begin(), spaced.end(), ',', ' ');
  std::istringstream in(spaced);
  for (double x; in >> x;) numbers.push_back(x);
  return numbers;
}

TEST(ExportTools, MaterialXDefinesEveryInputTheMtlxWritesWithItsTypeAndRange) {
  REQUIRE_TOOL(std::filesystem::exists(test::npm_modules() + kMaterialXPackage + "/bin/JsMaterialXGenShader.data.txt"),
               "the npm package @needle-tools/materialx");
  const std::string library = materialx_library_file("/libraries/bxdf/open_pbr_surface.mtlx");
  ASSERT_NE(library.find("<materialx version=\"1.39\">"), std::string::npos) << library.substr(0, 200);
  const size_t begin = library.find("<nodedef name=\"ND_open_pbr_surface_surfaceshader\"");
  const size_t end = library.find("</nodedef>", begin);
  ASSERT_NE(begin, std::string::npos);
  ASSERT_NE(end, std::string::npos);
  const std::string nodedef = library.substr(begin, end - begin);
  EXPECT_EQ(elements_of(nodedef, "nodedef").at(0).at("node"), "open_pbr_surface");
  std::map<std::string, std::map<std::string, std::string>> definition;
  for (auto& input : elements_of(nodedef, "input")) definition[input.at("name")] = input;
  ASSERT_GT(definition.size(), 30u);  // the whole nodedef was found, not a fragment

  // Each OpenPBR model's fit at both ends of every bound and in between: openpbr's inputs, the coat's
  // and the fuzz's, all of them inputs of the nodedef with its types and within its ranges.
  const std::string dir = test::fresh_dir("export-materialx-nodedef");
  const std::map<std::string, std::vector<std::string>> middle = {
      {"openpbr", kOpenPbr},
      {"openpbr+coat", with(kOpenPbr, kOpenPbrCoat)},
      {"openpbr+fuzz", with(kOpenPbr, kOpenPbrFuzz)},
      {"openpbr+coat+fuzz", with(with(kOpenPbr, kOpenPbrCoat), kOpenPbrFuzz)}};
  for (const auto& [model_name, middle_values] : middle) {
    const Model& model = *find_model(model_name);
    std::vector<std::string> low, high;
    for (const ParamSpec& p : model.parameters()) {
      low.push_back(fmt::format("{}={}", p.name, p.lower));
      high.push_back(fmt::format("{}={}", p.name, p.upper));
    }
    // The model's parameters, the three held inputs of the base and the coat's two.
    const size_t held = model.find_parameter("coat_weight") ? 5 : 3;
    for (const auto& [bound_name, assignments] :
         {std::pair{"low", low}, std::pair{"mid", middle_values}, std::pair{"high", high}}) {
      const std::string name = std::to_string(model.num_values()) + "-" + bound_name;
      SCOPED_TRACE(model_name + " " + bound_name);
      const std::string doc =
          test::write_document(dir + "/" + name + ".json", "/data/x.binary", {fit_of(model_name, assignments)});
      const auto run = test::run_cli("export " + doc + " -m " + model_name + " --out " + dir + "/" + name + ".mtlx");
      ASSERT_EQ(run.exit_code, 0) << run.output;
      const std::string mtlx = read_file(dir + "/" + name + ".mtlx");
      EXPECT_NE(mtlx.find("<materialx version=\"1.39\""), std::string::npos);  // the library's version
      const size_t shader_begin = mtlx.find("<open_pbr_surface "), shader_end = mtlx.find("</open_pbr_surface>");
      ASSERT_LT(shader_begin, shader_end);
      const std::string shader = mtlx.substr(shader_begin, shader_end - shader_begin);
      const auto inputs = elements_of(shader, "input");
      EXPECT_EQ(inputs.size(), model.parameters().size() + held);
      for (const auto& input : inputs) {
        const std::string& input_name = input.at("name");
        SCOPED_TRACE(input_name);
        ASSERT_TRUE(definition.count(input_name)) << "not an input of ND_open_pbr_surface_surfaceshader";
        const auto& defined = definition.at(input_name);
        EXPECT_EQ(input.at("type"), defined.at("type"));
        const std::vector<double> value = numbers_in(input.at("value"));
        ASSERT_EQ(value.size(), input.at("type") == "color3" ? 3u : 1u);
        for (const auto& [bound, below] : {std::pair{"uimin", true}, std::pair{"uimax", false}}) {
          if (!defined.count(bound)) continue;  // e.g. specular_ior has only a soft maximum
          const std::vector<double> limit = numbers_in(defined.at(bound));
          ASSERT_EQ(limit.size(), value.size()) << defined.at(bound);
          for (size_t c = 0; c < value.size(); ++c)
            EXPECT_TRUE(below ? value[c] >= limit[c] : value[c] <= limit[c]) << bound << " " << defined.at(bound);
        }
      }
    }
  }
}

TEST(ExportTools, KhronosValidatorFindsNothing) {
  const std::string module_dir = test::npm_modules();
  REQUIRE_TOOL(test::have_tool("node") && std::filesystem::exists(module_dir + "/gltf-validator"),
               "node with the npm package gltf-validator");
  const std::string dir = test::fresh_dir("export-validator");
  const std::string doc = test::write_document(
      dir + "/hostile.json", kHostileInput,
      {fit_of("gltf", {"baseColor=0.9,0.6,0.3", "metallic=1", "roughness=0.3"}), fit_of("gltf-specular", kGltfSpecular),
       fit_of("gltf+clearcoat", kGltfClearcoat), fit_of("gltf+sheen", kGltfSheen),
       fit_of("gltf+clearcoat+sheen", kGltfClearcoatSheen), fit_of("gltf+anisotropy", kGltfAnisotropy)});
  for (const std::string& model : gltf_models()) {
    const std::string out = dir + "/" + model + ".gltf";
    const auto run = test::run_cli("export " + doc + " -m " + model + " --out " + out);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const auto report = test::run_command("NODE_PATH=" + module_dir + " node " + BRDFFIT_SOURCE_DIR +
                                          "/tests/tools/validate_gltf.js " + out);
    EXPECT_EQ(report.exit_code, 0) << report.output;
    EXPECT_NE(report.output.find("\"numErrors\": 0"), std::string::npos) << report.output;
    EXPECT_NE(report.output.find("\"numWarnings\": 0"), std::string::npos) << report.output;
  }
}

// Directions over the hemisphere (l and v in different planes), for comparing two BRDFs.
std::vector<std::pair<Vec3, Vec3>> direction_pairs() {
  std::vector<std::pair<Vec3, Vec3>> pairs;
  const auto at = [](double theta, double phi) {
    return Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  };
  for (const double theta_l : {0.0, 0.3, 0.8, 1.2, 1.5})
    for (const double theta_v : {0.1, 0.6, 1.0, 1.45})
      for (const double phi : {0.0, 1.0, 2.5, 3.14}) pairs.emplace_back(at(theta_l, 0.4), at(theta_v, 0.4 + phi));
  return pairs;
}

// A glTF file of one gltf-specular material, with KHR_materials_ior's ior set to `ior`.
std::string write_gltf_with_ior(const std::string& path, const std::vector<double>& values, double ior) {
  nlohmann::json gltf = nlohmann::json::parse(gltf_document({"m", "gltf-specular", values}, nlohmann::json::object()));
  gltf["materials"][0]["extensions"]["KHR_materials_ior"]["ior"] = ior;
  write_file_atomic(path, gltf.dump());
  return path;
}

TEST(MaterialImport, GltfIorZeroIsFresnelOneReadExactlyOrRefused) {
  // KHR_materials_ior: ior 0 is valid, ((0-1)/(0+1))² = 1, so dielectric_f0 = min(specularColor, 1)·specular
  // and dielectric_f90 = specular. Each file below is read as a material whose BRDF is that one,
  // evaluated here from the extension's formulas with the file's own factors.
  const std::string dir = test::fresh_dir("import-ior-zero");
  const Model& model = *find_model("gltf-specular");
  struct Case {
    std::string name;
    std::vector<std::string> factors;  // as written, with ior 0
    std::string read_as;               // the warning that says how it was read
  };
  const std::vector<Case> cases = {
      {"no reflection", {"specular=0", "specularColor=1,0.9,0.7"}, "read exactly as ior 1.5"},
      {"dark tint", {"specular=0.7", "specularColor=0.2,0.1,0.05"}, "read exactly as ior 3"},
      {"mirror", {"specular=1", "specularColor=1,1,1"}, "read exactly as metallic 1"}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    std::vector<std::string> assignments = {"baseColor=0.8,0.5,0.25", "metallic=0.3", "roughness=0.45"};
    assignments.insert(assignments.end(), c.factors.begin(), c.factors.end());
    const std::vector<double> written = parameter_values(model, assignments);
    std::vector<std::string> warnings;
    const Material read = read_material(write_gltf_with_ior(dir + "/m.gltf", written, 0.0), "", warnings);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("KHR_materials_ior ior 0"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find(c.read_as), std::string::npos) << warnings[0];
    EXPECT_GE(value_of(read, "ior"), 1.0);  // within the model, not clamped from 0 to 1 ...
    const double specular = written[model.offset_of("specular")];
    Rgb<double> f0;
    for (int k = 0; k < 3; ++k) f0[k] = std::min(written[model.offset_of("specularColor") + k], 1.0) * specular;
    for (const auto& [l, v] : direction_pairs()) {  // ... but the same BRDF
      const Rgb<double> expected = models::gltf_metallic_roughness(
          &written[model.offset_of("baseColor")], written[model.offset_of("metallic")],
          models::gltf_specular_vd(written[model.offset_of("roughness")], l, v), f0, specular, l, v);
      const Rgb<double> got = *model.brdf(read.values.data(), l, v);
      EXPECT_TRUE(got.isApprox(expected, 1e-12)) << got.transpose() << " vs " << expected.transpose();
    }
  }
  // The mirror case in numbers: metallic 1, baseColor 0.3·b + 0.7.
  std::vector<std::string> warnings;
  const Material mirror = read_material(dir + "/m.gltf", "", warnings);
  EXPECT_EQ(value_of(mirror, "metallic"), 1.0);
  EXPECT_NEAR(value_of(mirror, "baseColor", 2), 0.3 * 0.25 + 0.7, 1e-15);

  // A partial Fresnel of 1 (F0 = F90 = 0.5): no model holds it; refused, not clamped.
  const std::string partial = write_gltf_with_ior(
      dir + "/partial.gltf",
      parameter_values(model, {"baseColor=0.5", "metallic=0", "roughness=0.5", "specular=0.5", "specularColor=1"}),
      0.0);
  try {
    read_material(partial, "", warnings);
    ADD_FAILURE() << "read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("ior 0 (Fresnel 1): a dielectric F0 of 0.5, 0.5, 0.5 and F90 0.5, which no "
                                         "brdffit model holds"),
              std::string::npos)
        << e.what();
  }
  // Any other ior below 1 is outside the extension's range: clamped to 1, with a warning.
  warnings.clear();
  const Material low = read_material(
      write_gltf_with_ior(dir + "/low.gltf", parameter_values(model, {"specular=0.5"}), 0.5), "", warnings);
  EXPECT_EQ(value_of(low, "ior"), 1.0);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("ior of 'm' is 0.5, outside"), std::string::npos) << warnings[0];
}

// A Mitsuba scene of one principled BSDF with these children.
std::string write_mitsuba(const std::string& path, const std::string& children) {
  write_file_atomic(
      path, "<scene version=\"3.0.0\">\n  <bsdf type=\"principled\" id=\"m\">\n" + children + "  </bsdf>\n</scene>\n");
  return path;
}

TEST(MaterialImport, MitsubaEtaIsReadAsTheSpecularOfTheSameIor) {
  // The plugin's η = 2/(1 - √(0.08·specular)) - 1 (models/mitsuba_principled.h): the specular read
  // from eta must give back the same η.
  const std::string dir = test::fresh_dir("import-mitsuba-eta");
  const auto eta_of = [](double specular) { return 2.0 / (1.0 - std::sqrt(0.08 * specular)) - 1.0; };
  std::vector<std::string> warnings;
  const Material water =
      read_material(write_mitsuba(dir + "/water.xml", "    <float name=\"eta\" value=\"1.33\"/>\n"), "", warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_NEAR(eta_of(value_of(water, "specular")), 1.33, 1e-12);
  EXPECT_NEAR(value_of(water, "specular"), reflectance_of_ior(1.33) / 0.08, 1e-15);
  // η 2 reflects 11 % at normal incidence, above the model's specular 1 (F0 8 %): clamped, said.
  const Material dense =
      read_material(write_mitsuba(dir + "/dense.xml", "    <float name=\"eta\" value=\"2\"/>\n"), "", warnings);
  EXPECT_EQ(value_of(dense, "specular"), 1.0);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("specular of 'm' is 1.38"), std::string::npos) << warnings[0];
  // The plugin refuses both; so does the reader.
  try {
    read_material(
        write_mitsuba(dir + "/both.xml",
                      "    <float name=\"eta\" value=\"1.5\"/>\n    <float name=\"specular\" value=\"0.5\"/>\n"),
        "", warnings);
    ADD_FAILURE() << "read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'m' gives both eta and specular"), std::string::npos) << e.what();
  }
}

// A glTF file of one core material (kGltfClearcoat's base) with these material extensions.
std::string write_gltf_with_extensions(const std::string& path, const std::string& extensions) {
  nlohmann::json gltf = nlohmann::json::parse(gltf_document(
      {"m", "gltf", parameter_values(*find_model("gltf"), {kGltfClearcoat[0], kGltfClearcoat[1], kGltfClearcoat[2]})},
      nlohmann::json::object()));
  gltf["materials"][0]["extensions"] = nlohmann::json::parse(extensions);
  write_file_atomic(path, gltf.dump());
  return path;
}

TEST(MaterialImport, GltfClearcoatIsReadWithTheExtensionsDefaults) {
  // KHR_materials_clearcoat: clearcoatFactor and clearcoatRoughnessFactor default to 0.
  const std::string dir = test::fresh_dir("import-clearcoat");
  std::vector<std::string> warnings;
  const Material coated = read_material(
      write_gltf_with_extensions(dir + "/coated.gltf", R"({"KHR_materials_clearcoat": {"clearcoatFactor": 0.4}})"), "",
      warnings);
  EXPECT_EQ(coated.model, "gltf+clearcoat");
  EXPECT_EQ(value_of(coated, "baseColor", 1), 0.5);
  EXPECT_EQ(value_of(coated, "clearcoatFactor"), 0.4);
  // The default roughness 0 (a mirror coat) is below the model's 0.01: clamped, and said.
  EXPECT_EQ(value_of(coated, "clearcoatRoughnessFactor"), 0.01);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("clearcoatRoughnessFactor of 'm' is 0, outside"), std::string::npos) << warnings[0];
  // Factor 0: the coat is off, so its roughness is no error (nothing to say), and the BRDF is the core's.
  warnings.clear();
  const Material off =
      read_material(write_gltf_with_extensions(dir + "/off.gltf", R"({"KHR_materials_clearcoat": {}})"), "", warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(off.model, "gltf+clearcoat");
  EXPECT_EQ(value_of(off, "clearcoatFactor"), 0.0);
  // With KHR_materials_specular too, no model holds both: gltf-specular, and the coat said to be left out.
  const Material both = read_material(
      write_gltf_with_extensions(
          dir + "/both.gltf",
          R"({"KHR_materials_specular": {"specularFactor": 0.5}, "KHR_materials_clearcoat": {"clearcoatFactor": 1}})"),
      "", warnings);
  EXPECT_EQ(both.model, "gltf-specular");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("uses KHR_materials_clearcoat, which the gltf-specular model it is read as leaves out"),
            std::string::npos)
      << warnings[0];
}

TEST(MaterialImport, GltfSheenIsReadWithTheExtensionsDefaults) {
  // KHR_materials_sheen: sheenColorFactor defaults to [0, 0, 0], sheenRoughnessFactor to 0.
  const std::string dir = test::fresh_dir("import-sheen");
  std::vector<std::string> warnings;
  const Material sheen =
      read_material(write_gltf_with_extensions(dir + "/sheen.gltf",
                                               R"({"KHR_materials_sheen": {"sheenColorFactor": [0.3, 0.2, 0.1]}})"),
                    "", warnings);
  EXPECT_EQ(sheen.model, "gltf+sheen");
  EXPECT_EQ(value_of(sheen, "baseColor", 1), 0.5);
  EXPECT_EQ(value_of(sheen, "sheenColorFactor", 0), 0.3);
  EXPECT_EQ(value_of(sheen, "sheenColorFactor", 2), 0.1);
  // The default roughness 0 (fibres exactly along the normal) is below the model's 0.1: clamped, and said.
  EXPECT_EQ(value_of(sheen, "sheenRoughnessFactor"), 0.1);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("sheenRoughnessFactor of 'm' is 0, outside"), std::string::npos) << warnings[0];
  // Colour 0: the sheen is off, its roughness no error, and the material is the core's (sheenColor 0 nests gltf).
  warnings.clear();
  const Material off =
      read_material(write_gltf_with_extensions(dir + "/off.gltf", R"({"KHR_materials_sheen": {}})"), "", warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(off.model, "gltf+sheen");
  EXPECT_EQ(value_of(off, "sheenColorFactor", 1), 0.0);
  // With the coat too: gltf+clearcoat+sheen, every factor read.
  const Material both = read_material(
      write_gltf_with_extensions(dir + "/both.gltf", R"({"KHR_materials_clearcoat": {"clearcoatFactor": 0.4,
          "clearcoatRoughnessFactor": 0.2}, "KHR_materials_sheen": {"sheenColorFactor": [0.3, 0.2, 0.1],
          "sheenRoughnessFactor": 0.6}})"),
      "", warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(both.model, "gltf+clearcoat+sheen");
  EXPECT_EQ(value_of(both, "clearcoatFactor"), 0.4);
  EXPECT_EQ(value_of(both, "clearcoatRoughnessFactor"), 0.2);
  EXPECT_EQ(value_of(both, "sheenColorFactor", 1), 0.2);
  EXPECT_EQ(value_of(both, "sheenRoughnessFactor"), 0.6);
}

// The cosine-weighted mean albedo of an openpbr material over the hemisphere, by the midpoint rule
// in cosθ and φ: (1/π)∫∫ f cosθl cosθv dωl dωv.
double mean_albedo(const std::vector<double>& values, int channel) {
  const Model& model = *find_model("openpbr");
  constexpr int kMu = 96, kPhi = 48;  // φ over [0, π] (f is even in φ), counted twice
  double sum = 0.0;
  for (int i = 0; i < kMu; ++i) {
    const double mu_v = (i + 0.5) / kMu;
    const Vec3 v(std::sqrt(1 - mu_v * mu_v), 0.0, mu_v);
    for (int j = 0; j < kMu; ++j) {
      const double mu_l = (j + 0.5) / kMu, s = std::sqrt(1 - mu_l * mu_l);
      for (int k = 0; k < kPhi; ++k) {
        const double phi = (k + 0.5) * kPi / kPhi;
        sum += model.shade(values.data(), Vec3(s * std::cos(phi), s * std::sin(phi), mu_l), v)[channel] * mu_v;
      }
    }
  }
  // dωl = dμl dφ (φ's step π/kPhi, twice), dωv = dμv dφv (2π: isotropic); shade carries cosθl.
  return sum * (1.0 / kMu) * (2.0 * kPi / kPhi) * (1.0 / kMu) * 2.0 * kPi / kPi;
}

TEST(MaterialImport, MtlxBaseWeightIsFoldedExactlyOrWithItsError) {
  const std::string dir = test::fresh_dir("import-base-weight");
  const auto write_mtlx = [&](const std::string& name, double diffuse_roughness) {
    write_file_atomic(
        dir + "/" + name + ".mtlx",
        fmt::format("<materialx version=\"1.39\">\n  <open_pbr_surface name=\"m\" type=\"surfaceshader\">\n"
                    "    <input name=\"base_weight\" type=\"float\" value=\"0.5\" />\n"
                    "    <input name=\"base_color\" type=\"color3\" value=\"0.8, 0.6, 0.4\" />\n"
                    "    <input name=\"base_diffuse_roughness\" type=\"float\" value=\"{}\" />\n"
                    "    <input name=\"specular_ior\" type=\"float\" value=\"1\" />\n"
                    "  </open_pbr_surface>\n</materialx>\n",
                    diffuse_roughness));
    return dir + "/" + name + ".mtlx";
  };
  // Diffuse roughness 0: EON is Lambert, linear in the colour; the fold is exact and silent.
  std::vector<std::string> warnings;
  const Material lambert = read_material(write_mtlx("lambert", 0.0), "", warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(value_of(lambert, "base_color", 0), 0.4);
  EXPECT_EQ(value_of(lambert, "base_color", 2), 0.2);
  // Diffuse roughness 1: EON's multiple scattering is not linear in ρ, so 0.5·EON(0.8) is not
  // EON(0.4). With specular_ior 1 the material is EON alone (no dielectric reflection), and the
  // warning's error is the folded material's mean albedo against half the unfolded one's.
  const Material rough = read_material(write_mtlx("rough", 1.0), "", warnings);
  EXPECT_EQ(value_of(rough, "base_color", 0), 0.4);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("base_weight 0.5 of 'm' is folded into base_color, which is not exact"), std::string::npos)
      << warnings[0];
  const double stated = number_after(warnings[0], "mean albedo is");
  std::vector<double> unfolded = rough.values;
  unfolded[find_model("openpbr")->offset_of("base_color")] = 0.8;  // the red channel: the largest error
  const double integrated = mean_albedo(rough.values, 0) / (0.5 * mean_albedo(unfolded, 0)) - 1.0;
  EXPECT_LT(integrated, -0.01);  // a real darkening, larger than the numbers' precision
  EXPECT_NEAR(stated / 100.0, integrated, 2e-4) << warnings[0];
}

TEST(ScoreCli, ScoresAMaterialFromAnAsset) {
  const std::string dir = test::fresh_dir("score-material");
  const std::vector<std::string> params = {"baseColor=0.7,0.5,0.3", "metallic=0.2", "roughness=0.4"};
  const std::string data = test::write_model_csv(dir + "/m.csv", "gltf", params);
  // A glTF with two materials: the generating one scores 0, the other does not; --name chooses.
  nlohmann::json gltf = nlohmann::json::parse(
      gltf_document({"exact", "gltf", parameter_values(*find_model("gltf"), params)}, nlohmann::json::object()));
  nlohmann::json other = gltf["materials"][0];
  other["name"] = "other";
  other["pbrMetallicRoughness"]["roughnessFactor"] = 0.8;
  gltf["materials"].push_back(other);
  write_file_atomic(dir + "/two.gltf", gltf.dump());
  const auto exact = test::run_cli("score " + data + " --material " + dir + "/two.gltf --name exact --json");
  ASSERT_EQ(exact.exit_code, 0) << exact.output;
  EXPECT_NEAR(nlohmann::json::parse(exact.output)["metrics"]["cosine"].get<double>(), 0.0, 1e-6) << exact.output;
  const auto rough = test::run_cli("score " + data + " --material " + dir + "/two.gltf --name other --json");
  ASSERT_EQ(rough.exit_code, 0) << rough.output;
  EXPECT_GT(nlohmann::json::parse(rough.output)["metrics"]["cosine"].get<double>(), 0.01) << rough.output;
  // Scored as another model: converted, with a warning.
  const auto converted = test::run_cli("score " + data + " --material " + dir + "/two.gltf --name exact -m openpbr");
  ASSERT_EQ(converted.exit_code, 0) << converted.output;
  EXPECT_NE(converted.output.find("scored converted to openpbr"), std::string::npos) << converted.output;
  test::expect_cli_errors({{"score " + data + " --material " + dir + "/two.gltf",
                            "two.gltf: holds 2 materials (exact, other): choose one with --name"},
                           {"score " + data + " --material " + dir + "/two.gltf --name none",
                            "two.gltf: has no material 'none' (it has: exact, other)"},
                           {"score " + data + " --material " + data, "m.csv: a material is read from .gltf, .mtlx"},
                           {"score " + data, "give -m MODEL (with --param) or --material"}},
                          dir + "/nothing");
  write_file_atomic(dir + "/broken.mtlx", "<materialx><open_pbr_surface name=\"a\"></materialx>");
  test::expect_cli_errors({{"score " + data + " --material " + dir + "/broken.mtlx", "broken.mtlx: malformed XML"}},
                          dir + "/nothing");
}

}  // namespace
}  // namespace brdffit
