// RGL .bsdf files: the tensor file container, evaluation against the public RGL loader, physical
// plausibility of the shared measurements, samples and rejected files.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>

#include "brdffit/io.h"
#include "brdffit/measured.h"
#include "brdffit/rgl.h"
#include "brdffit/rusinkiewicz.h"
#include "brdffit/tensor_file.h"
#include "tables_test_util.h"
#include "tensor_file_writer.h"

namespace brdffit {
namespace {

using test::expect_error;
using test::TensorField;

struct Reference {
  const char* file;
  Vec3 wi, wo;  // not normalised
  Rgb<double> f;
};

// BRDF::eval(normalize(wi), normalize(wo)) of the public RGL loader (github.com/rgl-epfl/brdf-loader
// at c9ea6f9, powitacq_rgb.h with its default RGB clipping, in float32), for the same six
// direction pairs in every file. Its documented convention: "Evaluate f_r * cos", f·cosθo.
const Reference kSharedReferences[] = {
    {"acrylic_felt_green_rgb.bsdf", {0.3, -0.2, 1}, {-0.4, 0.1, 0.8}, {0.042402871, 0.0757949799, 0.0131368749}},
    {"acrylic_felt_green_rgb.bsdf", {1, 0, 1}, {-1, 0, 1}, {0.0543082319, 0.087515533, 0.0194609854}},
    {"acrylic_felt_green_rgb.bsdf", {0, 0.9, 0.3}, {0.1, -0.8, 0.5}, {0.164072841, 0.209415793, 0.0512508415}},
    {"acrylic_felt_green_rgb.bsdf", {0.5, 0.5, 0.7}, {0.2, -0.6, 0.5}, {0.0251786318, 0.0508974306, 0.00681251427}},
    {"acrylic_felt_green_rgb.bsdf", {-0.2, 0.1, 1}, {0.6, 0.7, 0.4}, {0.0132519044, 0.0285516158, 0.00387011259}},
    {"acrylic_felt_green_rgb.bsdf", {0.05, 0, 1}, {-0.05, 0.01, 1}, {0.0583861172, 0.0984976143, 0.015816981}},
    {"cc_ibiza_sunset_rgb.bsdf", {0.3, -0.2, 1}, {-0.4, 0.1, 0.8}, {0.729462743, 0.287705481, 0.388631165}},
    {"cc_ibiza_sunset_rgb.bsdf", {1, 0, 1}, {-1, 0, 1}, {2.46805429, 1.27064264, 0.944497049}},
    {"cc_ibiza_sunset_rgb.bsdf", {0, 0.9, 0.3}, {0.1, -0.8, 0.5}, {0.496618569, 0.28788951, 0.0699345693}},
    {"cc_ibiza_sunset_rgb.bsdf", {0.5, 0.5, 0.7}, {0.2, -0.6, 0.5}, {0.00909701921, 0.00349800475, 0.000671707501}},
    {"cc_ibiza_sunset_rgb.bsdf", {-0.2, 0.1, 1}, {0.6, 0.7, 0.4}, {0.00529342704, 0.00188865722, 0.000474356028}},
    {"cc_ibiza_sunset_rgb.bsdf", {0.05, 0, 1}, {-0.05, 0.01, 1}, {1.91041863, 0.798688591, 1.28060877}},
    {"cc_iris_purple_gem_rgb.bsdf", {0.3, -0.2, 1}, {-0.4, 0.1, 0.8}, {0.0837910771, 0.251078397, 0.755005956}},
    {"cc_iris_purple_gem_rgb.bsdf", {1, 0, 1}, {-1, 0, 1}, {2.81532049, 2.05037189, 3.67765903}},
    {"cc_iris_purple_gem_rgb.bsdf", {0, 0.9, 0.3}, {0.1, -0.8, 0.5}, {0.27972129, 0.104409568, 0.201221853}},
    {"cc_iris_purple_gem_rgb.bsdf", {0.5, 0.5, 0.7}, {0.2, -0.6, 0.5}, {0.000435706956, 0.000884498586, 0.00829091016}},
    {"cc_iris_purple_gem_rgb.bsdf", {-0.2, 0.1, 1}, {0.6, 0.7, 0.4}, {0, 0.000525848125, 0.00279184431}},
    {"cc_iris_purple_gem_rgb.bsdf", {0.05, 0, 1}, {-0.05, 0.01, 1}, {0.971428633, 1.91512477, 4.18875074}},
    {"colodur_napoli_4f_rgb.bsdf", {0.3, -0.2, 1}, {-0.4, 0.1, 0.8}, {0.0716329217, 0.0208893232, 0.0218942109}},
    {"colodur_napoli_4f_rgb.bsdf", {1, 0, 1}, {-1, 0, 1}, {0.0824725479, 0.0365745425, 0.0358607657}},
    {"colodur_napoli_4f_rgb.bsdf", {0, 0.9, 0.3}, {0.1, -0.8, 0.5}, {0.114489429, 0.0755852759, 0.0736019537}},
    {"colodur_napoli_4f_rgb.bsdf", {0.5, 0.5, 0.7}, {0.2, -0.6, 0.5}, {0.0525888093, 0.0137157375, 0.0145423347}},
    {"colodur_napoli_4f_rgb.bsdf", {-0.2, 0.1, 1}, {0.6, 0.7, 0.4}, {0.032506112, 0.00803510938, 0.00857270323}},
    {"colodur_napoli_4f_rgb.bsdf", {0.05, 0, 1}, {-0.05, 0.01, 1}, {0.0964592844, 0.0267047659, 0.028668059}},
    {"paper_white_rgb.bsdf", {0.3, -0.2, 1}, {-0.4, 0.1, 0.8}, {0.239509389, 0.242829323, 0.282479435}},
    {"paper_white_rgb.bsdf", {1, 0, 1}, {-1, 0, 1}, {0.211511448, 0.212895542, 0.242933631}},
    {"paper_white_rgb.bsdf", {0, 0.9, 0.3}, {0.1, -0.8, 0.5}, {0.20380199, 0.203160807, 0.221262023}},
    {"paper_white_rgb.bsdf", {0.5, 0.5, 0.7}, {0.2, -0.6, 0.5}, {0.1695299, 0.171012044, 0.196538001}},
    {"paper_white_rgb.bsdf", {-0.2, 0.1, 1}, {0.6, 0.7, 0.4}, {0.10119956, 0.102824613, 0.120246224}},
    {"paper_white_rgb.bsdf", {0.05, 0, 1}, {-0.05, 0.01, 1}, {0.271933913, 0.276162177, 0.323061436}},
    {"vch_golden_yellow_rgb.bsdf", {0.3, -0.2, 1}, {-0.4, 0.1, 0.8}, {1.19913566, 0.667165995, 0.0243667159}},
    {"vch_golden_yellow_rgb.bsdf", {1, 0, 1}, {-1, 0, 1}, {5.76215267, 2.9787271, 0}},
    {"vch_golden_yellow_rgb.bsdf", {0, 0.9, 0.3}, {0.1, -0.8, 0.5}, {0.872879207, 0.541232228, 0.193820477}},
    {"vch_golden_yellow_rgb.bsdf", {0.5, 0.5, 0.7}, {0.2, -0.6, 0.5}, {0.0100324983, 0.00980438013, 0.00268762838}},
    {"vch_golden_yellow_rgb.bsdf", {-0.2, 0.1, 1}, {0.6, 0.7, 0.4}, {0.00588893006, 0.00566020096, 0.00193234649}},
    {"vch_golden_yellow_rgb.bsdf", {0.05, 0, 1}, {-0.05, 0.01, 1}, {8.4000349, 4.29107285, 0}},
};

// The same, for the synthetic files of tensor_file_writer.h (written to disk and given to the
// loader): grids of 20x12, 24x24, 17x3 and 9x3 vertices, five uneven θi, one or four φi.
const Reference kSyntheticReferences[] = {
    {"isotropic", {0.3, -0.2, 1}, {-0.4, 0.1, 0.8}, {0.533184707, 1.47509634, 2.53481627}},
    {"isotropic", {1, 0, 1}, {-1, 0, 1}, {1.63191772, 3.35286975, 4.20151186}},
    {"isotropic", {0, 0.9, 0.3}, {0.1, -0.8, 0.5}, {0.624161363, 1.60369182, 2.49871016}},
    {"isotropic", {0.5, 0.5, 0.7}, {0.2, -0.6, 0.5}, {0.262659162, 0.793107212, 1.38875377}},
    {"isotropic", {-0.2, 0.1, 1}, {0.6, 0.7, 0.4}, {0.188911572, 0.60690248, 1.12375438}},
    {"isotropic", {0.05, 0, 1}, {-0.05, 0.01, 1}, {1.1537292, 2.24235845, 2.49513936}},
    {"anisotropic", {0.3, -0.2, 1}, {-0.4, 0.1, 0.8}, {0.531223416, 1.5292244, 2.7459023}},
    {"anisotropic", {1, 0, 1}, {-1, 0, 1}, {1.72167683, 3.55517173, 4.48984241}},
    {"anisotropic", {0, 0.9, 0.3}, {0.1, -0.8, 0.5}, {0.772778869, 1.830235, 2.51554489}},
    {"anisotropic", {0.5, 0.5, 0.7}, {0.2, -0.6, 0.5}, {0.305116624, 0.885107577, 1.4655807}},
    {"anisotropic", {-0.2, 0.1, 1}, {0.6, 0.7, 0.4}, {0.280130416, 0.778270006, 1.16098773}},
    {"anisotropic", {0.05, 0, 1}, {-0.05, 0.01, 1}, {1.23203027, 2.40365958, 2.69447732}},
};

void expect_matches(const RglBrdf& brdf, const Reference& r) {
  SCOPED_TRACE(::testing::Message() << r.file << " wi " << r.wi.transpose() << " wo " << r.wo.transpose());
  // The loader returns f·cosθo with wi the view and wo the light; the reader f(l, v).
  const Vec3 view = r.wi.normalized(), light = r.wo.normalized();
  const Rgb<double> f_cos = brdf.eval(light, view) * light.z();
  // The loader computes in float32; this reader in double.
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(f_cos[c], r.f[c], 2e-5 * r.f[c] + 1e-7) << "channel " << c;
}

RglBrdf synthetic(bool anisotropic) {
  return RglBrdf::parse(test::tensor_file_bytes(test::synthetic_rgl_fields(anisotropic)),
                        anisotropic ? "synthetic-anisotropic.bsdf" : "synthetic-isotropic.bsdf");
}

const Vec3 l_off_axis = test::dir(0.3, -0.2, 1), v_off_axis = test::dir(-0.4, 0.1, 0.8);
Vec3 turned_90(const Vec3& d) { return Vec3(-d.y(), d.x(), d.z()); }  // about the normal

TEST(Rgl, MatchesThePublicLoaderOnTheSharedFiles) {
  SKIP_UNLESS_SHARED(!test::shared_rgl_files().empty(), "the shared RGL files (" << test::kSharedDir << "/data/rgl)");
  for (const std::string& path : test::shared_rgl_files()) {
    const RglBrdf brdf = RglBrdf::read(path);
    EXPECT_TRUE(brdf.isotropic()) << path;
    int compared = 0;
    for (const Reference& r : kSharedReferences)
      if (test::fs::path(path).filename() == r.file) {
        expect_matches(brdf, r);
        ++compared;
      }
    EXPECT_EQ(compared, 6) << path;
    // Isotropic: turning both directions about the normal leaves f as it was (up to the
    // interpolation of the tabulated projected area).
    const Rgb<double> f = brdf.eval(l_off_axis, v_off_axis);
    EXPECT_LT((brdf.eval(turned_90(l_off_axis), turned_90(v_off_axis)) - f).norm(), 0.01 * f.norm()) << path;
  }
}

TEST(Rgl, MatchesThePublicLoaderAtOtherResolutionsAndWhenAnisotropic) {
  const RglBrdf isotropic = synthetic(false), anisotropic = synthetic(true);
  EXPECT_TRUE(isotropic.isotropic());
  EXPECT_FALSE(anisotropic.isotropic());
  for (const Reference& r : kSyntheticReferences)
    expect_matches(std::string(r.file) == "anisotropic" ? anisotropic : isotropic, r);
  // Anisotropic: turning both directions about the normal changes f. (The synthetic isotropic
  // file's sigma varies with φ, which no measured isotropic file does: its invariance is checked
  // on the shared files.)
  EXPECT_GT((anisotropic.eval(turned_90(l_off_axis), turned_90(v_off_axis)) - anisotropic.eval(l_off_axis, v_off_axis))
                .norm(),
            1e-3);
}

TEST(Rgl, BundledDemoFileIsTheSharedIbizaSunset) {
  const std::string bundled = std::string(BRDFFIT_SOURCE_DIR) + "/data/cc_ibiza_sunset_rgb.bsdf";
  const RglBrdf brdf = RglBrdf::read(bundled);
  EXPECT_NE(brdf.description().find("Ibiza Sunset"), std::string::npos) << brdf.description();
  for (const Reference& r : kSharedReferences)
    if (std::string(r.file) == "cc_ibiza_sunset_rgb.bsdf") expect_matches(brdf, r);
}

// Energy: no measured material reflects more than it receives. (Reciprocity: test_measurement_truth.cc.)
TEST(Rgl, AlbedoAtMostOneAtEveryIncidence) {
  const std::vector<std::string> files = test::shared_rgl_files();
  SKIP_UNLESS_SHARED(!files.empty(), "the shared RGL files (" << test::kSharedDir << "/data/rgl)");
  for (const std::string& path : files) {
    SCOPED_TRACE(path);
    const RglBrdf brdf = RglBrdf::read(path);
    for (double theta_deg : {0.0, 30.0, 45.0, 60.0, 75.0}) {
      const double t = theta_deg * kPi / 180;
      const Rgb<double> albedo = directional_albedo(brdf, Vec3(std::sin(t), 0, std::cos(t)));
      EXPECT_LE(albedo.maxCoeff(), 1.0) << theta_deg << "°: " << albedo.transpose();
      EXPECT_GT(albedo.minCoeff(), 0.0) << theta_deg << "°: " << albedo.transpose();
    }
  }
}

TEST(Rgl, SamplesLieOnTheDocumentedHalfDifferenceGrid) {
  const RglBrdf brdf = synthetic(false);
  const SampleSet set = brdf.samples(SamplingOptions{});
  EXPECT_EQ(set.weighting, "solid-angle");
  // The documented grid, 64 θh x 64 θd x 90 φd bins over φd in [0, 180°), centres by hand:
  // θh = ((iθh+½)/64)²·90°, θd = (iθd+½)/64·90°, φd = (iφd+½)·2°; one sample per centre whose
  // directions are both above the horizon (counted with test::pair_from_angles).
  size_t above = 0;
  for (int ih = 0; ih < 64; ++ih)
    for (int id = 0; id < 64; ++id)
      for (int ip = 0; ip < 90; ++ip) {
        const double u = (ih + 0.5) / 64;
        const auto [l, v] = test::pair_from_angles(u * u * 90, (id + 0.5) / 64 * 90, (ip + 0.5) * 2, 0.0);
        above += l.z() > 0 && v.z() > 0;
      }
  ASSERT_EQ(set.size(), above);
  double weight_sum = 0.0;
  for (const Sample& s : set.samples) {
    weight_sum += s.weight;
    // On a centre (θh and θd do not change when the pair is turned about the normal): √(θh/90°)·64 and θd/90°·64 are a
    // whole number and a half.
    const Vec3 h = (s.l + s.v).normalized();
    const double th = std::atan2(std::hypot(h.x(), h.y()), h.z()) * 180 / kPi;
    const double td = std::atan2(s.l.cross(h).norm(), s.l.dot(h)) * 180 / kPi;
    const double uh = std::sqrt(th / 90) * 64 - 0.5, ud = td / 90 * 64 - 0.5;
    ASSERT_NEAR(uh, std::round(uh), 1e-5) << "θh " << th;
    ASSERT_NEAR(ud, std::round(ud), 1e-5) << "θd " << td;
  }
  EXPECT_NEAR(weight_sum, 2 * kPi * kPi, 0.03 * 2 * kPi * kPi);  // as for MERL bins
  for (size_t i = 0; i < set.size(); i += 997) {
    const Sample& s = set.samples[i];
    const Rgb<double> expected = brdf.eval(s.l, s.v) * s.l.z();
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(s.value[c], expected[c], 1e-12 * expected[c]);
  }
  // Isotropic and anisotropic files alike: the half vectors turn about the normal.
  for (const bool anisotropic : {false, true}) {
    const SampleSet turned = synthetic(anisotropic).samples(SamplingOptions{90.0, 2000, 1});
    EXPECT_EQ(turned.isotropic, !anisotropic);
    size_t off_plane = 0;
    for (const Sample& s : turned.samples) off_plane += std::abs(s.l.y() + s.v.y()) > 1e-3;
    EXPECT_GT(off_plane, 1500u);
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
  EXPECT_THROW(ParametricGrid2D(2, 2, {1, 2, 3}, {}, false), std::invalid_argument);
}

// --- rejected files ---------------------------------------------------------------------------

// The synthetic isotropic file with one field changed by `edit`, parsed as `name`.
template <class Edit>
void parse_edited(const std::string& name, Edit&& edit) {
  std::vector<TensorField> fields = test::synthetic_rgl_fields(false);
  edit(fields);
  RglBrdf::parse(test::tensor_file_bytes(fields), name);
}

TensorField& field_named(std::vector<TensorField>& fields, const std::string& name) {
  for (TensorField& f : fields)
    if (f.name == name) return f;
  throw std::logic_error("no field " + name);
}

TEST(Rgl, RejectsMalformedContainersNamingTheFileAndTheProblem) {
  const std::string good = test::tensor_file_bytes(test::synthetic_rgl_fields(false));
  EXPECT_NO_THROW(RglBrdf::parse(good, "good.bsdf"));
  expect_error([] { RglBrdf::parse("not a tensor file at all", "bad.bsdf"); }, {"bad.bsdf", "not a tensor file"});
  expect_error([] { RglBrdf::parse("", "empty-file.bsdf"); }, {"empty-file.bsdf", "not a tensor file"});
  std::string version = good;
  version[12] = 2;
  expect_error([&] { RglBrdf::parse(version, "version.bsdf"); }, {"version.bsdf", "version 2.0"});
  // Cut inside the header: at every length up to the data, the message says where it ended.
  expect_error([&] { RglBrdf::parse(good.substr(0, 14), "count.bsdf"); }, {"count.bsdf", "truncated", "field count"});
  expect_error([&] { RglBrdf::parse(good.substr(0, 20), "name.bsdf"); }, {"name.bsdf", "truncated", "field name"});
  for (size_t length = 0; length < 400; ++length) {
    try {
      RglBrdf::parse(good.substr(0, length), "cut.bsdf");
      ADD_FAILURE() << "a file cut at " << length << " bytes was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("cut.bsdf: ", 0), 0u) << e.what();
    }
  }
  expect_error([&] { RglBrdf::parse(good.substr(0, good.size() - 1), "short.bsdf"); },
               {"short.bsdf", "truncated", "field 'jacobian' needs bytes"});
  // Field table problems.
  expect_error([] { parse_edited("type.bsdf", [](auto& fields) { fields[1].type = 42; }); },
               {"type.bsdf", "field 'phi_i' has unknown type code 42"});
  expect_error([] { parse_edited("unnamed.bsdf", [](auto& fields) { fields[1].name = ""; }); },
               {"unnamed.bsdf", "field 1 has an empty name"});
  expect_error([] { parse_edited("twice.bsdf", [](auto& fields) { fields[1].name = "theta_i"; }); },
               {"twice.bsdf", "field 'theta_i' appears twice"});
  expect_error(
      [] {
        parse_edited("huge.bsdf", [](auto& fields) { field_named(fields, "ndf").shape = {1ull << 40, 1ull << 40}; });
      },
      {"huge.bsdf", "truncated", "field 'ndf' of shape [1099511627776", "does not fit"});
}

TEST(Rgl, RejectsBadFieldsNamingTheFileFieldAndProblem) {
  // Names.
  expect_error([] { parse_edited("misnamed.bsdf", [](auto& f) { field_named(f, "theta_i").name = "thetai"; }); },
               {"misnamed.bsdf", "missing field 'theta_i'", "'thetai'"});
  expect_error([] { parse_edited("no-jacobian.bsdf", [](auto& f) { f.pop_back(); }); },
               {"no-jacobian.bsdf", "missing field 'jacobian'"});
  // Types.
  expect_error([] { parse_edited("double.bsdf", [](auto& f) { field_named(f, "theta_i").type = test::kFloat64; }); },
               {"double.bsdf", "field 'theta_i' is float64, expected float32"});
  expect_error([] { parse_edited("int.bsdf", [](auto& f) { field_named(f, "description").type = test::kUInt32; }); },
               {"int.bsdf", "field 'description' is uint32, expected uint8"});
  // Shapes.
  expect_error([] { parse_edited("rank.bsdf", [](auto& f) {
                      field_named(f, "ndf").shape = {3, 17, 1};
                    }); },
               {"rank.bsdf", "field 'ndf' has rank 3 (shape [3, 17, 1]), expected 2"});
  expect_error([] { parse_edited("vndf.bsdf", [](auto& f) {
                      field_named(f, "vndf").shape = {1, 4, 15, 20};
                    }); },
               {"vndf.bsdf", "field 'vndf' has shape [1, 4, 15, 20], expected [1, 5, *, *]"});
  expect_error([] { parse_edited("rgb.bsdf", [](auto& f) {
                      field_named(f, "rgb").shape = {1, 5, 4, 24, 18};
                    }); },
               {"rgb.bsdf", "field 'rgb' has shape [1, 5, 4, 24, 18], expected [1, 5, 3, *, *]"});
  expect_error([] { parse_edited("thin.bsdf", [](auto& f) {
                      field_named(f, "ndf").shape = {51, 1};
                    }); },
               {"thin.bsdf", "field 'ndf' has a 51x1 table, at least 2x2 needed"});
  expect_error(
      [] {
        parse_edited("theta.bsdf", [](auto& f) { field_named(f, "theta_i") = test::float_values("theta_i", {0.5f}); });
      },
      {"theta.bsdf", "'theta_i' at least 2"});
  expect_error(
      [] {
        parse_edited("jacobian.bsdf",
                     [](auto& f) { field_named(f, "jacobian") = test::bytes_field("jacobian", "ab"); });
      },
      {"jacobian.bsdf", "field 'jacobian' has shape [2], expected [1]"});
  // Values.
  auto set_float = [](TensorField& field, size_t index, float value) {
    std::memcpy(field.data.data() + 4 * index, &value, 4);
  };
  expect_error([&] { parse_edited("nan.bsdf", [&](auto& f) { set_float(field_named(f, "vndf"), 7, NAN); }); },
               {"nan.bsdf", "field 'vndf' has 1 NaN and 0 infinite values"});
  expect_error([&] { parse_edited("inf.bsdf", [&](auto& f) { set_float(field_named(f, "rgb"), 0, -INFINITY); }); },
               {"inf.bsdf", "field 'rgb' has 0 NaN and 1 infinite values"});
  expect_error([&] { parse_edited("density.bsdf", [&](auto& f) { set_float(field_named(f, "ndf"), 3, -1.0f); }); },
               {"density.bsdf", "field 'ndf' has 1 negative values"});
  expect_error([&] { parse_edited("sigma.bsdf", [&](auto& f) { set_float(field_named(f, "sigma"), 2, 0.0f); }); },
               {"sigma.bsdf", "field 'sigma' has 1 values that are not positive"});
  expect_error([&] { parse_edited("order.bsdf", [&](auto& f) { set_float(field_named(f, "theta_i"), 2, 0.35f); }); },
               {"order.bsdf", "field 'theta_i' must be strictly ascending"});
  // An anisotropic file whose φi grid covers half a turn (a symmetry-reduced file) is refused.
  expect_error(
      [] {
        std::vector<TensorField> fields = test::synthetic_rgl_fields(true);
        field_named(fields, "phi_i") = test::float_values("phi_i", {0.0f, 1.0f, 2.0f, float(kPi)});
        RglBrdf::parse(test::tensor_file_bytes(fields), "reduced.bsdf");
      },
      {"reduced.bsdf", "anisotropic", "not 2π", "not supported"});
}

TEST(Rgl, RejectsSharedFilesCutShortAndMissingFiles) {
  expect_error([] { RglBrdf::read("/nonexistent/x.bsdf"); }, {"/nonexistent/x.bsdf", "cannot open"});
  expect_error([] { open_measured("/nonexistent/x.bsdf"); }, {"/nonexistent/x.bsdf", "cannot open"});
  const std::vector<std::string> files = test::shared_rgl_files();
  SKIP_UNLESS_SHARED(!files.empty(), "the shared RGL files (" << test::kSharedDir << "/data/rgl)");
  const std::string bytes = read_file(files[0]);
  expect_error([&] { RglBrdf::parse(bytes.substr(0, bytes.size() / 2), "half.bsdf"); }, {"half.bsdf", "truncated"});
  // Through the dispatcher, by content and by extension.
  const std::string cut = test::scratch_path("cut.bsdf");
  test::write_bytes(cut, bytes.substr(0, 1000));
  expect_error([&] { open_measured(cut); }, {cut, "truncated"});
  expect_error([&] { load_samples(cut, SamplingOptions{}); }, {cut, "truncated"});
  const std::string garbage = test::scratch_path("garbage.bsdf");
  test::write_bytes(garbage, "garbage");
  expect_error([&] { open_measured(garbage); }, {garbage, "not a tensor file"});
  const std::string unknown = test::scratch_path("garbage.dat");
  test::write_bytes(unknown, "garbage");
  expect_error([&] { open_measured(unknown); }, {unknown, "unknown format"});
}

}  // namespace
}  // namespace brdffit
