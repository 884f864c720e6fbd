// Exported glTF drawn by three.js (npm package `three`, pinned in scripts/install-deps.sh), the
// glTF viewer most users have, in headless Chromium (tests/tools/render_gltf_three.js): one
// directional light, no environment, no tone mapping, a float render target read back linear,
// against `brdffit render` of the same fit under the same light and camera.
//
// three.js departs from the glTF specification's BRDF (Appendix B, KHR_materials_specular) in
// these documented ways (src/renderers/shaders/ShaderChunk/lights_physical_*.glsl.js of the
// pinned version), each written into this test's model of what three.js should draw:
//  1. Specular anti-aliasing: roughness becomes min(max(roughness, 0.045) + g, 1), g the largest
//     screen-space derivative of the normal (dFdx, dFdy over a 2x2 pixel quad). On a sphere of R
//     pixels' radius g ≈ 1/R at the centre, more toward the rim: the highlight widens and drops.
//  2. Multiple-scattering energy compensation (Turquin 2019) on direct light: the specular term is
//     multiplied by 1 + F0·(1/E(roughness, n·v) - 1), E the single-scattering lobe's directional
//     albedo for F = 1, read from a 16x16 half-float table with bilinear filtering; F0 is the
//     metallic mix of the dielectric f0 and baseColor. The specification has no such term.
//  3. The diffuse term is weighted per channel by 1 - F(v·h) of the dielectric f0 with the
//     metallic mix of f90 (three.js's specularF90), where KHR_materials_specular takes the largest
//     channel of F with the dielectric's own f90 = specular. Identical for core glTF (grey f0,
//     f90 = 1); a fraction of a percent for the gltf-specular material here, 12 % for a fit with a
//     strongly tinted specularColor (RGL's acrylic felt green: [1, 0.16, 0] at ior 2.6).
//  4. Float32 shading on interpolated vertex normals of a 720x360 SphereGeometry: angular error
//     under 1e-4 rad, about 1e-4 relative in the shading.
//  5. KHR_materials_clearcoat (BRDF_GGX_Clearcoat in lights_physical_pars_fragment, the mix in
//     ShaderLib/meshphysical.glsl.js): the base is weighted by 1 - c·F_c(n·v) as the extension
//     says, but the coat's lobe by Schlick's F(v·h) of f0 0.04 where the extension has F_c(n·v)
//     (c·F_c·V·D), and the coat's roughness is raised as in 1 (max(r, 0.045) + g, at most 1). Its
//     lobe has no energy compensation (as the extension). At the coat's highlight h ≈ n, so
//     v·h ≈ n·v: the two Fresnels differ away from it, where the lobe is small.
//  6. Every Schlick weight (1 - x)^5 is Epic's (Karis 2013) exp2((-5.55473 x - 6.98316) x)
//     (F_Schlick in common.glsl.js): within 0.004 of it, which the coat's mix by F_c(n·v) carries
//     over the whole sphere, toward its rim most.
//  7. KHR_materials_sheen (BRDF_Sheen, IBLSheenBRDF and RE_Direct_Physical in lights_physical_pars_fragment): the
//     Charlie distribution as the extension (α = sheenRoughness², sin²θh clamped at 2^-7 for half floats), but
//     Neubelt and Pettineo's visibility 1/(4 (n·l + n·v - n·l n·v)), clamped at 1, where the extension gives
//     Charlie's 1/((1 + Λ(n·v) + Λ(n·l)) 4 n·l n·v) (it allows the simpler one, saying that the albedo scaling
//     then does not conserve energy); and for E, the sheen's albedo, a curve fit exp(a·n·v + b) clamped to [0, 1]
//     where the extension looks E up in a table of the Charlie sheen's albedo (brdffit integrates it: its
//     gltf_sheen.h). The scaling itself is the extension's full form, 1 - max3(sheenColor)·max(E(n·v), E(n·l)),
//     applied to the direct light's diffuse and specular alike; the sheen's roughness is not raised by the
//     anti-aliasing of 1, and the sheen lobe gets no energy compensation.
//  8. KHR_materials_anisotropy (BRDF_GGX's USE_ANISOTROPY path, lights_physical_fragment): the extension's D and
//     V (D_GGX_Anisotropic, V_GGX_SmithCorrelated_Anisotropic, no clamp at 1) with α_t = mix(α, 1, strength²) and
//     α_b = α of the roughness raised as in 1; the energy compensation of 2 with that isotropic roughness. The
//     tangent: three.js's from the SphereGeometry's computed tangents (along u, the longitude), which is
//     brdffit's sphere frame (sphere.h's LocalFrame); with the rotation off by π/2 the picture is 80 % off.
// With these written in, the three.js picture must match to kModelTolerance, 0.5 % (measured:
// 0.04 %): E's table is the one thing approximated (E is integrated here at the table's texel
// centres and interpolated the same way; its half-float storage and three's own integration of E
// remain). Against the specification, the tolerance is the departure the model predicts at these
// pixels plus kModelTolerance: departures 1-3 and 5-7 are what three.js is documented to draw, so the
// difference they predict is the difference allowed, and no more. Measured at kSize 256:
// gltf 0.66 % mean per channel over the lit pixels, gltf-specular 1.34 %, gltf-clearcoat 0.52 % (coat 0.7 at
// roughness 0.3 over the gltf material: the coat dims the base and its departures by 1 - c·F_c; three.js against
// the departures written in, 0.04 % for each), gltf+sheen 9.5 % (sheen [0.9, 0.6, 0.5] at roughness 0.5 over the gltf
// material: Neubelt's visibility and three.js's E against Charlie's; three.js against the departures, 0.03 %),
// gltf+clearcoat+sheen 9.4 % (that sheen under that coat; against the departures, 0.03 %), gltf+anisotropy 1.9 %
// (strength 0.6 turned by 0.4 rad over a metallic 0.7 material; against the departures, 0.09 %).
// The fits of the shared MERL proxies (MerlFits, below) differ by more: gltf 2.5 % (blue-acrylic), 10.4 %
// (gold-metallic-paint, a rough metal) and 4.1 % (red-fabric); gltf-specular 0.11 %, gltf+clearcoat 2.4 %
// (blue-acrylic); gltf+sheen 12.1 % (gold-metallic-paint). The departures account for all of it but
// 0.03-0.13 %.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cctype>
#include <cmath>
#include <nlohmann/json.hpp>

#include "batch_test_util.h"
#include "brdffit/imaging/image_io.h"
#include "brdffit/math.h"
#include "brdffit/models/gltf_sheen.h"

namespace brdffit {
namespace {

constexpr int kSize = 256;                       // pixels; the sphere's radius is kSize/2 - 1
constexpr double kModelTolerance = 0.005;        // three.js against its documented departures, mean relative
const Vec3 kRenderLight = Vec3(-1.0, 1.0, 2.0);  // brdffit render's default light, upper left

// A glTF material as the specification and three.js both read it.
struct GltfMaterial {
  Rgb<double> base;
  double metallic = 0.0, roughness = 0.5;
  Rgb<double> dielectric_f0 = Rgb<double>::Constant(0.04);  // KHR_materials_specular's, 0.04 without it
  double dielectric_f90 = 1.0;                              // its specularFactor, 1 without it
  double clearcoat = 0.0, clearcoat_roughness = 0.1;        // KHR_materials_clearcoat's factors
  Rgb<double> sheen_color = Rgb<double>::Zero();            // KHR_materials_sheen's factors
  double sheen_roughness = 0.5;
  double anisotropy_strength = 0.0, anisotropy_rotation = 0.0;  // KHR_materials_anisotropy's
};

// The glTF BRDF's parts for F = 1: D·V, with α = roughness².
double ggx_dv(double roughness, double nl, double nv, double nh) {
  const double a2 = std::pow(roughness, 4), denom = nh * nh * (a2 - 1.0) + 1.0;
  const double d = a2 / (kPi * denom * denom);
  const double v = 0.5 / (nv * std::sqrt(a2 + (1.0 - a2) * nl * nl) + nl * std::sqrt(a2 + (1.0 - a2) * nv * nv));
  return d * v;
}

// KHR_materials_anisotropy's D·V at normal n (seen from v, lit from l) for the material's strength
// s and rotation r: α_b = roughness², α_t = mix(α_b, 1, s²), along t = cos r·t₀ + sin r·b₀ and
// b = n × t, where t₀ = ŷ × n normalised and b₀ = n × t₀ are the tangent frame brdffit's sphere
// (sphere.h's LocalFrame) and three.js's computed tangents (BufferGeometry.computeTangents on its
// SphereGeometry, whose u runs along the longitude) share. three.js draws this with the same D
// and V (D_GGX_Anisotropic, V_GGX_SmithCorrelated_Anisotropic: no clamp) on its raised roughness.
double anisotropic_dv(const GltfMaterial& m, double roughness, const Vec3& n, const Vec3& l, const Vec3& v) {
  const Vec3 h = (l + v).normalized(), t0 = Vec3::UnitY().cross(n).normalized(), b0 = n.cross(t0);
  const Vec3 t = std::cos(m.anisotropy_rotation) * t0 + std::sin(m.anisotropy_rotation) * b0, b = n.cross(t);
  const double s = m.anisotropy_strength, ab = roughness * roughness, at = ab + (1.0 - ab) * s * s;
  const double stretched = std::pow(h.dot(t) / at, 2) + std::pow(h.dot(b) / ab, 2) + std::pow(h.dot(n), 2);
  const double d = 1.0 / (kPi * at * ab * stretched * stretched);
  const auto smith = [&](const Vec3& w) { return Vec3(at * w.dot(t), ab * w.dot(b), w.dot(n)).norm(); };
  return d * 0.5 / (n.dot(l) * smith(v) + n.dot(v) * smith(l));
}

// E(roughness, μ): the directional albedo of D·V (F = 1) seen from μ = n·v, by a midpoint rule over
// half vectors distributed like D·(n·h) (so the peak is resolved at any roughness).
double lobe_albedo(double roughness, double mu) {
  constexpr int kTheta = 96, kPhi = 48;
  const double a2 = std::pow(std::max(roughness, 1e-3), 4);
  const Vec3 v(std::sqrt(1.0 - mu * mu), 0.0, mu);
  double sum = 0.0;
  for (int i = 0; i < kTheta; ++i) {
    const double xi = (i + 0.5) / kTheta, cos_h = std::sqrt((1.0 - xi) / (1.0 + (a2 - 1.0) * xi));
    const double sin_h = std::sqrt(1.0 - cos_h * cos_h);
    for (int j = 0; j < kPhi; ++j) {
      const double phi = 2.0 * kPi * (j + 0.5) / kPhi;
      const Vec3 h(sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h);
      const double vh = v.dot(h);
      const Vec3 l = 2.0 * vh * h - v;
      if (l.z() <= 0.0 || vh <= 0.0) continue;
      // f·cosθl / pdf(l), pdf(l) = D·(n·h) / (4 v·h)
      const double d = a2 / (kPi * std::pow(cos_h * cos_h * (a2 - 1.0) + 1.0, 2));
      sum += ggx_dv(std::pow(a2, 0.25), l.z(), mu, cos_h) * l.z() * 4.0 * vh / (d * cos_h);
    }
  }
  return sum / (kTheta * kPhi);
}

// three.js's table of E: 16x16 texels at (roughness, n·v) = ((i + ½)/16, (j + ½)/16), bilinear,
// clamped at the edges.
class LobeAlbedoTable {
 public:
  LobeAlbedoTable() {
    for (int j = 0; j < kTexels; ++j)
      for (int i = 0; i < kTexels; ++i) texels_[j][i] = lobe_albedo((i + 0.5) / kTexels, (j + 0.5) / kTexels);
  }
  double operator()(double roughness, double mu) const {
    const auto coordinate = [](double u, int& i0, double& t) {
      const double x = std::clamp(u * kTexels - 0.5, 0.0, kTexels - 1.0);
      i0 = std::min(static_cast<int>(x), kTexels - 2);
      t = x - i0;
    };
    int i, j;
    double s, t;
    coordinate(roughness, i, s);
    coordinate(mu, j, t);
    const auto row = [&](int r) { return (1.0 - s) * texels_[r][i] + s * texels_[r][i + 1]; };
    return (1.0 - t) * row(j) + t * row(j + 1);
  }

 private:
  static constexpr int kTexels = 16;
  double texels_[kTexels][kTexels];
};

// three.js's E of the sheen (IBLSheenBRDF in lights_physical_pars_fragment): a curve fit exp(a·μ + b), a and b
// quadratic in the sheen roughness r plus a term in 1/(r + 0.1), clamped to [0, 1] (departure 7).
double three_js_sheen_albedo(double mu, double r) {
  const double a = -1.9362 + 1.0678 * r + 0.4573 * r * r - 0.8469 / (r + 0.1);
  const double b = -0.6014 + 0.5538 * r - 0.4670 * r * r - 0.1255 / (r + 0.1);
  return std::clamp(std::exp(a * std::clamp(mu, 0.0, 1.0) + b), 0.0, 1.0);
}

// KHR_materials_sheen's Λ of the Charlie visibility (the extension's text; α = sheenRoughness²).
double charlie_lambda(double mu, double alpha) {
  const double t = (1.0 - alpha) * (1.0 - alpha);
  const auto at = [t](double at_zero, double at_one) { return at_zero + (at_one - at_zero) * t; };
  const auto l = [&](double x) {
    return at(21.5473, 25.3245) / (1.0 + at(3.82987, 3.32435) * std::pow(x, at(0.19823, 0.16801))) +
           at(-1.97760, -1.27393) * x + at(-4.32054, -4.85967);
  };
  return mu < 0.5 ? std::exp(l(mu)) : std::exp(2.0 * l(0.5) - l(1.0 - mu));
}

// f·cosθi of the material at normal n seen from +z (orthographic), lit from l: the specification's
// when extra_roughness is NaN, three.js's with its departures otherwise (extra_roughness being g).
Rgb<double> shade(const GltfMaterial& m, const Vec3& n, const Vec3& l, double extra_roughness,
                  const LobeAlbedoTable& albedo) {
  const Vec3 v = Vec3::UnitZ(), h = (l + v).normalized();
  const double nl = n.dot(l), nv = n.z(), nh = n.dot(h), vh = v.dot(h);
  if (nl <= 0.0 || nv <= 0.0) return Rgb<double>::Zero();
  const bool three = !std::isnan(extra_roughness);
  const double roughness = three ? std::min(std::max(m.roughness, 0.045) + extra_roughness, 1.0) : m.roughness;
  // Schlick's weight of a cosine x: the specification's, or three.js's (departure 6).
  const auto schlick = [three](double x) {
    return three ? std::exp2((-5.55473 * x - 6.98316) * x) : std::pow(1.0 - x, 5);
  };
  const double w = schlick(vh);
  const Rgb<double> f0 = (1.0 - m.metallic) * m.dielectric_f0 + m.metallic * m.base;
  const double f90 = (1.0 - m.metallic) * m.dielectric_f90 + m.metallic;
  const double dv = m.anisotropy_strength > 0.0 ? anisotropic_dv(m, roughness, n, l, v) : ggx_dv(roughness, nl, nv, nh);
  Rgb<double> specular = (f0.array() + (f90 - f0.array()) * w).matrix() * dv;
  const Rgb<double> dielectric_fresnel =
      (m.dielectric_f0.array() + ((three ? f90 : m.dielectric_f90) - m.dielectric_f0.array()) * w).matrix();
  Rgb<double> diffuse_weight = Rgb<double>::Constant(1.0 - dielectric_fresnel.maxCoeff());
  if (three) {
    specular = (specular.array() * (1.0 + f0.array() * (1.0 / albedo(roughness, nv) - 1.0))).matrix();
    diffuse_weight = (1.0 - dielectric_fresnel.array()).matrix();
  }
  const Rgb<double> diffuse = ((1.0 - m.metallic) * kInvPi * m.base.array() * diffuse_weight.array()).matrix();
  // KHR_materials_sheen: sheenColor·D·V over the base scaled by min(1 - max3(sheenColor)·E(μ)) over μ = n·v, n·l, E
  // the Charlie sheen's albedo (brdffit's table, checked against the integral in HandValues.GltfSheen); three.js
  // with departure 7.
  Rgb<double> sheen = Rgb<double>::Zero();
  double sheen_scaling = 1.0;
  if (m.sheen_color.maxCoeff() > 0.0) {
    const double alpha = m.sheen_roughness * m.sheen_roughness;
    const double sin2h = three ? std::max(1.0 - nh * nh, 0.0078125) : 1.0 - nh * nh;
    const double d = (2.0 + 1.0 / alpha) * std::pow(sin2h, 0.5 / alpha) / (2.0 * kPi);
    const double visibility =
        three ? std::min(1.0 / (4.0 * (nl + nv - nl * nv)), 1.0)
              : 1.0 / ((1.0 + charlie_lambda(nv, alpha) + charlie_lambda(nl, alpha)) * 4.0 * nv * nl);
    sheen = m.sheen_color * (d * visibility);
    const auto albedo_at = [&](double mu) {
      return three ? three_js_sheen_albedo(mu, m.sheen_roughness) : models::SheenAlbedo::table()(mu, m.sheen_roughness);
    };
    sheen_scaling = 1.0 - m.sheen_color.maxCoeff() * std::max(albedo_at(nv), albedo_at(nl));
  }
  // KHR_materials_clearcoat: mix(material, V·D(clearcoatRoughness²), c·F_c), F_c = 0.04 + 0.96 (1 - n·v)^5 (the
  // coat's normal is n); three.js with departure 5.
  const double coat_fresnel = 0.04 + 0.96 * schlick(nv);
  const double coat_lobe_fresnel = three ? 0.04 + 0.96 * w : coat_fresnel;
  const double coat_roughness =
      three ? std::min(std::max(m.clearcoat_roughness, 0.045) + extra_roughness, 1.0) : m.clearcoat_roughness;
  const double coat = m.clearcoat > 0.0 ? m.clearcoat * coat_lobe_fresnel * ggx_dv(coat_roughness, nl, nv, nh) : 0.0;
  return ((1.0 - m.clearcoat * coat_fresnel) * ((specular + diffuse) * sheen_scaling + sheen) +
          Rgb<double>::Constant(coat)) *
         nl;
}

// The normal brdffit render's sphere shows at pixel (x, y) (sphere.h: SphereView::centred); false off the sphere.
bool normal_at(int x, int y, Vec3& n) {
  const double middle = (kSize - 1) / 2.0, radius = kSize / 2.0 - 1.0;
  const double nx = (x - middle) / radius, ny = -(y - middle) / radius, r2 = nx * nx + ny * ny;
  if (!(r2 < 1.0)) return false;
  n = Vec3(nx, ny, std::sqrt(1.0 - r2));
  return true;
}

struct RenderComparison {
  size_t pixels = 0;
  double three_vs_spec = 0.0, three_vs_model = 0.0, model_vs_spec = 0.0, spec_vs_brdffit = 0.0;
};

// Mean relative differences per channel over the lit pixels well inside the outline (three.js's
// polygonal silhouette differs from the circle by a fraction of a pixel) whose 2x2 quad lies on
// the sphere (g is the quad's normal difference there).
RenderComparison compare(const GltfMaterial& m, const cv::Mat& three_js, const cv::Mat& brdffit_render) {
  static const LobeAlbedoTable albedo;
  const Vec3 l = kRenderLight.normalized();
  const double inner = 1.0 - 3.0 / (kSize / 2.0 - 1.0);
  RenderComparison c;
  const auto relative = [](const Rgb<double>& a, const Rgb<double>& b) {
    return ((a - b).array().abs() / b.array()).mean();
  };
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      Vec3 n, across, down;
      // WebGL's quads pair columns x, x^1 and, the picture's height being even, rows y, y^1.
      if (!normal_at(x, y, n) || !normal_at(x ^ 1, y, across) || !normal_at(x, y ^ 1, down)) continue;
      if (n.head<2>().norm() > inner || n.dot(l) < 0.05) continue;
      const double g = std::max((across - n).cwiseAbs().maxCoeff(), (down - n).cwiseAbs().maxCoeff());
      const Rgb<double> spec = shade(m, n, l, NAN, albedo), model = shade(m, n, l, g, albedo);
      const cv::Vec3f t = three_js.at<cv::Vec3f>(y, x), b = brdffit_render.at<cv::Vec3f>(y, x);
      const Rgb<double> three(t[0], t[1], t[2]), rendered(b[0], b[1], b[2]);
      c.three_vs_spec += relative(three, rendered);
      c.three_vs_model += relative(three, model);
      c.model_vs_spec += relative(model, spec);
      c.spec_vs_brdffit += relative(spec, rendered);
      ++c.pixels;
    }
  for (double* mean : {&c.three_vs_spec, &c.three_vs_model, &c.model_vs_spec, &c.spec_vs_brdffit})
    *mean /= std::max<size_t>(c.pixels, 1);
  return c;
}

// The pixels render_gltf_three.js wrote (rows top first).
cv::Mat read_three_js_pixels(const std::string& path) {
  const nlohmann::json document = nlohmann::json::parse(read_file(path));
  const int width = document.at("width"), height = document.at("height");
  const std::vector<float> rgb = document.at("rgb").get<std::vector<float>>();
  if (rgb.size() != static_cast<size_t>(3 * width * height))
    fail("{}: {} values for {}x{}", path, rgb.size(), width, height);
  return cv::Mat(height, width, CV_32FC3, const_cast<float*>(rgb.data())).clone();
}

struct RendererCase {
  std::string model;
  std::vector<std::string> assignments;
  GltfMaterial material;
  std::string three_js_material;  // the class GLTFLoader chooses
  std::string fitted_to;          // the measured table whose fit this is, if any
};
void PrintTo(const RendererCase& c, std::ostream* out) { *out << c.model << " " << c.fitted_to; }

class ThreeJs : public ::testing::TestWithParam<RendererCase> {};

TEST_P(ThreeJs, DrawsTheExportedMaterialAsFittedWithinItsDocumentedDepartures) {
  const RendererCase& c = GetParam();
  const std::string chromium = test::find_chromium();
  REQUIRE_TOOL(!chromium.empty(), "chromium (scripts/install-deps.sh with BRDFFIT_WITH_CHROMIUM=1)");
  REQUIRE_TOOL(test::have_tool("node") && std::filesystem::exists(test::npm_modules() + "/three"),
               "node with the npm package three");
  const std::string dir = test::fresh_dir("three-js-" + c.model);
  const std::string doc =
      test::write_document(dir + "/fit.json", "/data/m.binary", {test::fit_of(c.model, c.assignments)});
  const std::string light = fmt::format("{},{},{}", kRenderLight.x(), kRenderLight.y(), kRenderLight.z());
  const auto exported = test::run_cli("export " + doc + " -m " + c.model + " -o " + dir + "/m.gltf");
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  const auto rendered = test::run_cli(
      fmt::format("render {} -m {} --size {} --light {} -o {}/brdffit.exr", doc, c.model, kSize, light, dir));
  ASSERT_EQ(rendered.exit_code, 0) << rendered.output;
  const auto drawn = test::run_command(
      fmt::format("NODE_PATH={} node {}/tests/tools/render_gltf_three.js {} {}/m.gltf {} {} {}/three.json",
                  test::npm_modules(), BRDFFIT_SOURCE_DIR, chromium, dir, kSize, light, dir));
  ASSERT_EQ(drawn.exit_code, 0) << drawn.output;
  EXPECT_NE(read_file(dir + "/three.json").find("\"material\":\"" + c.three_js_material + "\""), std::string::npos);

  const RenderComparison r = compare(c.material, read_three_js_pixels(dir + "/three.json"),
                                     read_image(dir + "/brdffit.exr", Decoding{Transfer::Linear}));
  std::printf(
      "%s %s: three.js vs brdffit render %.4f, three.js vs its departures %.4f, departures alone %.4f (%zu lit "
      "pixels)\n",
      c.model.c_str(), c.fitted_to.c_str(), r.three_vs_spec, r.three_vs_model, r.model_vs_spec, r.pixels);
  EXPECT_GT(r.pixels, static_cast<size_t>(0.3 * kPi * kSize * kSize / 4));  // most of the lit hemisphere
  EXPECT_LT(r.spec_vs_brdffit, 1e-5);  // the specification written here is brdffit's model
  EXPECT_LT(r.three_vs_model, kModelTolerance);
  EXPECT_LT(r.three_vs_spec, r.model_vs_spec + kModelTolerance);
  EXPECT_GT(r.model_vs_spec, 0.0);
}

GltfMaterial specular_material() {
  GltfMaterial m{{0.8, 0.5, 0.25}, 0.3, 0.45};
  const double r = (1.7 - 1.0) / (1.7 + 1.0);
  m.dielectric_f0 = Rgb<double>(1.0, 0.9, 0.7) * (r * r * 0.8);
  m.dielectric_f90 = 0.8;
  return m;
}

GltfMaterial sheen_material() {
  GltfMaterial m{{0.8, 0.5, 0.25}, 0.3, 0.45};
  m.sheen_color = Rgb<double>(0.9, 0.6, 0.5);
  m.sheen_roughness = 0.5;
  return m;
}

// Both layers: the coat over the sheen, as KHR_materials_sheen layers them.
GltfMaterial clearcoat_sheen_material() {
  GltfMaterial m = sheen_material();
  m.clearcoat = 0.7;
  m.clearcoat_roughness = 0.3;
  return m;
}

GltfMaterial anisotropic_material() {
  GltfMaterial m{{0.8, 0.5, 0.25}, 0.7, 0.3};
  m.anisotropy_strength = 0.6;
  m.anisotropy_rotation = 0.4;
  return m;
}

GltfMaterial clearcoat_material() {
  GltfMaterial m{{0.8, 0.5, 0.25}, 0.3, 0.45};
  m.clearcoat = 0.7;
  m.clearcoat_roughness = 0.3;
  return m;
}

// gltf-specular: GltfSpecular, gltf+sheen: GltfSheen; a fit of blue-acrylic: GltfBlueAcrylic.
std::string test_name(const ::testing::TestParamInfo<RendererCase>& info) {
  std::string name;
  bool word_start = true;
  for (const char c : info.param.model + "-" + info.param.fitted_to) {
    if (std::isalnum(static_cast<unsigned char>(c))) name += word_start ? static_cast<char>(std::toupper(c)) : c;
    word_start = !std::isalnum(static_cast<unsigned char>(c));
  }
  return name;
}

INSTANTIATE_TEST_SUITE_P(Export, ThreeJs,
                         ::testing::Values(RendererCase{"gltf",
                                                        {"baseColor=0.8,0.5,0.25", "metallic=0.3", "roughness=0.45"},
                                                        {{0.8, 0.5, 0.25}, 0.3, 0.45},
                                                        "MeshStandardMaterial"},
                                           RendererCase{"gltf-specular",
                                                        {"baseColor=0.8,0.5,0.25", "metallic=0.3", "roughness=0.45",
                                                         "ior=1.7", "specular=0.8", "specularColor=1,0.9,0.7"},
                                                        specular_material(),
                                                        "MeshPhysicalMaterial"},
                                           RendererCase{"gltf+clearcoat",
                                                        {"baseColor=0.8,0.5,0.25", "metallic=0.3", "roughness=0.45",
                                                         "clearcoatFactor=0.7", "clearcoatRoughnessFactor=0.3"},
                                                        clearcoat_material(),
                                                        "MeshPhysicalMaterial"},
                                           RendererCase{"gltf+sheen",
                                                        {"baseColor=0.8,0.5,0.25", "metallic=0.3", "roughness=0.45",
                                                         "sheenColorFactor=0.9,0.6,0.5", "sheenRoughnessFactor=0.5"},
                                                        sheen_material(),
                                                        "MeshPhysicalMaterial"},
                                           RendererCase{"gltf+clearcoat+sheen",
                                                        {"baseColor=0.8,0.5,0.25", "metallic=0.3", "roughness=0.45",
                                                         "clearcoatFactor=0.7", "clearcoatRoughnessFactor=0.3",
                                                         "sheenColorFactor=0.9,0.6,0.5", "sheenRoughnessFactor=0.5"},
                                                        clearcoat_sheen_material(),
                                                        "MeshPhysicalMaterial"},
                                           RendererCase{"gltf+anisotropy",
                                                        {"baseColor=0.8,0.5,0.25", "metallic=0.7", "roughness=0.3",
                                                         "anisotropyStrength=0.6", "anisotropyRotation=0.4"},
                                                        anisotropic_material(),
                                                        "MeshPhysicalMaterial"}),
                         test_name);

// Fits of the shared MERL proxies (`brdffit fit TABLE -m gltf,gltf-specular,gltf+clearcoat,gltf+sheen`,
// values to four digits), as bench/renderer_image_error.sh draws them: measured materials, whose
// three.js pictures differ from brdffit's by up to 10 % (gold-metallic-paint, a rough metal). The
// documented departures must account for all of it.
RendererCase merl_gltf(const std::string& table, const std::string& base, const Rgb<double>& base_color,
                       double metallic, double roughness) {
  return {"gltf",
          {"baseColor=" + base, fmt::format("metallic={}", metallic), fmt::format("roughness={}", roughness)},
          GltfMaterial{base_color, metallic, roughness},
          "MeshStandardMaterial",
          table};
}

std::vector<RendererCase> merl_fits() {
  std::vector<RendererCase> cases = {
      merl_gltf("blue-acrylic", "0,0.01331,0.0869", {0.0, 0.01331, 0.0869}, 0.1991, 0.7261),
      merl_gltf("gold-metallic-paint", "0.3537,0.2155,0.05825", {0.3537, 0.2155, 0.05825}, 1.0, 0.661),
      merl_gltf("red-fabric", "0.2926,0.02385,0.0004523", {0.2926, 0.02385, 0.0004523}, 0.5209, 0.8928)};
  // blue-acrylic's gltf-specular: ior 3 and specular 0.01411, dielectric F0 ((3-1)/(3+1))²·0.01411.
  GltfMaterial specular{{0.01896, 0.04104, 0.1079}, 0.0, 0.1382};
  specular.dielectric_f0 = Rgb<double>::Constant(0.25 * 0.01411);
  specular.dielectric_f90 = 0.01411;
  cases.push_back({"gltf-specular",
                   {"baseColor=0.01896,0.04104,0.1079", "metallic=0", "roughness=0.1382", "ior=3", "specular=0.01411",
                    "specularColor=1,1,1"},
                   specular,
                   "MeshPhysicalMaterial",
                   "blue-acrylic"});
  GltfMaterial coated{{0.0, 0.01928, 0.09364}, 0.1548, 0.8431};
  coated.clearcoat = 0.01118;
  coated.clearcoat_roughness = 0.1422;
  cases.push_back({"gltf+clearcoat",
                   {"baseColor=0,0.01928,0.09364", "metallic=0.1548", "roughness=0.8431", "clearcoatFactor=0.01118",
                    "clearcoatRoughnessFactor=0.1422"},
                   coated,
                   "MeshPhysicalMaterial",
                   "blue-acrylic"});
  GltfMaterial sheened{{0.3507, 0.2188, 0.06031}, 1.0, 0.6464};
  sheened.sheen_color = Rgb<double>(0.1565, 0.0, 0.0);
  sheened.sheen_roughness = 0.252;
  cases.push_back({"gltf+sheen",
                   {"baseColor=0.3507,0.2188,0.06031", "metallic=1", "roughness=0.6464", "sheenColorFactor=0.1565,0,0",
                    "sheenRoughnessFactor=0.252"},
                   sheened,
                   "MeshPhysicalMaterial",
                   "gold-metallic-paint"});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(MerlFits, ThreeJs, ::testing::ValuesIn(merl_fits()), test_name);

}  // namespace
}  // namespace brdffit
