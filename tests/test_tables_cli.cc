// The info, lookup and bake commands.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <nlohmann/json.hpp>

#include "brdffit/io.h"
#include "brdffit/merl.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"
#include "tables_test_util.h"

namespace brdffit {
namespace {

using test::run_cli;
using test::scratch_path;

nlohmann::json json_output(const test::CommandResult& r) {
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return nlohmann::json::parse(r.output);
}

Rgb<double> rgb_of(const nlohmann::json& j) { return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()}; }

TEST(TableCli, InfoDescribesEveryFormat) {
  const std::string merl = scratch_path("info.binary");
  ASSERT_EQ(run_cli("bake -m lambert --param albedo=0.5,0.25,0.125 --out " + merl).exit_code, 0);
  const nlohmann::json j = json_output(run_cli("info " + merl + " --json"));
  for (const char* key : {"format", "resolution", "valid", "invalid", "min", "max", "albedo"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["format"], "merl");
  EXPECT_EQ(j["resolution"], "90x90x180");
  EXPECT_EQ(j["valid"].get<size_t>() + j["invalid"].get<size_t>(), 90u * 90 * 180);
  // Lambert: f = albedo/π everywhere; the directional albedo is the albedo (quadrature error).
  EXPECT_NEAR(j["min"][0].get<double>(), 0.5 / kPi, 1e-12);
  EXPECT_NEAR(j["max"][2].get<double>(), 0.125 / kPi, 1e-12);
  EXPECT_NEAR(j["albedo"][1].get<double>(), 0.25, 0.005);
  const auto text = run_cli("info " + merl);
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_NE(text.output.find("albedo"), std::string::npos) << text.output;

  const std::string rgl = std::string(BRDFFIT_SOURCE_DIR) + "/data/cc_ibiza_sunset_rgb.bsdf";
  const nlohmann::json r = json_output(run_cli("info " + rgl + " --json"));
  EXPECT_EQ(r["format"], "rgl");
  EXPECT_EQ(r["resolution"], "1x8 incident, 32x32 rgb (isotropic)");
  EXPECT_EQ(r["valid"], 8192);
  const Rgb<double> albedo = rgb_of(r["albedo"]);
  EXPECT_TRUE((albedo.array() > 0.02).all() && (albedo.array() < 1).all()) << albedo.transpose();
  EXPECT_GT(rgb_of(r["max"]).maxCoeff(), 10.0) << "the vinyl's specular peak";

  const std::string csv = scratch_path("info.csv");
  test::write_bytes(csv, "lx,ly,lz,vx,vy,vz,r,g,b\n0,0,1,0.6,0,0.8,0.1,0.2,0.3\n0,0,1,0,0,1,0.4,0.1,0.3\n");
  const nlohmann::json c = json_output(run_cli("info " + csv + " --json"));
  EXPECT_EQ(c["format"], "csv");
  EXPECT_EQ(c["valid"], 2);
  EXPECT_EQ(rgb_of(c["max"]), Rgb<double>(0.4, 0.2, 0.3));
  EXPECT_TRUE(c["albedo"].is_null());
}

TEST(TableCli, LookupGivesTheMeasuredMerlBin) {
  // MERL: the nearest bin by hand (l = (0.2,0.6,1), v = (0.25,0.5,1): iθh 52, iθd 2, iφd 53, see
  // test_merl.cc), and the default trilinear lookup equals the library's.
  const std::string proxy = test::merl_proxy("red-fabric");
  SKIP_UNLESS_SHARED(!proxy.empty(), "the shared MERL proxies (" << test::kSharedDir << "/data/merl-proxy)");
  {
    const std::string bytes = read_file(proxy);
    double raw[3];
    for (int c = 0; c < 3; ++c)
      std::memcpy(&raw[c], bytes.data() + 12 + (c * size_t(90 * 90 * 180) + (52 * 90 + 2) * 180 + 53) * 8, 8);
    const Rgb<double> nearest = rgb_of(json_output(
        run_cli("lookup " + proxy + " --light 0.2,0.6,1 --view 0.25,0.5,1 --interp nearest --json"))["brdf"]);
    EXPECT_DOUBLE_EQ(nearest[0], raw[0] / 1500);
    EXPECT_DOUBLE_EQ(nearest[1], raw[1] * 1.15 / 1500);
    EXPECT_DOUBLE_EQ(nearest[2], raw[2] * 1.66 / 1500);
    const Rgb<double> trilinear =
        rgb_of(json_output(run_cli("lookup " + proxy + " --light 0.2,0.6,1 --view 0.25,0.5,1 --json"))["brdf"]);
    const Rgb<double> expected = MerlTable::read(proxy).lookup(
        Vec3(0.2, 0.6, 1).normalized(), Vec3(0.25, 0.5, 1).normalized(), Interpolation::Trilinear);
    for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(trilinear[c], expected[c]);
  }
}

TEST(TableCli, LookupGivesTheMeasuredF) {
  // RGL: the public loader's value at wi = (1,0,1), wo = (-1,0,1), the mirror pair of 45°
  // incidence (test_rgl.cc), is f·cosθo with wi the view and wo the light (rgl.h).
  const std::string rgl = std::string(BRDFFIT_SOURCE_DIR) + "/data/cc_ibiza_sunset_rgb.bsdf";
  const Rgb<double> f = rgb_of(json_output(run_cli("lookup " + rgl + " --light -1,0,1 --view 2,0,2 --json"))["brdf"]);
  EXPECT_NEAR(f[0], 2.46805429 / std::sqrt(0.5), 1e-4);
  EXPECT_NEAR(f[2], 0.944497049 / std::sqrt(0.5), 1e-4);
  const auto text = run_cli("lookup " + rgl + " --light -1,0,1 --view 1,0,1");
  EXPECT_EQ(text.output.rfind("brdf 3.490", 0), 0u) << text.output;
  // Below the horizon: zero.
  EXPECT_TRUE(rgb_of(json_output(run_cli("lookup " + rgl + " --light 1,0,-1 --view -1,0,1 --json"))["brdf"]).isZero());
}

TEST(TableCli, BakeWritesAModelAsAMerlTable) {
  const std::string path = scratch_path("bake.binary");
  const auto r = run_cli("bake -m ward --param alpha=0.2 --out " + path);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(path), std::string::npos) << r.output;
  // The bins below the horizon, counted over every bin centre by hand (test::pair_from_angles),
  // hold -1 and nothing else does; a few baked values are Ward's f at the centre.
  const std::string bytes = read_file(path);
  size_t below = 0;
  for (int ih = 0; ih < 90; ++ih)
    for (int id = 0; id < 90; ++id)
      for (int ip = 0; ip < 180; ++ip) {
        const double u = (ih + 0.5) / 90;
        const auto [l, v] = test::pair_from_angles(u * u * 90, id + 0.5, ip + 0.5, 0.0);
        const bool invalid = l.z() <= 0 || v.z() <= 0;
        below += invalid;
        if (invalid != (test::raw_bin(bytes, 0, ih, id, ip) == -1.0))
          ADD_FAILURE() << "bin " << ih << "," << id << "," << ip;
      }
  const MerlTable table = MerlTable::read(path);
  EXPECT_EQ(table.invalid_bins(), below);
  EXPECT_GT(below, 0u);
  EXPECT_LT(below, table.bins() / 2);
  const Model& ward = *find_model("ward");
  const std::vector<double> ward_values = parameter_values(ward, {"alpha=0.2"});
  for (const auto& [ih, id, ip] : {std::array<int, 3>{10, 20, 90}, {40, 5, 30}, {60, 45, 170}}) {
    const double u = (ih + 0.5) / 90;
    const auto [l, v] = test::pair_from_angles(u * u * 90, id + 0.5, ip + 0.5, 0.0);
    const Rgb<double> f = *ward.brdf(ward_values.data(), l, v), baked = test::raw_f(bytes, ih, id, ip);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(baked[c], f[c], 1e-9 * f[c]) << ih << "," << id << "," << ip;
  }
  // Models without a BRDF are tabulated as shade/cosθi.
  const std::string toon = scratch_path("toon.binary");
  ASSERT_EQ(run_cli("bake -m toon --out " + toon).exit_code, 0);
  const Model& model = *find_model("toon");
  const std::vector<double> values = model.default_values();
  const MerlTable baked_toon = MerlTable::read(toon);
  Vec3 l, v;
  from_half_diff(baked_toon.grid().centre(40, 30, 20), l, v);
  const Rgb<double> expected = model.shade(values.data(), l, v) / l.z();
  const Rgb<double> baked = baked_toon.lookup(l, v, Interpolation::Nearest);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(baked[c], expected[c], 1e-12 * (1 + expected[c]));
}

TEST(TableCli, ErrorsNameTheFileOrOptionAndTheProblem) {
  const std::string missing = scratch_path("missing.binary");
  const std::string truncated = scratch_path("truncated.binary");
  std::string header(12, '\0');
  const int32_t dims[3] = {90, 90, 180};
  std::memcpy(header.data(), dims, 12);
  test::write_bytes(truncated, header + std::string(100, '\0'));
  const std::string rgl = std::string(BRDFFIT_SOURCE_DIR) + "/data/cc_ibiza_sunset_rgb.bsdf";
  const std::pair<std::string, std::vector<std::string>> cases[] = {
      {"info " + missing, {missing, "cannot open"}},
      {"info " + truncated + " --json", {truncated, "truncated MERL table"}},
      {"lookup " + missing + " --light 0,0,1 --view 0,0,1", {missing, "cannot open"}},
      {"lookup " + truncated + " --light 0,0,1 --view 0,0,1", {truncated, "truncated"}},
      {"lookup " + rgl + " --light 0,0,1 --view 0,0,1 --interp nearest", {"--interp", "MERL tables only", rgl}},
      {"lookup " + rgl + " --light 0,0,1 --view 0,0,1 --interp cubic", {"--interp", "cubic"}},
      {"lookup " + rgl + " --light 0,0,0 --view 0,0,1", {"--light", "non-zero"}},
      {"lookup " + rgl + " --light 0,0 --view 0,0,1", {"--light"}},
      {"bake nosuchmodel --out " + missing, {"unknown model 'nosuchmodel'"}},
      {"bake -m ggx --param roughness=7 --out " + missing, {"roughness"}},
  };
  for (const auto& [arguments, fragments] : cases) {
    const auto r = run_cli(arguments);
    EXPECT_NE(r.exit_code, 0) << arguments;
    EXPECT_NE(r.exit_code, 70) << "an internal error: " << r.output;
    for (const std::string& f : fragments)
      EXPECT_NE(r.output.find(f), std::string::npos) << arguments << ": " << r.output;
  }
  EXPECT_FALSE(test::fs::exists(missing));
}

TEST(TableCli, AFailedWriteLeavesTheExistingFileWhole) {
  // /proc/version exists, but nothing can be created beside it (even by root): the write fails
  // before the existing file is touched, with a message naming it.
  const std::string before = read_file("/proc/version");
  const auto r = run_cli("bake -m lambert --out /proc/version");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("/proc/version: cannot write"), std::string::npos) << r.output;
  EXPECT_EQ(read_file("/proc/version"), before);
  // A model error is reported before anything is written.
  const std::string path = scratch_path("never.binary");
  EXPECT_NE(run_cli("bake -m ggx --param roughness=5 --out " + path).exit_code, 0);
  EXPECT_FALSE(test::fs::exists(path));
}

}  // namespace
}  // namespace brdffit
