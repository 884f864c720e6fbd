// MERL tables: reading, lookups against raw bins, writing, samples and rejected files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "brdffit/io.h"
#include "brdffit/measured.h"
#include "brdffit/merl.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"
#include "tables_test_util.h"

namespace brdffit {
namespace {

using test::expect_error;
using test::scratch_path;

constexpr size_t kBins = 90 * 90 * 180;

std::string merl_header(int32_t a, int32_t b, int32_t c) {
  std::string bytes(12, '\0');
  const int32_t dims[3] = {a, b, c};
  std::memcpy(bytes.data(), dims, 12);
  return bytes;
}

// A 90x90x180 file whose every value is `value`.
std::string constant_merl_file(double value) {
  std::string bytes = merl_header(90, 90, 180);
  for (size_t i = 0; i < 3 * kBins; ++i) bytes.append(reinterpret_cast<const char*>(&value), sizeof value);
  return bytes;
}

void put_double(std::string& bytes, size_t value_index, double value) {
  std::memcpy(bytes.data() + 12 + 8 * value_index, &value, 8);
}

using test::pair_from_angles;
using test::raw_bin;
using test::raw_f;

using test::expect_rgb_near;

// --- reading and lookups on the shared proxies ---------------------------------------------------

class MerlProxy : public ::testing::TestWithParam<const char*> {};

TEST_P(MerlProxy, LookupsEqualTheRawBins) {
  const std::string path = test::merl_proxy(GetParam());
  SKIP_UNLESS_SHARED(!path.empty(), "the shared MERL proxies (" << test::kSharedDir << "/data/merl-proxy)");
  const std::string bytes = read_file(path);
  const MerlTable table = MerlTable::read(path);
  EXPECT_EQ(table.phi_d_bins(), 180);

  // The bin of each pair, worked out by hand from MERL's index formulas:
  // iθh = ⌊√(θh/90°)·90⌋, iθd = ⌊θd/90°·90⌋, iφd = ⌊(φd mod 180°)/180°·180⌋.
  struct Case {
    Vec3 l, v;
    int ih, id, ip;
  };
  auto angles = [](double th, double td, double pd, double ph, int ih, int id, int ip) {
    const auto [l, v] = pair_from_angles(th, td, pd, ph);
    return Case{l, v, ih, id, ip};
  };
  const Case cases[] = {
      angles(20.25, 40.5, 90.5, 0, 42, 40, 90),      // √0.225·90 = 42.69
      angles(1.0, 10.3, 45.7, 37, 9, 10, 45),        // √(1/90)·90 = 9.49; φh does not matter
      angles(50.0, 25.2, 150.2, -120, 67, 25, 150),  // √(5/9)·90 = 67.08
      angles(5.0, 60.4, 200.3, 10, 21, 60, 20),      // √(1/18)·90 = 21.21; φd 200.3° ≡ 20.3°
      angles(30.0, 5.5, 300.8, 200, 51, 5, 120),     // √(1/3)·90 = 51.96; φd 300.8° ≡ 120.8°
      angles(0.3, 0.7, 10.5, 0, 5, 0, 10),           // near the normal: √(1/300)·90 = 5.20
      angles(70.0, 15.4, 90.4, 45, 79, 15, 90),      // √(7/9)·90 = 79.37, both directions at ~71°
      // Plain (unnormalised) vectors; h = normalize(l̂ + v̂), θh = acos(h_z), θd = acos(l̂·h) and
      // φd from l̂'s components along t and b as above:
      {{0.7, 0.1, 0.3}, {-0.6, 0.0, 0.5}, 30, 58, 142},   // θh 22.96° (u 30.93), θd 58.37°, φd 142.62°
      {{0.2, 0.6, 1}, {0.25, 0.5, 1}, 52, 2, 53},         // u 52.56, θd 2.59°, φd 53.11°
      {{0.5, -0.3, 0.8}, {-0.4, 0.15, 0.9}, 23, 30, 29},  // u 23.52, θd 30.60°, φd 29.09°
      {{0.1, 0.05, 1}, {-0.3, 0.2, 1}, 28, 11, 32},       // u 28.17, θd 11.81°, φd -147.80° ≡ 32.20°
      {{-0.8, -0.2, 0.4}, {0.3, 0.5, 0.6}, 51, 48, 67},   // u 51.08, θd 48.75°, φd 67.34°
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(::testing::Message() << "bin " << c.ih << "," << c.id << "," << c.ip);
    const Rgb<double> expected = raw_f(bytes, c.ih, c.id, c.ip);
    ASSERT_TRUE((expected.array() >= 0).all()) << "the chosen bins hold measurements";
    const Rgb<double> nearest = table.lookup(c.l, c.v, Interpolation::Nearest);
    for (int ch = 0; ch < 3; ++ch) EXPECT_DOUBLE_EQ(nearest[ch], expected[ch]) << "channel " << ch;
  }

  // Trilinear: at a bin centre, the bin; between centres, the weighted bins around.
  auto centre_deg = [](int ih, int id, int ip) {
    const double u = (ih + 0.5) / 90;
    return std::array<double, 3>{u * u * 90, id + 0.5, ip + 0.5};
  };
  for (const auto& [ih, id, ip] : {std::array<int, 3>{42, 40, 90}, {9, 10, 45}, {67, 25, 150}}) {
    const auto [th, td, pd] = centre_deg(ih, id, ip);
    const auto [l, v] = pair_from_angles(th, td, pd, 20);
    expect_rgb_near(table.lookup(l, v, Interpolation::Trilinear), raw_f(bytes, ih, id, ip), 1e-9);
    // Halfway between two θd centres, then between two φd centres.
    const auto [l_d, v_d] = pair_from_angles(th, td + 0.5, pd, 20);
    expect_rgb_near(table.lookup(l_d, v_d, Interpolation::Trilinear),
                    0.5 * (raw_f(bytes, ih, id, ip) + raw_f(bytes, ih, id + 1, ip)), 1e-9);
    const auto [l_p, v_p] = pair_from_angles(th, td, pd + 0.25, 20);
    expect_rgb_near(table.lookup(l_p, v_p, Interpolation::Trilinear),
                    0.75 * raw_f(bytes, ih, id, ip) + 0.25 * raw_f(bytes, ih, id, ip + 1), 1e-9);
  }
  // A general point: u = √(θh/90°)·90 = 42.8 (0.3 past centre 42 at 42.5), θd 40.9° (0.4 past
  // centre 40 at 40.5°), φd 90.2° (0.7 past centre 89 at 89.5°).
  const double u = 42.8 / 90;
  const auto [l, v] = pair_from_angles(u * u * 90, 40.9, 90.2, -60);
  Rgb<double> expected = Rgb<double>::Zero();
  for (int corner = 0; corner < 8; ++corner) {
    const int dh = corner & 1, dd = (corner >> 1) & 1, dp = (corner >> 2) & 1;
    const double w = (dh ? 0.3 : 0.7) * (dd ? 0.4 : 0.6) * (dp ? 0.7 : 0.3);
    expected += w * raw_f(bytes, 42 + dh, 40 + dd, 89 + dp);
  }
  expect_rgb_near(table.lookup(l, v, Interpolation::Trilinear), expected, 1e-9);
  // eval is the trilinear lookup; below the horizon f is zero.
  EXPECT_EQ(table.eval(l, v), table.lookup(l, v, Interpolation::Trilinear));
  EXPECT_TRUE(table.eval(Vec3(0.3, 0, -1), v).isZero());
}

TEST_P(MerlProxy, WritingATableReadBackGivesTheSameBytes) {
  const std::string path = test::merl_proxy(GetParam());
  SKIP_UNLESS_SHARED(!path.empty(), "the shared MERL proxies (" << test::kSharedDir << "/data/merl-proxy)");
  const std::string copy = scratch_path(std::string(GetParam()) + "-copy.binary");
  MerlTable::read(path).write(copy);
  EXPECT_TRUE(read_file(copy) == read_file(path));
}

TEST_P(MerlProxy, InfoCountsBinsAndGivesAPlausibleAlbedo) {
  const std::string path = test::merl_proxy(GetParam());
  SKIP_UNLESS_SHARED(!path.empty(), "the shared MERL proxies (" << test::kSharedDir << "/data/merl-proxy)");
  const std::string bytes = read_file(path);
  size_t negative = 0;
  for (size_t bin = 0; bin < kBins; ++bin) {
    double r, g, b;
    std::memcpy(&r, bytes.data() + 12 + bin * 8, 8);
    std::memcpy(&g, bytes.data() + 12 + (kBins + bin) * 8, 8);
    std::memcpy(&b, bytes.data() + 12 + (2 * kBins + bin) * 8, 8);
    negative += r < 0 || g < 0 || b < 0;
  }
  const TableInfo info = MerlTable::read(path).info();
  EXPECT_EQ(info.format, "merl");
  EXPECT_EQ(info.resolution, "90x90x180");
  EXPECT_EQ(info.invalid, negative);
  EXPECT_EQ(info.valid + info.invalid, kBins);
  EXPECT_TRUE((info.albedo.array() > 0).all() && (info.albedo.array() < 1).all()) << info.albedo.transpose();
  EXPECT_TRUE((info.min.array() >= 0).all() && (info.max.array() > info.min.array()).all());
}

INSTANTIATE_TEST_SUITE_P(Merl, MerlProxy, ::testing::Values("gold-metallic-paint", "blue-acrylic", "red-fabric"),
                         [](const auto& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

// --- writing ----------------------------------------------------------------------------------

TEST(Merl, BakeAndReadRoundTripExactly) {
  const std::string path = scratch_path("ggx.binary");
  const auto bake =
      test::run_cli("bake -m ggx --param albedo=0.2,0.3,0.4 --param roughness=0.3 --param f0=0.5 --out " + path);
  ASSERT_EQ(bake.exit_code, 0) << bake.output;
  EXPECT_EQ(test::fs::file_size(path), 12u + 3u * kBins * 8);
  // Every bin holds the model's f at the bin centre divided by the channel scale: the centre's
  // directions from the angles by hand (u = (iθh+½)/90, θh = u²·90°, θd = iθd+½°, φd = iφd+½°),
  // the value from the file's bytes; bins with a direction below the horizon hold -1.
  const std::string bytes = read_file(path);
  const Model& ggx = *find_model("ggx");
  const std::vector<double> values = parameter_values(ggx, {"albedo=0.2,0.3,0.4", "roughness=0.3", "f0=0.5"});
  int checked = 0, below = 0;
  for (int ih : {0, 1, 7, 45, 89})
    for (int id : {0, 30, 60, 89})
      for (int ip : {0, 90, 179}) {
        const double u = (ih + 0.5) / 90;
        const auto [l, v] = pair_from_angles(u * u * 90, id + 0.5, ip + 0.5, 0.0);
        if (l.z() <= 0 || v.z() <= 0) {
          for (int c = 0; c < 3; ++c) EXPECT_EQ(raw_bin(bytes, c, ih, id, ip), -1.0);
          ++below;
          continue;
        }
        ++checked;
        const Rgb<double> f = *ggx.brdf(values.data(), l, v);
        expect_rgb_near(raw_f(bytes, ih, id, ip), f, 1e-9);
      }
  EXPECT_GT(checked, 20);
  EXPECT_GT(below, 5);
  // Read and written again: the same bytes.
  const MerlTable table = MerlTable::read(path);
  const std::string again = scratch_path("ggx-again.binary");
  table.write(again);
  EXPECT_TRUE(read_file(again) == bytes);
}

TEST(Merl, WritesAndReads360PhiDBins) {
  // A function of φd alone over [0, 2π): 360 bins keep φd and φd+π apart.
  const std::string path = scratch_path("wide.binary");
  auto f = [](const Vec3& l, const Vec3& v) {
    const double phi_d = to_half_diff(l, v).phi_d;
    return Rgb<double>(1 + std::cos(phi_d), 1 + std::sin(phi_d), 1);
  };
  write_merl(path, f, 360);
  const MerlTable table = MerlTable::read(path);
  ASSERT_EQ(table.phi_d_bins(), 360);
  for (double phi_d_deg : {10.5, 100.5, 190.5, 280.5}) {  // bin centres
    const auto [l, v] = pair_from_angles(20, 30.5, phi_d_deg, 0);
    expect_rgb_near(table.lookup(l, v, Interpolation::Nearest), f(l, v), 1e-12);
    expect_rgb_near(table.lookup(l, v, Interpolation::Trilinear), f(l, v), 1e-9);
  }
}

TEST(Merl, RefusesToWriteValuesThatWouldReadAsMissing) {
  const std::string path = scratch_path("negative.binary");
  expect_error([&] { write_merl(path, [](const Vec3&, const Vec3&) { return Rgb<double>(0.1, -0.2, 0.1); }); },
               {path, "-0.2", "non-negative"});
  expect_error([&] { write_merl(path, [](const Vec3&, const Vec3&) { return Rgb<double>(0.1, NAN, 0.1); }); },
               {path, "finite"});
  expect_error(
      [&] {
        write_merl(
            path, [](const Vec3&, const Vec3&) { return Rgb<double>(0.1, 0.1, 0.1); }, 90);
      },
      {path, "180 or 360"});
  EXPECT_FALSE(test::fs::exists(path));
}

// --- samples ----------------------------------------------------------------------------------

TEST(Merl, SamplesCarrySolidAngleWeightsAndRespectOptions) {
  const std::string path = scratch_path("lambert.binary");
  ASSERT_EQ(test::run_cli("bake -m lambert --param albedo=0.5 --out " + path).exit_code, 0);
  const MerlTable table = MerlTable::read(path);
  const SampleSet all = table.samples(SamplingOptions{});
  EXPECT_EQ(all.weighting, "solid-angle");
  EXPECT_EQ(all.size(), table.bins() - table.invalid_bins());
  double weight_sum = 0.0;
  for (const Sample& s : all.samples) {
    weight_sum += s.weight;
    ASSERT_GT(s.weight, 0.0);
    ASSERT_NEAR(s.value[0], 0.5 / kPi * s.l.z(), 1e-12);  // values are f·cosθi
  }
  // The weights measure pairs of directions: ∫∫ dωi dωo over the upper hemisphere twice is
  // (2π)², and the φd half-range (reciprocity) counts each unordered pair once: 2π².
  EXPECT_NEAR(weight_sum, 2 * kPi * kPi, 0.03 * 2 * kPi * kPi);
  // The √-spaced θh bins: the first bins are tiny, so are their weights.
  const HalfDiffGrid grid = table.grid();
  EXPECT_LT(grid.weight(0, 45, 0), 1e-4 * grid.weight(89, 45, 0));

  // Ngan et al. drop directions beyond 80°.
  const SampleSet limited = table.samples(SamplingOptions{80.0, 0, 1});
  for (const Sample& s : limited.samples) ASSERT_GE(std::min(s.l.z(), s.v.z()), std::cos(80 * kPi / 180) - 1e-12);
  EXPECT_LT(limited.size(), all.size());
  EXPECT_GT(limited.size(), all.size() / 2);

  // Subsets: the requested size, the same for the same seed, different for another seed.
  const SampleSet a = table.samples(SamplingOptions{80.0, 1000, 7}), b = table.samples(SamplingOptions{80.0, 1000, 7});
  const SampleSet c = table.samples(SamplingOptions{80.0, 1000, 8});
  ASSERT_EQ(a.size(), 1000u);
  ASSERT_EQ(c.size(), 1000u);
  size_t same_as_other_seed = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a.samples[i].l, b.samples[i].l);
    ASSERT_EQ(a.samples[i].v, b.samples[i].v);
    same_as_other_seed += a.samples[i].l == c.samples[i].l;
    ASSERT_GE(std::min(a.samples[i].l.z(), a.samples[i].v.z()), std::cos(80 * kPi / 180) - 1e-12);
  }
  EXPECT_LT(same_as_other_seed, 100u);
  EXPECT_EQ(table.samples(SamplingOptions{90.0, 5 * all.size(), 1}).size(), all.size());
}

TEST(Merl, SamplesSkipBinsWithoutAMeasurement) {
  std::string bytes = constant_merl_file(0.3 * 1500);
  const MerlTable full = MerlTable::parse(bytes, "full.binary");
  // Mark one bin above the horizon (iθh 42, iθd 40, iφd 90) as unmeasured in one channel.
  put_double(bytes, kBins + (size_t(42) * 90 + 40) * 180 + 90, -1.0);
  const MerlTable holed = MerlTable::parse(bytes, "holed.binary");
  EXPECT_EQ(holed.invalid_bins(), full.invalid_bins() + 1);
  EXPECT_EQ(holed.samples(SamplingOptions{}).size() + 1, full.samples(SamplingOptions{}).size());
  // Lookups: nearest gives no value, trilinear fills from the neighbours.
  const auto [l, v] = pair_from_angles(std::pow(42.5 / 90, 2) * 90, 40.5, 90.5, 0);
  EXPECT_TRUE(holed.lookup(l, v, Interpolation::Nearest).isZero());
  expect_rgb_near(holed.lookup(l, v, Interpolation::Trilinear), Rgb<double>(0.3, 0.3 * 1.15, 0.3 * 1.66), 1e-9);
}

// --- rejected files ---------------------------------------------------------------------------

TEST(Merl, RejectsMalformedFilesNamingTheFileAndTheProblem) {
  const std::string good = constant_merl_file(1.0);
  expect_error([] { MerlTable::parse("abc", "tiny.binary"); },
               {"tiny.binary", "3 bytes", "shorter than the 12-byte header"});
  expect_error([] { MerlTable::parse(merl_header(90, 90, 90) + "xxxx", "dims.binary"); },
               {"dims.binary", "dimensions 90x90x90", "expected 90x90x180 or 90x90x360"});
  expect_error([] { MerlTable::parse(merl_header(-90, 90, 180), "negative-dims.binary"); },
               {"negative-dims.binary", "dimensions -90x90x180"});
  expect_error([&] { MerlTable::parse(good.substr(0, good.size() - 8), "short.binary"); },
               {"short.binary", "truncated", std::to_string(good.size() - 8) + " bytes", std::to_string(good.size())});
  expect_error([&] { MerlTable::parse(merl_header(90, 90, 180), "header-only.binary"); },
               {"header-only.binary", "truncated", "12 bytes"});
  expect_error([&] { MerlTable::parse(good + "x", "long.binary"); }, {"long.binary", "oversized", "1 extra"});
  std::string bad_values = good;
  put_double(bad_values, 5, NAN);
  put_double(bad_values, 9, NAN);
  put_double(bad_values, 2 * kBins + 3, INFINITY);
  expect_error([&] { MerlTable::parse(bad_values, "nan.binary"); },
               {"nan.binary", "2 NaN and 1 infinite values", "channel R of bin 5"});
  expect_error([] { MerlTable::read("/nonexistent/x.binary"); }, {"/nonexistent/x.binary", "cannot open"});
  expect_error([] { open_measured("/nonexistent/x.binary"); }, {"/nonexistent/x.binary", "cannot open"});
  // The dispatcher hands a .binary of the wrong shape to the MERL reader, whose message says why.
  const std::string wrong = scratch_path("wrong.binary");
  test::write_bytes(wrong, merl_header(45, 45, 90) + std::string(64, '\0'));
  expect_error([&] { open_measured(wrong); }, {wrong, "dimensions 45x45x90"});
  expect_error([&] { load_samples(wrong, SamplingOptions{}); }, {wrong, "dimensions 45x45x90"});

  // Negative bins are counted as invalid, not dropped silently; 360 φd bins are accepted.
  std::string negative = good;
  put_double(negative, 3, -1.0);
  put_double(negative, kBins + 3, -1.0);  // the same bin in G: still one bin
  put_double(negative, 2 * kBins + 4, -0.5);
  EXPECT_EQ(MerlTable::parse(negative, "neg.binary").invalid_bins(), 2u);
  EXPECT_EQ(
      MerlTable::parse(merl_header(90, 90, 360) + std::string(3 * kBins * 2 * 8, '\0'), "wide.binary").phi_d_bins(),
      360);
}

}  // namespace
}  // namespace brdffit
