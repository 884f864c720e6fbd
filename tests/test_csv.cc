// Tabulated samples as CSV: both header forms, what samples store, and rejected input.
#include <gtest/gtest.h>

#include <cmath>

#include "brdffit/csv_samples.h"
#include "brdffit/measured.h"
#include "tables_test_util.h"

namespace brdffit {
namespace {

using test::expect_error;

TEST(Csv, ReadsAnglesInDegreesOrRadiansAndStoresFCosThetaI) {
  const SampleSet degrees = parse_csv_samples(
      "# measured by hand\n# unit: degrees\ntheta_i,phi_i,theta_o,phi_o,r,g,b\n60,0,30,180,0.2,0.3,0.4\n", "a.csv");
  ASSERT_EQ(degrees.size(), 1u);
  EXPECT_EQ(degrees.source, "a.csv");
  EXPECT_EQ(degrees.weighting, "uniform");
  const Sample& s = degrees.samples[0];
  EXPECT_NEAR(s.l.x(), std::sqrt(3.0) / 2, 1e-12);
  EXPECT_NEAR(s.l.z(), 0.5, 1e-12);
  EXPECT_NEAR(s.v.x(), -0.5, 1e-12);
  EXPECT_NEAR(s.v.y(), 0.0, 1e-12);
  EXPECT_NEAR(s.v.z(), std::sqrt(3.0) / 2, 1e-12);
  EXPECT_NEAR(s.value[0], 0.2 * 0.5, 1e-12);  // f·cosθi
  EXPECT_NEAR(s.value[2], 0.4 * 0.5, 1e-12);
  EXPECT_EQ(s.weight, 1.0);
  const SampleSet radians = parse_csv_samples(
      "#unit:radians\ntheta_i,phi_i,theta_o,phi_o,r,g,b,weight\n1.0471975511965976,0,0.5235987755982988,"
      "3.141592653589793,0.2,0.3,0.4,2.5\n",
      "r.csv");
  ASSERT_EQ(radians.size(), 1u);
  EXPECT_LT((radians.samples[0].l - s.l).norm(), 1e-12);
  EXPECT_LT((radians.samples[0].v - s.v).norm(), 1e-12);
  EXPECT_EQ(radians.samples[0].weight, 2.5);
  EXPECT_EQ(radians.weighting, "from file");
}

TEST(Csv, ReadsDirectionVectorsWithOptionalWeights) {
  // Not unit length; spaces, a CRLF line end, a byte order mark, '+' signs and comments are fine.
  const SampleSet set = parse_csv_samples(
      "\xEF\xBB\xBFlx, ly, lz, vx, vy, vz, r, g, b, weight\r\n0,0,2,1,0,1,1,0.5,0.25,3\r\n# a comment\n\n"
      "+0.6, 0, 0.8, 0, -0.6, 0.8, 1e-1, 2E-1, .3, 0\n",
      "v.csv");
  ASSERT_EQ(set.size(), 2u);
  EXPECT_EQ(set.samples[0].weight, 3.0);
  EXPECT_EQ(set.samples[0].l, Vec3(0, 0, 1));
  EXPECT_NEAR(set.samples[0].v.x(), std::sqrt(0.5), 1e-15);
  EXPECT_EQ(set.samples[0].value, Rgb<double>(1, 0.5, 0.25));  // cosθi = 1
  EXPECT_NEAR(set.samples[1].value[2], 0.3 * 0.8, 1e-15);
  EXPECT_EQ(set.samples[1].weight, 0.0);
  const SampleSet unweighted = parse_csv_samples("lx,ly,lz,vx,vy,vz,r,g,b\n0,0,1,0,0,1,1,1,1\n", "u.csv");
  EXPECT_EQ(unweighted.samples[0].weight, 1.0);
  EXPECT_EQ(unweighted.weighting, "uniform");
}

TEST(Csv, WritingAndReadingGivesTheSameSamples) {
  SampleSet set;
  set.samples.push_back(
      {Vec3(0.1, 0.2, 0.3).normalized(), Vec3(-0.3, 0.1, 0.9).normalized(), Rgb<double>(0.1, 1.0 / 3, 2e-9), 0.7});
  set.samples.push_back({Vec3(0, 0, 1), Vec3(0.6, 0, 0.8), Rgb<double>(5, 6, 7), 1});
  const SampleSet again = parse_csv_samples(format_csv_samples(set), "again.csv");
  ASSERT_EQ(again.size(), set.size());
  for (size_t i = 0; i < set.size(); ++i) {
    // Directions are renormalised when read and f·cosθi recomputed: equal to rounding.
    EXPECT_LT((again.samples[i].l - set.samples[i].l).norm(), 1e-15);
    EXPECT_LT((again.samples[i].v - set.samples[i].v).norm(), 1e-15);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(again.samples[i].value[c], set.samples[i].value[c], 1e-15 * set.samples[i].value[c]);
    EXPECT_EQ(again.samples[i].weight, set.samples[i].weight);
  }
}

TEST(Csv, LoadSamplesReadsFilesAndAppliesTheOptions) {
  std::string text = "# unit: degrees\ntheta_i,phi_i,theta_o,phi_o,r,g,b\n";
  for (int t = 0; t < 90; t += 5) text += std::to_string(t) + ",0,30,180,0.1,0.2,0.3\n";
  const std::string path = test::scratch_path("angles.csv");
  test::write_bytes(path, text);
  EXPECT_EQ(load_samples(path, SamplingOptions{}).size(), 18u);
  EXPECT_EQ(load_samples(path, SamplingOptions{80.0, 0, 1}).size(), 17u);  // θi = 85° dropped
  const SampleSet subset = load_samples(path, SamplingOptions{90.0, 5, 3});
  ASSERT_EQ(subset.size(), 5u);
  EXPECT_EQ(subset.source, path);
  for (size_t i = 1; i < subset.size(); ++i)
    EXPECT_GT(subset.samples[i - 1].l.z(), subset.samples[i].l.z()) << "the file's order (θi rising) is kept";
  const TableInfo info = describe_measured(path);
  EXPECT_EQ(info.format, "csv");
  EXPECT_EQ(info.valid, 18u);
  EXPECT_EQ(info.max, Rgb<double>(0.1, 0.2, 0.3));
  EXPECT_FALSE(info.albedo.allFinite());
  expect_error([&] { open_measured(path); }, {path, "not a table"});
}

TEST(Csv, RejectsMalformedInputNamingFileLineAndProblem) {
  const std::string v = "lx,ly,lz,vx,vy,vz,r,g,b\n";
  expect_error([] { parse_csv_samples("", "e.csv"); }, {"e.csv", "no CSV header"});
  expect_error([] { parse_csv_samples("# only a comment\n\n", "c.csv"); }, {"c.csv", "no CSV header"});
  expect_error([] { parse_csv_samples("a,b,c\n", "h.csv"); }, {"h.csv:1", "unrecognised header 'a,b,c'"});
  expect_error([] { parse_csv_samples("lx,ly,lz,vx,vy,vz,r,g\n", "h2.csv"); }, {"h2.csv:1", "unrecognised header"});
  expect_error([] { parse_csv_samples("lx,ly,lz,vx,vy,vz,r,g,b,w\n", "h3.csv"); }, {"h3.csv:1", "unrecognised header"});
  expect_error([] { parse_csv_samples("theta_i,phi_i,theta_o,phi_o,r,g,b\n", "u.csv"); },
               {"u.csv:1", "'# unit: degrees'"});
  expect_error([] { parse_csv_samples("# unit: gradians\ntheta_i,phi_i,theta_o,phi_o,r,g,b\n", "g.csv"); },
               {"g.csv:1", "unknown angle unit 'gradians'"});
  expect_error([&] { parse_csv_samples(v + "0,0,1,0,0,1,1,1\n", "n.csv"); }, {"n.csv:2", "8 fields, the header has 9"});
  expect_error([&] { parse_csv_samples(v + "0,0,1,0,0,1,1,1,1,1\n", "n2.csv"); }, {"n2.csv:2", "10 fields"});
  expect_error([&] { parse_csv_samples(v + "0,0,1,0,0,1,1,nan,1\n", "nan.csv"); },
               {"nan.csv:2", "field 8 'nan' is not a finite number"});
  expect_error([&] { parse_csv_samples(v + "0,0,1,0,0,1,1,inf,1\n", "inf.csv"); }, {"inf.csv:2", "'inf'"});
  expect_error([&] { parse_csv_samples(v + "0,0,1,0,0,1,1,1e999,1\n", "big.csv"); }, {"big.csv:2", "'1e999'"});
  expect_error([&] { parse_csv_samples(v + "0,0,1,0,0,1,1,x,1\n", "x.csv"); }, {"x.csv:2", "field 8 'x'"});
  expect_error([&] { parse_csv_samples(v + "0,0,1,0,0,1,1,0.5.5,1\n", "dots.csv"); }, {"dots.csv:2", "'0.5.5'"});
  expect_error([&] { parse_csv_samples(v + "0,0,1,0,0,1,1,,1\n", "blank.csv"); }, {"blank.csv:2", "field 8 ''"});
  expect_error([&] { parse_csv_samples(v + "0,0,1,0,0,1,1,1,1\n0,0,-1,0,0,1,1,1,1\n", "b.csv"); },
               {"b.csv:3", "below the horizon"});
  expect_error([&] { parse_csv_samples(v + "0,0,0,0,0,1,1,1,1\n", "z.csv"); }, {"z.csv:2", "zero vector"});
  expect_error([&] { parse_csv_samples(v + "0,0,1,0,0,1,1,-0.1,1\n", "neg.csv"); },
               {"neg.csv:2", "negative reflectance"});
  expect_error([] { parse_csv_samples("lx,ly,lz,vx,vy,vz,r,g,b,weight\n0,0,1,0,0,1,1,1,1,-2\n", "w.csv"); },
               {"w.csv:2", "negative weight"});
  expect_error(
      [] { parse_csv_samples("# unit: degrees\ntheta_i,phi_i,theta_o,phi_o,r,g,b\n95,0,30,0,1,1,1\n", "a.csv"); },
      {"a.csv:3", "below the horizon"});
  expect_error([&] { parse_csv_samples(v, "none.csv"); }, {"none.csv", "no samples after the header"});
  expect_error([] { load_samples("/nonexistent/x.csv", SamplingOptions{}); }, {"/nonexistent/x.csv", "cannot open"});
}

}  // namespace
}  // namespace brdffit
