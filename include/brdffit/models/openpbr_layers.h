// OpenPBR Surface's coat and fuzz over the opaque base of models/openpbr.h: openpbr+coat,
// openpbr+fuzz and openpbr+coat+fuzz, with OpenPBR's parameter names. The layering is what
// MaterialX 1.39.4 renders an exported .mtlx with: its open_pbr_surface node graph
// (libraries/bxdf/open_pbr_surface.mtlx) and its pbrlib GLSL closures (mx_dielectric_bsdf,
// mx_sheen_bsdf, mx_layer_bsdf and their lib/ helpers). The base under the layers is brdffit's
// openpbr model unchanged (the specification's reciprocal form, see its header), so that
// coat_weight 0 and fuzz_weight 0 are exactly `openpbr`.
//
// MaterialX's layer(top, base) shades top + base·throughput(top), throughput = 1 - (the top's
// directional albedo from v): albedo scaling by the view's direction alone.
//
// Coat (C = coat_weight, rc = coat_roughness, nc = coat_ior, T = coat_color, all per channel where
// coloured; n·l, n·v > 0):
//
//   f = f_coat + τ · Δ · A · f_base(r', η_s)
//   f_coat = C · D(h; αc) · F(v·h; nc) · G2(l, v; αc) · comp / (4 n·l n·v),    αc = rc²
//   comp   = 1 + F(v·h; nc) · (1 - Ess) / Ess,  Ess = a + b           (Turquin's energy compensation)
//   τ      = 1 - C · (F0c·a + b) · comp,  F0c = ((nc - 1)/(nc + 1))²    (the coat's throughput)
//   a, b   = MaterialX's rational fit of GGX's directional albedo at (n·v, αc): E = F0·a + F90·b
//            (mx_ggx_dir_albedo_analytic, clamped to [0, 1]; its coefficients are in
//            materialx_ggx_albedo_fit below)
//   Δ      = lerp(1, (1 - K)/(1 - ρ·K), C),  K = 1 - (1 - F0c)/nc²         (darkening, ρ = base_color)
//   A      = lerp(1, T, C)                                                  (the coat's absorption)
//   r'     = lerp(r, min(1, r⁴ + 2 rc⁴)^¼, C)            (the base's specular_roughness, roughened)
//   η_s    = lerp(ns, max(ns/nc, nc/ns), C)             (the base's specular_ior relative to the coat)
//
// with D the GGX distribution, G2 Smith's height-correlated shadowing and F the exact dielectric
// Fresnel (models/microfacet.h, the same formulas as MaterialX's). coat_roughness_anisotropy is
// held at 0 (MaterialX's open_pbr_anisotropy is then α = rc² both ways; isotropic data could not
// tell, see openpbr.h's specular_roughness_anisotropy) and coat_darkening at its default 1 (it
// scales C in Δ only; a darkening below 1 is an artist's boost, not a measured property).
//
// Fuzz (W = fuzz_weight, Fz = fuzz_color, σ = fuzz_roughness), over what lies below (the coated
// base, or the base):
//
//   f·(n·l) = W · Fz · E(n·v, σ) · D_ltc(l | v, σ) + (1 - W · E(n·v, σ)) · f_below·(n·l)
//   E       = MaterialX's Gaussian fit of Zeltner et al. 2022's albedo (mx_zeltner_sheen_dir_albedo)
//   D_ltc   = cos⁺(w)/π · (a⁻¹/|w|²)²,  w = (a⁻¹ x + b⁻¹ z, a⁻¹ y, z),   (x, y, z) = l in the frame
//             whose x axis is v's tangential direction; a⁻¹, b⁻¹ MaterialX's rational fits at
//             (n·v, σ) (mx_zeltner_sheen_ltc_aInv, _bInv)
//
// i.e. the specification's albedo-scaled fuzz layer (the base is not tinted by the fuzz, E is
// grey). With both layers the fuzz is on top of the coat, as in the graph.
//
// Where this departs from the specification (what MaterialX's graph does instead, and brdffit
// follows): the coat_color absorption is the constant A, without the specification's
// view-dependent T^(1/μi + 1/μo) in the refracted cosines; the darkening's K is the rough base's
// K_r with F0c for the hemispherical Fresnel average E_F, and not blended towards K_s = F(ωo) by
// the base's roughness; the coat's layering (the specification leaves the operator to the
// implementation) is albedo scaling by τ(v) with MaterialX's fitted albedo and energy
// compensation; E and D_ltc are
// MaterialX's closed-form fits instead of Zeltner's tables. Where brdffit departs from MaterialX:
// the base is openpbr's (MaterialX layers its dielectric by albedo scaling with its own fitted
// albedo and adds energy compensation to the base's lobes; see openpbr.h), E is clamped at 0
// (MaterialX's Gaussian fit dips to -2e-5 near σ = 0.1, n·v ≈ 0.3), and fuzz_roughness is fitted
// in [0.1, 1] (MaterialX clamps it at 0.01; at σ = 0.05 the fuzz's albedo E is below 1 % beyond
// n·v = 0.044, a few grazing bins of a table, as with glTF's sheen), coat_roughness in [0.01, 1]
// with a fit's start at 0.1 (the specification's default 0 is a mirror, which no table
// resolves), coat_ior in [1, 3] (the specification's soft range).
//
// Neither layer is reciprocal: τ, E and the LTC's frame depend on v alone, as in MaterialX
// (brdffit's openpbr base, alone, is). Energy: the fuzz layer conserves it (D_ltc integrates to at
// most 1 and 0 ≤ E ≤ 0.75, so the fuzz takes from the base what it reflects); the coat does not
// quite: MaterialX's fitted albedo, which sets τ, is below the coat lobe's own by up to about 2 %,
// so a white base under a coat of roughness 0.3 and ior 1.8 reflects 1.02 at θo 60°.
//
// Nestings (exact): coat_weight 0 is `openpbr` (r' = r, η_s = ns, Δ = A = τ = 1, f_coat = 0);
// fuzz_weight 0 is `openpbr` (or openpbr+coat); openpbr+coat+fuzz holds openpbr+coat (fuzz_weight
// 0) and openpbr+fuzz (coat_weight 0).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "brdffit/models/openpbr.h"

namespace brdffit::models {

// MaterialX's rational fit of GGX's directional albedo at cosine mu and width alpha
// (mx_ggx_dir_albedo_analytic): the albedo is F0·scale + F90·bias, each clamped to [0, 1].
template <class T>
void materialx_ggx_albedo_fit(double mu, const T& alpha, T& scale, T& bias) {
  const double x = mu, x2 = mu * mu;
  const T y = alpha, y2 = alpha * alpha;
  // Four rational polynomials' coefficients of 1, x, y, xy, x², y², x²y, xy², x²y² (numerator of
  // scale, numerator of bias, denominator of scale, denominator of bias).
  constexpr double k[9][4] = {
      {0.1003, 0.9345, 1.0, 1.0},      {-0.6303, -2.323, -1.765, 0.2281}, {9.748, 2.229, 8.263, 15.94},
      {-2.038, -3.748, 11.53, -55.83}, {29.34, 1.424, 28.96, 13.08},      {-8.245, -0.7684, -7.507, 41.26},
      {-26.44, 1.436, -36.11, 54.9},   {19.99, 0.2913, 15.86, 300.2},     {-5.448, 0.6286, 33.37, -285.1}};
  std::array<T, 4> r;
  for (int i = 0; i < 4; ++i)
    r[i] = k[0][i] + k[1][i] * x + k[4][i] * x2 + y * (k[2][i] + k[3][i] * x + k[6][i] * x2) +
           y2 * (k[5][i] + k[7][i] * x + k[8][i] * x2);
  scale = saturate(T(r[0] / r[2]));
  bias = saturate(T(r[1] / r[3]));
}

// The coat over the openpbr base of values p (OpenPbr's layout), for n·l, n·v > 0; coat holds
// coat_weight, coat_color (3), coat_roughness, coat_ior.
template <class T>
Rgb<T> openpbr_coat_layer(const T* p, const T* coat, const Vec3& l, const Vec3& v) {
  using std::sqrt;
  const T &weight = coat[0], &coat_roughness = coat[4], &coat_ior = coat[5];
  const T* coat_color = coat + 1;
  if (constant_zero(weight)) return OpenPbr::brdf(p, l, v);  // no coat (math.h)
  // The terms of one or two parameters run on Jets of one or two derivatives (math.h).

  // The base as the coat changes it: roughened, its Fresnel relative to the coat's index.
  std::array<T, OpenPbr::kNumValues> base;
  std::copy_n(p, OpenPbr::kNumValues, base.begin());
  const T r = p[OpenPbr::kSpecularRoughness];
  const T combined_roughness = of_two_parameters(r, coat_roughness, [](const auto& r, const auto& rc) {
    using R = std::decay_t<decltype(r)>;
    const R r2 = r * r, rc2 = rc * rc, variance = r2 * r2 + 2.0 * (rc2 * rc2);
    return R(sqrt(sqrt(variance < R(1.0) ? variance : R(1.0))));
  });
  base[OpenPbr::kSpecularRoughness] = r + weight * (combined_roughness - r);
  const T specular_ior = p[OpenPbr::kSpecularIor];
  const T relative_ior = specular_ior > coat_ior ? T(specular_ior / coat_ior) : T(coat_ior / specular_ior);
  base[OpenPbr::kSpecularIor] = specular_ior + weight * (relative_ior - specular_ior);
  const Rgb<T> below = OpenPbr::brdf(base.data(), l, v);

  // The coat's lobe at full weight, and the part of the light it reflects from v (1 - throughput
  // at full weight): both functions of its roughness and ior, sharing their Fresnel, fitted albedo
  // and energy compensation, so evaluated together.
  const double nl = l.z(), nv = v.z();
  const Vec3 h = half_vector(l, v);
  const auto [full_lobe, full_reflected] = of_parameters(
      [&](const auto& rc, const auto& nc) {
        using R = std::decay_t<decltype(rc)>;
        const R alpha = rc * rc;
        const R fresnel = dielectric_fresnel(v.dot(h), nc);
        R scale, bias;
        materialx_ggx_albedo_fit(nv, alpha, scale, bias);
        const R single_scattering = scale + bias;
        const R compensation = 1.0 + fresnel * (1.0 - single_scattering) / single_scattering;
        const R f0_root = (nc - 1.0) / (nc + 1.0);
        const R reflected = (f0_root * f0_root * scale + bias) * compensation;
        // Isotropic D and G2 in MaterialX's form: D = α²/(π((n·h)²(α² - 1) + 1)²) and
        // G2/(4 n·l n·v) = 1/(2(λl n·v + λv n·l)), λ = √(α² + (1 - α²)μ²).
        const R alpha2 = alpha * alpha, ndf_root = h.z() * h.z() * (alpha2 - 1.0) + 1.0;
        const R lambda_l = sqrt(alpha2 + (1.0 - alpha2) * (nl * nl)),
                lambda_v = sqrt(alpha2 + (1.0 - alpha2) * (nv * nv));
        const R lobe =
            alpha2 * fresnel * compensation / (2.0 * kPi * ndf_root * ndf_root * (lambda_l * nv + lambda_v * nl));
        return std::array<R, 2>{lobe, reflected};
      },
      coat_roughness, coat_ior);
  const T lobe = weight * full_lobe;
  const T throughput = 1.0 - weight * full_reflected;

  // Darkening by the coat's internal reflections (K), and its absorption.
  const T internal_reflection = of_one_parameter(coat_ior, [](const auto& nc) {
    const auto f0_root = (nc - 1.0) / (nc + 1.0);
    return 1.0 - (1.0 - f0_root * f0_root) / (nc * nc);
  });
  Rgb<T> f;
  for (int c = 0; c < 3; ++c) {
    const T rho = p[OpenPbr::kBaseColor + c];
    const T darkening = 1.0 + weight * ((1.0 - internal_reflection) / (1.0 - rho * internal_reflection) - 1.0);
    const T absorption = 1.0 + weight * (coat_color[c] - 1.0);
    f[c] = lobe + throughput * darkening * absorption * below[c];
  }
  return f;
}

// The fuzz over `below` (a BRDF), for n·l, n·v > 0; fuzz holds fuzz_weight, fuzz_color (3),
// fuzz_roughness (within [0.1, 1]: MaterialX's clamp at 0.01 never acts).
template <class T>
Rgb<T> openpbr_fuzz_layer(const Rgb<T>& below, const T* fuzz, const Vec3& l, const Vec3& v) {
  const T &weight = fuzz[0], &sigma = fuzz[4];
  const T* fuzz_color = fuzz + 1;
  if (constant_zero(weight)) return below;  // no fuzz (math.h)
  const double x = v.z();

  // E(n·v, σ): MaterialX's Gaussian in n·v, of width s, centre m and offset o fitted in σ.
  auto albedo_of = [x](const auto& sigma) {
    using S = std::decay_t<decltype(sigma)>;
    using std::exp;
    const S s = sigma * (0.0206607 + 1.58491 * sigma) / (0.0379424 + sigma * (1.32227 + sigma));
    const S m =
        sigma * (-0.193854 + sigma * (-1.14885 + sigma * (1.7932 - 0.95943 * sigma * sigma))) / (0.046391 + sigma);
    const S o =
        sigma * (0.000654023 + (-0.0207818 + 0.119681 * sigma) * sigma) / (1.26264 + sigma * (-1.92021 + sigma));
    const S z = (x - m) / s;
    return max0(S(exp(-0.5 * z * z) / (s * std::sqrt(2.0 * kPi)) + o));
  };

  // l in the LTC's frame: x along v's tangential direction (any, for v = n), z = n.
  const double tangential = std::sqrt(v.x() * v.x() + v.y() * v.y());  // v is a unit vector: no hypot needed
  const double cx = tangential > 0.0 ? v.x() / tangential : 1.0, cy = tangential > 0.0 ? v.y() / tangential : 0.0;
  const double wx = l.x() * cx + l.y() * cy, wy = l.y() * cx - l.x() * cy, wz = l.z();
  // The fuzz's BRDF at full weight and its albedo E, functions of σ alone (terms of one parameter
  // run on Jets of one derivative, math.h): D_ltc / (n·l) = (a⁻¹/|w|²)²/π (the transformed
  // cosine's w_z is n·l > 0), times E.
  const auto [unit_fuzz_brdf, fuzz_albedo] = of_parameters(
      [&](const auto& sigma) {
        using S = std::decay_t<decltype(sigma)>;
        const S a_inv = (2.58126 * x + 0.813703 * sigma) * sigma / (1.0 + 0.310327 * x * x + 2.60994 * x * sigma);
        const S b_inv = std::sqrt(1.0 - x) * (sigma - 1.0) * sigma * sigma * sigma /
                        (0.0000254053 + 1.71228 * x - 1.71506 * x * sigma + 1.34174 * sigma * sigma);
        const S ox = a_inv * wx + b_inv * wz, oy = a_inv * wy;
        const S length2 = ox * ox + oy * oy + wz * wz;
        const S ratio = a_inv / length2;
        const S albedo = albedo_of(sigma);
        return std::array<S, 2>{S(albedo * ratio * ratio * kInvPi), albedo};
      },
      sigma);
  const T fuzz_brdf = weight * unit_fuzz_brdf;
  const T through = 1.0 - weight * fuzz_albedo;
  Rgb<T> f;
  for (int c = 0; c < 3; ++c) f[c] = fuzz_color[c] * fuzz_brdf + through * below[c];
  return f;
}

inline std::vector<ParamSpec> openpbr_coat_params() {
  return {{"coat_weight", 1, 0.0, 1.0, 0.0, "presence weight of the coat (0: no coat)"},
          {"coat_color", 3, 0.0, 1.0, 1.0,
           "the coat's absorption: tint of everything under it, not of its own reflection (linear RGB)",
           Role::SpecularColour, /*linear=*/true},
          {"coat_roughness", 1, 0.01, 1.0, 0.1, "roughness of the coat's GGX lobe, alpha = roughness²", Role::Roughness,
           false, false, Spacing::Log},
          {"coat_ior", 1, 1.0, 3.0, 1.6, "index of refraction of the coat", Role::F0}};
}

inline std::vector<ParamSpec> openpbr_fuzz_params() {
  return {
      {"fuzz_weight", 1, 0.0, 1.0, 0.0, "presence weight of the fuzz (0: no fuzz)"},
      {"fuzz_color", 3, 0.0, 1.0, 1.0, "colour of the fuzz's reflection (linear RGB)", Role::SpecularColour,
       /*linear=*/true},
      {"fuzz_roughness", 1, 0.1, 1.0, 0.5, "roughness of the fuzz: fibre-like (low) to dusty (high)", Role::Roughness}};
}

// openpbr with its coat, its fuzz or both (see the head of the file): one struct for the three,
// its values openpbr's, then the coat's, then the fuzz's.
template <bool kHasCoat, bool kHasFuzz>
struct OpenPbrLayers {
  static_assert(kHasCoat || kHasFuzz, "without a layer it is openpbr");
  static constexpr const char* kName = !kHasFuzz ? "openpbr+coat" : kHasCoat ? "openpbr+coat+fuzz" : "openpbr+fuzz";
  static constexpr const char* kSummary =
      !kHasFuzz ? "OpenPBR Surface's coat over its opaque base, as MaterialX's open_pbr_surface layers it"
      : kHasCoat
          ? "OpenPBR Surface's fuzz over its coat over its opaque base, as MaterialX's open_pbr_surface layers them"
          : "OpenPBR Surface's fuzz (Zeltner's LTC sheen) over its opaque base, as MaterialX layers it";
  static constexpr bool kEnergyConserving = !kHasCoat;  // the coat's fitted albedo (see above)
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 6 + (kHasCoat ? 4 : 0) + (kHasFuzz ? 3 : 0);
  static constexpr int kCoat = OpenPbr::kNumValues;                       // coat_weight, then the coat's others
  static constexpr int kFuzz = OpenPbr::kNumValues + (kHasCoat ? 6 : 0);  // fuzz_weight, then the fuzz's others
  static constexpr int kNumValues = kFuzz + (kHasFuzz ? 5 : 0);

  static std::vector<ParamSpec> parameters() {
    std::vector<ParamSpec> params = OpenPbr::parameters();
    if (kHasCoat)
      for (ParamSpec& p : openpbr_coat_params()) params.push_back(p);
    if (kHasFuzz)
      for (ParamSpec& p : openpbr_fuzz_params()) params.push_back(p);
    return params;
  }

  template <class T>
  static Rgb<T> brdf(const T* p, const Vec3& l, const Vec3& v) {
    if (l.z() <= 0.0 || v.z() <= 0.0) return Rgb<T>(T(0.0), T(0.0), T(0.0));
    // What lies under the fuzz depends on the base's and the coat's parameters alone: it runs on
    // Jets of their derivatives only (math.h), not the fuzz's too.
    constexpr int kBelowParameters = OpenPbr::kNumParameters + (kHasCoat ? 4 : 0);
    const auto below = [&l, &v](const auto* q) {
      if constexpr (kHasCoat)
        return openpbr_coat_layer(q, q + kCoat, l, v);
      else
        return OpenPbr::brdf(q, l, v);
    };
    if constexpr (kHasFuzz)
      return openpbr_fuzz_layer(on_leading_slots<kBelowParameters, kFuzz>(below, p), p + kFuzz, l, v);
    else
      return below(p);
  }

  // As openpbr's (its ior and colours trade off), and the coat's colour with the base's (see
  // tests/test_openpbr_layers.cc). The recovered coat is a glossy one (α = 0.0625), not the middle
  // of coat_roughness's log range (α of 0.006 or less, a mirror random directions rarely see).
  static RecoveryFacts recovery_facts() {
    RecoveryFacts facts = OpenPbr::recovery_facts();
    if (kHasCoat) facts.material = {"coat_roughness=0.25"};
    return facts;
  }

  static std::vector<Nesting> nestings() {
    std::vector<Nesting::Copy> base;
    for (const ParamSpec& p : OpenPbr::parameters()) base.push_back({p.name, p.name});
    auto with = [&base](const std::vector<ParamSpec>& layer) {
      std::vector<Nesting::Copy> copies = base;
      for (const ParamSpec& p : layer) copies.push_back({p.name, p.name});
      return copies;
    };
    if (kHasCoat && kHasFuzz)
      return {{"openpbr+coat",
               with(openpbr_coat_params()),
               {{"fuzz_weight", 0.0}},
               true,
               "fuzz_weight 0 removes the fuzz: the coat over the base"},
              {"openpbr+fuzz",
               with(openpbr_fuzz_params()),
               {{"coat_weight", 0.0}},
               true,
               "coat_weight 0 removes the coat: the fuzz over the base"}};
    return {{"openpbr",
             base,
             {{kHasCoat ? "coat_weight" : "fuzz_weight", 0.0}},
             true,
             kHasCoat ? "coat_weight 0 removes the coat: the openpbr base"
                      : "fuzz_weight 0 removes the fuzz: the openpbr base"}};
  }
};

using OpenPbrCoat = OpenPbrLayers<true, false>;
using OpenPbrFuzz = OpenPbrLayers<false, true>;
using OpenPbrCoatFuzz = OpenPbrLayers<true, true>;

}  // namespace brdffit::models
