// Measured inputs: MERL tables, RGL files, CSV samples, and the info/lookup/bake commands.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "brdffit/csv_samples.h"
#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/measured.h"
#include "brdffit/merl.h"
#include "brdffit/rgl.h"
#include "test_util.h"

namespace brdffit {
namespace {

namespace fs = std::filesystem;
const std::string kShared = BRDFFIT_SHARED_DIR;

std::string temp_path(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("brdffit-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return (dir / name).string();
}

// The shared MERL-format proxy `name`, decompressed once per test run.
std::string merl_proxy(const std::string& name) {
  const std::string packed = kShared + "/data/merl-proxy/" + name + ".binary.xz";
  if (!fs::exists(packed)) return "";
  const std::string path = temp_path(name + ".binary");
  if (!fs::exists(path)) {
    const auto r = test::run_command("xz -dkc '" + packed + "' > '" + path + ".part' && mv '" + path + ".part' '" + path + "'");
    EXPECT_EQ(r.exit_code, 0) << r.output;
  }
  return path;
}

// Expects `action` to throw an Error whose message contains every fragment.
template <class Action>
void expect_error(Action&& action, const std::vector<std::string>& fragments) {
  try {
    action();
    ADD_FAILURE() << "expected an error";
  } catch (const Error& e) {
    for (const std::string& f : fragments) EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what();
  }
}

std::string merl_header(int32_t a, int32_t b, int32_t c) {
  std::string bytes(12, '\0');
  const int32_t dims[3] = {a, b, c};
  std::memcpy(bytes.data(), dims, 12);
  return bytes;
}

// --- MERL ------------------------------------------------------------------------------------

TEST(Merl, BakeAndReadRoundTripExactly) {
  const std::string path = temp_path("ggx.binary");
  const auto bake = test::run_cli("bake ggx --param albedo=0.2,0.3,0.4 --param roughness=0.3 --param f0=0.5 --out " + path);
  ASSERT_EQ(bake.exit_code, 0) << bake.output;
  const MerlTable table = MerlTable::read(path);
  EXPECT_EQ(fs::file_size(path), 12u + 3u * 90 * 90 * 180 * 8);
  // Every bin holds the model's f at the bin centre, divided by the channel scale.
  const Model& ggx = *find_model("ggx");
  const std::vector<double> values = parameter_values(ggx, {"albedo=0.2,0.3,0.4", "roughness=0.3", "f0=0.5"});
  const HalfDiffGrid grid = table.grid();
  for (int ih : {0, 7, 45, 89})
    for (int id : {0, 30, 60})
      for (int ip : {0, 90, 179}) {
        Vec3 l, v;
        from_half_diff(grid.centre(ih, id, ip), l, v);
        const size_t bin = table.bin_index(ih, id, ip);
        if (l.z() <= 0 || v.z() <= 0) {
          EXPECT_EQ(table.raw(0, bin), -1.0);
          continue;
        }
        const Rgb<double> f = *ggx.brdf(values.data(), l, v);
        for (int c = 0; c < 3; ++c) EXPECT_EQ(table.raw(c, bin), f[c] / MerlTable::kScale[c]);
        // Nearest lookup at the bin centre returns the bin.
        const Rgb<double> looked_up = table.lookup(l, v, Interpolation::Nearest);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(looked_up[c], f[c], 1e-12 * (1 + f[c]));
      }
  // Writing the read table again gives the same bytes.
  const std::string again = temp_path("ggx-again.binary");
  write_merl(again, [&](const Vec3& l, const Vec3& v) { return *ggx.brdf(values.data(), l, v); });
  EXPECT_EQ(read_file(path), read_file(again));
}

TEST(Merl, LookupsOnSharedProxiesEqualTheRawBins) {
  const std::string path = merl_proxy("gold-metallic-paint");
  if (path.empty()) GTEST_SKIP() << "../shared/data/merl-proxy is absent";
  const std::string bytes = read_file(path);
  const MerlTable table = MerlTable::read(path);
  // Direction pairs built from chosen half/difference angles (φh = 0): d from (θd, φd), l = d
  // rotated by θh about y, v its mirror about h. Their bins, by hand, are iθh = ⌊√(θh/90°)·90⌋,
  // iθd = ⌊θd/90°·90⌋ and iφd = ⌊φd/180°·180⌋; the angles avoid bin edges.
  struct Case {
    Vec3 l, v;
    int ih, id, ip;
  };
  auto pair_from = [](double theta_h_deg, double theta_d_deg, double phi_d_deg, int ih, int id, int ip) {
    const double th = theta_h_deg * kPi / 180, td = theta_d_deg * kPi / 180, pd = phi_d_deg * kPi / 180;
    const Vec3 d(std::sin(td) * std::cos(pd), std::sin(td) * std::sin(pd), std::cos(td));
    const Vec3 h(std::sin(th), 0, std::cos(th));
    const Vec3 l(std::cos(th) * d.x() + std::sin(th) * d.z(), d.y(), -std::sin(th) * d.x() + std::cos(th) * d.z());
    return Case{l, 2 * l.dot(h) * h - l, ih, id, ip};
  };
  const Case cases[] = {pair_from(20.25, 40.5, 90.5, 42, 40, 90),   // √(0.225)·90 = 42.69
                        pair_from(1.0, 10.3, 45.7, 9, 10, 45),      // √(1/90)·90 = 9.49
                        pair_from(50.0, 25.2, 150.2, 67, 25, 150)}; // √(5/9)·90 = 67.08
  for (const Case& c : cases) {
    const size_t bin = (size_t(c.ih) * 90 + c.id) * 180 + c.ip;
    double raw[3];
    for (int ch = 0; ch < 3; ++ch)
      std::memcpy(&raw[ch], bytes.data() + 12 + (ch * size_t(90 * 90 * 180) + bin) * 8, 8);
    const Rgb<double> f = table.lookup(c.l, c.v, Interpolation::Nearest);
    EXPECT_DOUBLE_EQ(f[0], raw[0] / 1500);
    EXPECT_DOUBLE_EQ(f[1], raw[1] * 1.15 / 1500);
    EXPECT_DOUBLE_EQ(f[2], raw[2] * 1.66 / 1500);
  }
  // Trilinear lookups stay within the range of the neighbouring bins and are positive.
  const Rgb<double> t = table.lookup(test::dir(0.3, 0.1, 1), test::dir(-0.2, 0.4, 1), Interpolation::Trilinear);
  EXPECT_TRUE((t.array() > 0).all());
}

TEST(Merl, SamplesCarrySolidAngleWeightsAndRespectOptions) {
  const std::string path = temp_path("lambert.binary");
  ASSERT_EQ(test::run_cli("bake lambert --param albedo=0.5 --out " + path).exit_code, 0);
  const MerlTable table = MerlTable::read(path);
  const SampleSet all = table.samples(SamplingOptions{});
  EXPECT_EQ(all.weighting, "solid-angle");
  double weight_sum = 0.0;
  for (const Sample& s : all.samples) {
    weight_sum += s.weight;
    ASSERT_NEAR(s.value[0], 0.5 / kPi * s.l.z(), 1e-12);  // values are f·cosθi
  }
  // The weights measure pairs of directions: ∫∫ dωi dωo over both hemispheres is (2π)², and the
  // φd half-range (reciprocity) counts each pair once, so the sum is about (2π)²/2.
  EXPECT_NEAR(weight_sum, 2 * kPi * kPi, 0.05 * 2 * kPi * kPi);
  const SampleSet limited = table.samples(SamplingOptions{80.0, 0, 1});
  for (const Sample& s : limited.samples) ASSERT_GE(std::min(s.l.z(), s.v.z()), std::cos(80 * kPi / 180) - 1e-12);
  EXPECT_LT(limited.size(), all.size());
  const SampleSet a = table.samples(SamplingOptions{90.0, 1000, 7}), b = table.samples(SamplingOptions{90.0, 1000, 7});
  ASSERT_EQ(a.size(), 1000u);
  for (size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a.samples[i].l, b.samples[i].l);
}

TEST(Merl, RejectsMalformedFilesWithTheFileAndProblem) {
  const std::string good = merl_header(90, 90, 180) + std::string(3 * 90 * 90 * 180 * 8, '\0');
  expect_error([] { MerlTable::parse("abc", "tiny.binary"); }, {"tiny.binary", "shorter than the 12-byte header"});
  expect_error([] { MerlTable::parse(merl_header(90, 90, 90) + "xxxx", "dims.binary"); }, {"dims.binary", "90x90x90"});
  expect_error([&] { MerlTable::parse(good.substr(0, good.size() - 8), "short.binary"); }, {"short.binary", "truncated"});
  expect_error([&] { MerlTable::parse(good + "x", "long.binary"); }, {"long.binary", "oversized", "1 extra"});
  std::string with_nan = good;
  const double nan = NAN;
  std::memcpy(with_nan.data() + 12 + 8 * 5, &nan, 8);
  std::memcpy(with_nan.data() + 12 + 8 * 9, &nan, 8);
  expect_error([&] { MerlTable::parse(with_nan, "nan.binary"); }, {"nan.binary", "2 NaN or infinite"});
  expect_error([] { MerlTable::read("/nonexistent/x.binary"); }, {"/nonexistent/x.binary", "cannot open"});
  // Negative bins are counted as invalid, not dropped silently.
  std::string negative = good;
  const double minus_one = -1.0;
  std::memcpy(negative.data() + 12 + 8 * 3, &minus_one, 8);
  EXPECT_EQ(MerlTable::parse(negative, "neg.binary").info().invalid, 1u);
  // 360 φd bins are accepted.
  EXPECT_EQ(MerlTable::parse(merl_header(90, 90, 360) + std::string(3 * 90 * 90 * 360 * 8, '\0'), "wide.binary")
                .phi_d_bins(),
            360);
}

// --- RGL -------------------------------------------------------------------------------------

std::vector<std::string> rgl_files() {
  std::vector<std::string> files;
  const fs::path dir = kShared + "/data/rgl";
  if (fs::exists(dir))
    for (const auto& entry : fs::directory_iterator(dir))
      if (entry.path().extension() == ".bsdf") files.push_back(entry.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

TEST(Rgl, MatchesThePublicLoader) {
  // f(wi, wo) computed with the RGL loader (powitacq_rgb, RGB clipped at 0) for these files and
  // directions (wi, wo not normalised).
  struct Reference {
    const char* file;
    Vec3 wi, wo;
    Rgb<double> f;
  };
  const Reference references[] = {
      {"cc_ibiza_sunset_rgb.bsdf", {0.3, -0.2, 1}, {-0.4, 0.1, 0.8}, {0.729462743, 0.287705481, 0.388631165}},
      {"cc_ibiza_sunset_rgb.bsdf", {1, 0, 1}, {-1, 0, 1}, {2.46805429, 1.27064264, 0.944497049}},
      {"cc_ibiza_sunset_rgb.bsdf", {0, 0.9, 0.3}, {0.1, -0.8, 0.5}, {0.496618569, 0.28788951, 0.0699345693}},
      {"acrylic_felt_green_rgb.bsdf", {0, 0, 1}, {1, 1, 1}, {0.0167185627, 0.0375518166, 0.00476824259}},
      {"acrylic_felt_green_rgb.bsdf", {0.5, 0.5, 0.7}, {0.2, -0.6, 0.5}, {0.0251786318, 0.0508974306, 0.00681251427}},
      {"paper_white_rgb.bsdf", {0.3, -0.2, 1}, {-0.4, 0.1, 0.8}, {0.239509389, 0.242829323, 0.282479435}},
      {"vch_golden_yellow_rgb.bsdf", {1, 0, 1}, {-1, 0, 1}, {5.76215267, 2.9787271, 0}},
      {"cc_iris_purple_gem_rgb.bsdf", {1, 0, 1}, {-1, 0, 1}, {2.81532049, 2.05037189, 3.67765903}},
      {"colodur_napoli_4f_rgb.bsdf", {0, 0.9, 0.3}, {0.1, -0.8, 0.5}, {0.114489429, 0.0755852759, 0.0736019537}},
  };
  if (rgl_files().empty()) GTEST_SKIP() << "../shared/data/rgl is absent";
  for (const Reference& r : references) {
    SCOPED_TRACE(r.file);
    const RglBrdf brdf = RglBrdf::read(kShared + "/data/rgl/" + r.file);
    const Rgb<double> f = brdf.eval(r.wi.normalized(), r.wo.normalized());
    // The loader computes in float32.
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], r.f[c], 2e-5 * (1 + r.f[c]));
  }
}

TEST(Rgl, AlbedoAtMostOneAndApproximatelyReciprocal) {
  const std::vector<std::string> files = rgl_files();
  if (files.empty()) GTEST_SKIP() << "../shared/data/rgl is absent";
  std::mt19937_64 rng(3);
  for (const std::string& path : files) {
    SCOPED_TRACE(path);
    const RglBrdf brdf = RglBrdf::read(path);
    EXPECT_TRUE(brdf.isotropic());
    for (double theta_deg : {0.0, 30.0, 60.0, 75.0}) {
      const double t = theta_deg * kPi / 180;
      const Rgb<double> albedo = directional_albedo(brdf, Vec3(std::sin(t), 0, std::cos(t)));
      EXPECT_LE(albedo.maxCoeff(), 1.0 + 0.02) << theta_deg;
      EXPECT_GT(albedo.minCoeff(), 0.0) << theta_deg;
    }
    // Measured data is reciprocal only approximately: the tables are indexed by the incident
    // direction on a coarse θi grid. Σ|f(l,v) - f(v,l)| / Σ f over random pairs (n·l, n·v ≥ 0.2)
    // is 0.16 to 0.44 for these six files with the public RGL loader too.
    double difference = 0.0, magnitude = 0.0;
    for (int i = 0; i < 400; ++i) {
      const Vec3 l = test::random_upper_direction(rng, 0.2), v = test::random_upper_direction(rng, 0.2);
      const Rgb<double> a = brdf.eval(l, v), b = brdf.eval(v, l);
      difference += (a - b).cwiseAbs().sum();
      magnitude += (a + b).sum() / 2;
    }
    EXPECT_LT(difference / magnitude, 0.5);
  }
}

TEST(Rgl, GridLookupsClampCoordinatesOutsideTheUnitSquare) {
  // Found by fuzzing: a malformed VNDF warp can map to coordinates far outside [0,1] (or NaN);
  // lookups clamp them to the grid instead of converting them to out-of-range indices.
  const ParametricGrid2D grid(2, 2, {1, 2, 3, 4}, {}, false);
  EXPECT_EQ(grid.eval(0.0, 0.0, nullptr), 1.0);
  EXPECT_EQ(grid.eval(1.0, 1.0, nullptr), 4.0);
  EXPECT_EQ(grid.eval(4.9e42, -3e9, nullptr), 2.0);
  EXPECT_EQ(grid.eval(NAN, 0.5, nullptr), 2.0);
  const ParametricGrid2D warp(2, 2, {1, 1, 1, 1}, {}, true);
  const std::array<double, 2> inverted = warp.invert(1e300, -1e300, nullptr);
  EXPECT_TRUE(std::isfinite(inverted[0]) && std::isfinite(inverted[1]));
}

TEST(Rgl, RejectsMalformedTensorFiles) {
  expect_error([] { RglBrdf::parse("not a tensor file at all", "bad.bsdf"); }, {"bad.bsdf", "not a tensor file"});
  const std::string header = std::string("tensor_file\0", 12) + std::string("\x01\x00", 2);
  expect_error([&] { RglBrdf::parse(header, "short.bsdf"); }, {"short.bsdf", "truncated", "field count"});
  // A file with no fields lacks the ones an RGL BRDF needs.
  std::string empty = header + std::string(4, '\0');
  expect_error([&] { RglBrdf::parse(empty, "empty.bsdf"); }, {"empty.bsdf", "missing field 'theta_i'"});
  // One field whose data lies beyond the end of the file.
  std::string field = header;
  const uint32_t count = 1;
  field.append(reinterpret_cast<const char*>(&count), 4);
  const uint16_t name_length = 7, rank = 1;
  const uint8_t type = 10;  // float32
  const uint64_t offset = 1000, extent = 4;
  field.append(reinterpret_cast<const char*>(&name_length), 2).append("theta_i");
  field.append(reinterpret_cast<const char*>(&rank), 2).append(reinterpret_cast<const char*>(&type), 1);
  field.append(reinterpret_cast<const char*>(&offset), 8).append(reinterpret_cast<const char*>(&extent), 8);
  expect_error([&] { RglBrdf::parse(field, "beyond.bsdf"); }, {"beyond.bsdf", "truncated", "theta_i"});
  // A real file cut short.
  const std::vector<std::string> files = rgl_files();
  if (!files.empty()) {
    const std::string bytes = read_file(files[0]);
    expect_error([&] { RglBrdf::parse(bytes.substr(0, bytes.size() / 2), "half.bsdf"); }, {"half.bsdf", "truncated"});
  }
}

// --- CSV -------------------------------------------------------------------------------------

TEST(Csv, ReadsBothFormsAndStoresFCosThetaI) {
  const SampleSet angles = parse_csv_samples(
      "# measured by hand\n# unit: degrees\ntheta_i,phi_i,theta_o,phi_o,r,g,b\n60,0,30,180,0.2,0.3,0.4\n", "a.csv");
  ASSERT_EQ(angles.size(), 1u);
  EXPECT_NEAR(angles.samples[0].l.z(), 0.5, 1e-12);
  EXPECT_NEAR(angles.samples[0].v.x(), -0.5, 1e-12);
  EXPECT_NEAR(angles.samples[0].value[1], 0.3 * 0.5, 1e-12);
  const SampleSet vectors = parse_csv_samples("lx,ly,lz,vx,vy,vz,r,g,b,weight\n0,0,2,1,0,1,1,1,1,3\n", "v.csv");
  ASSERT_EQ(vectors.size(), 1u);
  EXPECT_EQ(vectors.samples[0].weight, 3.0);
  EXPECT_NEAR(vectors.samples[0].v.x(), std::sqrt(0.5), 1e-12);
  // Round trip through the writer.
  const SampleSet again = parse_csv_samples(format_csv_samples(vectors), "again.csv");
  EXPECT_NEAR(again.samples[0].value[0], vectors.samples[0].value[0], 1e-15);
}

TEST(Csv, RejectsMalformedInputNamingFileAndLine) {
  expect_error([] { parse_csv_samples("", "e.csv"); }, {"e.csv", "no CSV header"});
  expect_error([] { parse_csv_samples("a,b,c\n", "h.csv"); }, {"h.csv:1", "unrecognised header"});
  expect_error([] { parse_csv_samples("theta_i,phi_i,theta_o,phi_o,r,g,b\n", "u.csv"); }, {"u.csv:1", "unit"});
  expect_error([] { parse_csv_samples("lx,ly,lz,vx,vy,vz,r,g,b\n0,0,1,0,0,1,1,1\n", "n.csv"); }, {"n.csv:2", "8 fields"});
  expect_error([] { parse_csv_samples("lx,ly,lz,vx,vy,vz,r,g,b\n0,0,1,0,0,1,1,nan,1\n", "nan.csv"); },
               {"nan.csv:2", "not a finite number"});
  expect_error([] { parse_csv_samples("lx,ly,lz,vx,vy,vz,r,g,b\n0,0,1,0,0,1,1,x,1\n", "x.csv"); }, {"x.csv:2", "'x'"});
  expect_error([] { parse_csv_samples("lx,ly,lz,vx,vy,vz,r,g,b\n0,0,-1,0,0,1,1,1,1\n", "b.csv"); },
               {"b.csv:2", "below the horizon"});
  expect_error([] { parse_csv_samples("lx,ly,lz,vx,vy,vz,r,g,b\n", "none.csv"); }, {"none.csv", "no samples"});
}

// --- commands ----------------------------------------------------------------------------------

TEST(TableCli, InfoLookupAndBake) {
  const std::string path = temp_path("info.binary");
  ASSERT_EQ(test::run_cli("bake lambert --param albedo=0.5,0.25,0.125 --out " + path).exit_code, 0);
  const auto info = test::run_cli("info " + path + " --json");
  ASSERT_EQ(info.exit_code, 0) << info.output;
  const nlohmann::json j = nlohmann::json::parse(info.output);
  EXPECT_EQ(j["format"], "merl");
  EXPECT_EQ(j["resolution"], "90x90x180");
  EXPECT_EQ(j["valid"].get<size_t>() + j["invalid"].get<size_t>(), 90u * 90 * 180);
  // Lambert: f = albedo/π everywhere; directional albedo = albedo (quadrature tolerance).
  EXPECT_NEAR(j["max"][0].get<double>(), 0.5 / kPi, 1e-12);
  EXPECT_NEAR(j["albedo"][1].get<double>(), 0.25, 0.01);
  const auto lookup = test::run_cli("lookup " + path + " --light 0.2,0.1,1 --view -0.3,0,1 --json");
  ASSERT_EQ(lookup.exit_code, 0) << lookup.output;
  EXPECT_NEAR(nlohmann::json::parse(lookup.output)["brdf"][2].get<double>(), 0.125 / kPi, 1e-12);
  for (const char* bad : {"info /nonexistent.binary", "lookup /nonexistent.binary --light 0,0,1 --view 0,0,1",
                          "bake nosuchmodel --out /tmp/x.binary", "bake ggx --param roughness=7 --out /tmp/x.binary"}) {
    const auto r = test::run_cli(bad);
    EXPECT_NE(r.exit_code, 0) << bad;
    EXPECT_NE(r.output.find("error"), std::string::npos) << bad;
  }
}

TEST(TableCli, AFailedWriteLeavesTheExistingFileWhole) {
  // /proc/version exists, but nothing can be created beside it (even by root): the write fails
  // before the existing file is touched, with a message naming it.
  const std::string before = read_file("/proc/version");
  const auto r = test::run_cli("bake lambert --out /proc/version");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("/proc/version: cannot write"), std::string::npos) << r.output;
  EXPECT_EQ(read_file("/proc/version"), before);
  // A model error is reported before anything is written.
  const std::string path = temp_path("never.binary");
  EXPECT_NE(test::run_cli("bake ggx --param roughness=5 --out " + path).exit_code, 0);
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace brdffit
