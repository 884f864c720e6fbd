// Physical questions asked of what the readers return, not of the code's own conventions:
// reciprocity of every table, a Lambertian file written in the RGL convention (f·cosθo) reading
// back as albedo/π, `info`'s checks of a measurement, isotropic tables' samples, and "best" that
// never calls a poor fit usable (the fits behind the same questions: test_measurement_truth_fits.cc).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "batch_test_util.h"
#include "brdffit/compare.h"
#include "brdffit/fit.h"
#include "brdffit/measured.h"
#include "brdffit/merl.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"
#include "brdffit/rgl.h"
#include "brdffit/rusinkiewicz.h"
#include "tables_test_util.h"
#include "tensor_file_writer.h"

namespace brdffit {
namespace {

// --- reciprocity of every reader on every table ---------------------------------------------------

double median(std::vector<double> xs) {
  if (xs.empty()) return NAN;
  std::nth_element(xs.begin(), xs.begin() + xs.size() / 2, xs.end());
  return xs[xs.size() / 2];
}

// Per channel over random pairs (cosθ ≥ 0.2), values above 1e-3 of the channel's largest, with
// y = ln f(l,v)/f(v,l) and x = ln(cosθv/cosθl). Computed here from eval() alone, independently of
// `info`'s implementation.
struct ReciprocityStatistics {
  double noise = NAN;          // median |y| where |x| < 0.1: the data's own reciprocity error, whatever
                               // the convention (cosθv ≈ cosθl there)
  double median_abs = NAN;     // median |y| over all pairs
  double tilted_bias = NAN;    // median y where x > 0.5 ...
  double tilted_cosine = NAN;  // ... and median x there: what values of f·cosθo read as f would add
};

ReciprocityStatistics reciprocity_of(const MeasuredBrdf& table) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit;
  // Half the pairs anywhere (cosθ ≥ 0.2), half with cosθv/cosθl mostly above e^0.5 (cosθl in
  // [0.35, 0.6], cosθv ≥ 0.9: away from grazing, where measurements are noisiest).
  const auto direction = [&](double min_z, double max_z) {
    const double z = min_z + (max_z - min_z) * unit(rng), phi = 2 * kPi * unit(rng), r = std::sqrt(1 - z * z);
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
  };
  std::vector<std::array<Vec3, 2>> pairs;
  for (int i = 0; i < 2000; ++i) pairs.push_back({direction(0.2, 1), direction(0.2, 1)});
  for (int i = 0; i < 2000; ++i) pairs.push_back({direction(0.35, 0.6), direction(0.9, 1)});
  // Ratios of values near zero measure noise: each channel's floor is 1% of its median value.
  std::array<std::vector<double>, 3> values;
  for (const auto& [l, v] : pairs)
    for (int c = 0; c < 3; ++c) values[c].push_back(table.eval(l, v)[c]);
  Rgb<double> floor;
  for (int c = 0; c < 3; ++c) floor[c] = 0.01 * median(values[c]);
  std::vector<double> level, all, tilted, tilted_x;
  for (const auto& [l, v] : pairs) {
    const Rgb<double> a = table.eval(l, v), b = table.eval(v, l);
    const double x = std::log(v.z() / l.z());
    for (int c = 0; c < 3; ++c) {
      if (!(a[c] > floor[c] && b[c] > floor[c])) continue;
      const double y = std::log(a[c] / b[c]);
      all.push_back(std::abs(y));
      if (std::abs(x) < 0.1) level.push_back(std::abs(y));
      if (x > 0.5) tilted.push_back(y), tilted_x.push_back(x);
    }
  }
  EXPECT_GT(level.size(), 100u) << table.path();
  EXPECT_GT(tilted.size(), 1000u) << table.path();
  return {median(level), median(all), median(tilted), median(tilted_x)};
}

// A measurement is reciprocal up to its own noise, measured on pairs of nearly equal cosines
// (matte RGL files: 0.01-0.04; glossy ones up to 0.25 where the lobe falls off). And its error
// does not lean with the cosines: where cosθv/cosθl > e^0.5, values of f·cosθo read as f are off
// by the whole ln(cosθv/cosθl) (0.57-0.82 on the shared RGL files), a BRDF by its noise (below
// 0.2): the test decides between the two at half the difference.
void expect_reciprocal(const MeasuredBrdf& table) {
  SCOPED_TRACE(table.path());
  const ReciprocityStatistics s = reciprocity_of(table);
  EXPECT_LT(std::abs(s.tilted_bias), 0.5 * s.tilted_cosine) << "noise " << s.noise;
}

TEST(Reciprocity, EveryRglTableIsReciprocal) {
  const std::vector<std::string> files = test::shared_rgl_files();
  SKIP_UNLESS_SHARED(!files.empty(), "the shared RGL files (" << test::kSharedDir << "/data/rgl)");
  for (const std::string& path : files) expect_reciprocal(*open_measured(path));
  expect_reciprocal(*open_measured(std::string(BRDFFIT_SOURCE_DIR) + "/data/cc_ibiza_sunset_rgb.bsdf"));
}

TEST(Reciprocity, EveryMerlTableIsReciprocal) {
  for (const char* name : {"gold-metallic-paint", "blue-acrylic", "red-fabric"}) {
    const std::string path = test::merl_proxy(name);
    SKIP_UNLESS_SHARED(!path.empty(), "the shared MERL proxies (" << test::kSharedDir << "/data/merl-proxy)");
    expect_reciprocal(*open_measured(path));
  }
}

// --- a Lambertian table in the RGL convention -----------------------------------------------------

// An isotropic RGL file whose table holds (albedo/π)·cosθo, as the database's files hold f·cosθo:
// NDF and projected area 1, a uniform VNDF (its inverse warp is the identity) and, on a fine
// grid over (θi, u_m), RGB = 4·(albedo/π)·cosθo of the pair that u_m stands for.
std::string lambertian_rgl_file(const Rgb<double>& albedo) {
  using test::float_field;
  using Index = std::vector<uint64_t>;
  const int n_theta = 46, n_u = 97;
  std::vector<float> theta_i;
  for (int i = 0; i < n_theta; ++i) theta_i.push_back(float(i * (kPi / 2) / (n_theta - 1)));
  const auto cos_outgoing = [&](const Index& i) {
    const double ti = theta_i[i[1]], ux = i[4] / double(n_u - 1), uy = i[3] / double(n_u - 1);
    const double tm = ux * ux * (kPi / 2), dphi = uy * 2 * kPi - kPi;  // φi = 0
    const Vec3 wi(std::sin(ti), 0, std::cos(ti));
    const Vec3 wm(std::sin(tm) * std::cos(dphi), std::sin(tm) * std::sin(dphi), std::cos(tm));
    return std::max(0.0, (2 * wi.dot(wm) * wm - wi).z());
  };
  return test::tensor_file_bytes({
      test::bytes_field("description", "Lambertian, f·cosθo"),
      test::float_values("phi_i", {0.0f}),
      test::float_values("theta_i", theta_i),
      float_field("ndf", {2, 2}, [](const Index&) { return 1.0; }),
      float_field("sigma", {2, 2}, [](const Index&) { return 1.0; }),
      float_field("vndf", {1, uint64_t(n_theta), 2, 2}, [](const Index&) { return 1.0; }),
      float_field("luminance", {1, uint64_t(n_theta), 2, 2}, [](const Index&) { return 1.0; }),
      float_field("rgb", {1, uint64_t(n_theta), 3, uint64_t(n_u), uint64_t(n_u)},
                  [&](const Index& i) { return 4 * albedo[i[2]] / kPi * cos_outgoing(i); }),
      {"jacobian", test::kUInt8, {1}, std::string(1, '\x01')},
  });
}

TEST(Rgl, ALambertianFileReadsBackAsAlbedoOverPiAtEveryPair) {
  const Rgb<double> albedo(0.8, 0.5, 0.2);
  const RglBrdf table = RglBrdf::parse(lambertian_rgl_file(albedo), "lambertian.bsdf");
  std::mt19937_64 rng(5);
  double worst = 0;
  for (int i = 0; i < 500; ++i) {
    const Vec3 l = test::random_upper_direction(rng, 0.3), v = test::random_upper_direction(rng, 0.3);
    const Rgb<double> f = table.eval(l, v);
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(f[c] / (albedo[c] / kPi) - 1));
  }
  // The grids interpolate cosθo bilinearly: a few tenths of a percent.
  EXPECT_LT(worst, 0.01);
  // And the directional albedo at normal incidence is the albedo.
  const TableInfo info = table.describe();
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(info.albedo[c], albedo[c], 0.01 * albedo[c]);
  EXPECT_LT(std::abs(info.reciprocity_cosine_share), 0.05);
}

// --- info: the checks of a measurement ------------------------------------------------------------

// A table defined by a function, for `describe`.
class FunctionTable final : public MeasuredBrdf {
 public:
  FunctionTable(std::string name, std::function<Rgb<double>(const Vec3&, const Vec3&)> f)
      : name_(std::move(name)), f_(std::move(f)) {}
  const std::string& path() const override { return name_; }
  TableInfo info() const override {
    TableInfo info;
    info.format = "test";
    info.valid = 1;
    info.include_in_range(f_(Vec3(0, 0, 1), Vec3(0, 0, 1)));
    return info;
  }
  Rgb<double> eval(const Vec3& l, const Vec3& v) const override {
    return l.z() > 0 && v.z() > 0 ? f_(l, v) : Rgb<double>::Zero();
  }
  SampleSet samples(const SamplingOptions&) const override { return {}; }

 private:
  std::string name_;
  std::function<Rgb<double>(const Vec3&, const Vec3&)> f_;
};

TEST(Info, ALambertianTableIsReciprocalIsotropicAndReflectsItsAlbedoAtEveryIncidence) {
  const FunctionTable table("lambert",
                            [](const Vec3&, const Vec3&) -> Rgb<double> { return Rgb<double>(0.6, 0.4, 0.2) / kPi; });
  const TableInfo info = table.describe();
  ASSERT_EQ(info.albedo_by_incidence.size(), 4u);
  for (const TableInfo::AlbedoAt& a : info.albedo_by_incidence) {
    EXPECT_NEAR(a.albedo[0], 0.6, 1e-3) << a.theta_deg;
    EXPECT_NEAR(a.albedo[2], 0.2, 1e-3) << a.theta_deg;
  }
  EXPECT_NEAR(info.reciprocity, 0.0, 1e-12);
  EXPECT_NEAR(info.anisotropy, 0.0, 1e-12);
  EXPECT_TRUE(info.warnings.empty()) << info.warnings.front();
}

TEST(Info, FlagsValuesThatAreFTimesCosineAsNotReciprocal) {
  // What a reader that forgot RGL's cosθo returns: a Lambertian f times cosθv.
  const FunctionTable table(
      "f-cos", [](const Vec3&, const Vec3& v) -> Rgb<double> { return Rgb<double>::Constant(0.5 / kPi * v.z()); });
  const TableInfo info = table.describe();
  EXPECT_GT(info.reciprocity, 0.2);
  EXPECT_NEAR(info.reciprocity_cosine_share, 1.0, 0.05);  // ln(a/b) = ln(cosθv/cosθl) exactly, up to medians
  EXPECT_TRUE(test::mentions(info.warnings, "look like f·cosθ, not the BRDF"))
      << ::testing::PrintToString(info.warnings);
}

TEST(Info, FlagsAlbedoAboveOneAndAnisotropyOfADeclaredIsotropicTable) {
  // Lambert with albedo 1.3, and a term that depends on the azimuth of l.
  const FunctionTable table("bright", [](const Vec3& l, const Vec3&) -> Rgb<double> {
    return Rgb<double>::Constant(1.3 / kPi * (1 + 0.5 * l.x() / std::hypot(l.x(), l.y() + 1e-12)));
  });
  const TableInfo info = table.describe();
  EXPECT_TRUE(test::mentions(info.warnings, "not energy conserving")) << ::testing::PrintToString(info.warnings);
  EXPECT_GT(info.anisotropy, 0.1);
  EXPECT_TRUE(test::mentions(info.warnings, "declared isotropic")) << ::testing::PrintToString(info.warnings);
}

TEST(InfoCli, PrintsTheChecksOfTheBundledRglFile) {
  const test::CommandResult r =
      test::run_cli("info --json '" + std::string(BRDFFIT_SOURCE_DIR) + "/data/cc_ibiza_sunset_rgb.bsdf'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json info = nlohmann::json::parse(r.output);
  // A glossy coating: reciprocal to a few tenths, and not leaning with the cosines.
  EXPECT_LT(info["reciprocity"]["median_abs_log_ratio"].get<double>(), 0.35);
  EXPECT_LT(std::abs(info["reciprocity"]["cosine_share"].get<double>()), 0.5);
  EXPECT_TRUE(info["warnings"].empty()) << info["warnings"];
  EXPECT_EQ(info["isotropic"], true);
  EXPECT_EQ(info["albedo_by_incidence"].size(), 4u);
  for (const auto& a : info["albedo_by_incidence"]) EXPECT_LE(a["albedo"][0].get<double>(), 1.0);
}

// --- symmetry: anisotropic models on isotropic data -----------------------------------------------

TEST(Symmetry, IsotropicTablesSpreadTheirSamplesOverEveryAzimuth) {
  const std::string path = test::scratch_path("isotropic-ggx.binary");
  const Model& ggx = *find_model("ggx");
  const std::vector<double> values = parameter_values(ggx, {"albedo=0.2", "f0=0.6", "roughness=0.35"});
  write_merl(path, [&](const Vec3& l, const Vec3& v) { return *ggx.brdf(values.data(), l, v); });
  const SampleSet set = load_samples(path, SamplingOptions{});
  EXPECT_TRUE(set.isotropic);
  std::array<int, 4> quarters{};
  for (const Sample& s : set.samples) {
    const Vec3 h = half_vector(s.l, s.v);
    ++quarters[int(std::floor((std::atan2(h.y(), h.x()) + kPi) / (kPi / 2))) % 4];
  }
  for (int q : quarters) EXPECT_NEAR(q / double(set.size()), 0.25, 0.01);
  // Turned about the normal, each sample still holds the isotropic model's value.
  for (size_t i = 0; i < set.size(); i += 997)
    EXPECT_NEAR(set.samples[i].value[1], ggx.shade(values.data(), set.samples[i].l, set.samples[i].v)[1],
                0.02 * set.samples[i].value[1] + 1e-6);
}

// --- verdicts and "best" ---------------------------------------------------------------------------

TEST(Verdicts, ThePoorFitWithTheLowestErrorIsNeverBest) {
  const std::string dir = test::fresh_dir("best-usable");
  FitResult poor = test::known_result("gltf", 0.05);
  poor.verdict = Verdict::Poor;
  const FitResult good = test::known_result("ggx", 0.08), lambert = test::known_result("lambert", 0.1);
  test::write_document(dir + "/a.json", "/data/a.binary", {lambert, poor, good});
  FitResult poor_lambert = lambert;
  poor_lambert.verdict = Verdict::Poor;
  test::write_document(dir + "/b.json", "/data/b.binary", {poor_lambert, poor});
  const std::vector<FitDocument> documents = {read_fit_document(dir + "/a.json"), read_fit_document(dir + "/b.json")};
  EXPECT_EQ(best_result(documents[0].results, Metric::Cosine)->model, "ggx");
  EXPECT_EQ(best_result(documents[1].results, Metric::Cosine), nullptr);
  EXPECT_EQ(count_poor(documents[0].results), 1);
  const Comparison c = compare_results(documents, Metric::Cosine);
  EXPECT_EQ(c.materials[0].models[0].model, "gltf");  // ranked first by its error ...
  EXPECT_EQ(c.materials[0].best_usable, "ggx");       // ... but not best
  EXPECT_EQ(c.materials[1].best_usable, "");
  for (const ModelSummary& m : c.models) EXPECT_EQ(m.wins, m.model == "ggx" ? 1 : 0) << m.model;
  EXPECT_NE(comparison_text(c).find("(no usable fit)"), std::string::npos) << comparison_text(c);
}

}  // namespace
}  // namespace brdffit
