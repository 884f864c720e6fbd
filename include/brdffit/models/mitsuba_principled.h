// What Mitsuba 3's `principled` BSDF plugin evaluates (mitsuba3 src/bsdfs/principled.cpp with
// principledhelpers.h, read at commit b45b0a93), for an opaque material: the reflection (BRDF)
// part only, spec_trans = 0 and not thin (principledthin is another plugin). A fit of this model
// exported to Mitsuba is rendered as fitted; Burley's `principled` model is not what Mitsuba draws.
//
// Convention: the plugin's eval(wi, wo) returns f·|cosθo| with wi towards the viewer and wo
// towards the light (radiance transport); here l = wo, v = wi and the adapter multiplies f by n·l.
// The plugin computes in single precision; this model in double.
//
// With h = (l + v)/|l + v|, c = v·h (= l·h), C = base_color (linear RGB), m = metallic:
//   f = (1 - m)·C/π·mix(f_diff + f_retro, f_ss, flatness) + f_sheen + F·D·G/(4 n·l n·v) + f_cc
//   F_l, F_v = (1 - n·l)^5, (1 - n·v)^5 (Schlick weights);  R_r = 2·roughness·c²
//   f_diff = (1 - F_l/2)(1 - F_v/2);  f_retro = R_r (F_l + F_v + F_l F_v (R_r - 1))   (Burley 2015's split)
//   f_ss = 1.25 (F_ss (1/(n·l + n·v) - 0.5) + 0.5),  F_ss = mix(1, R_r/2, F_l)·mix(1, R_r/2, F_v)
//   C_tint = C/lum(C) with Rec. 709 luminance lum = 0.212671 R + 0.715160 G + 0.072169 B (1 when lum = 0)
//   f_sheen = sheen·(1 - m)·(1 - c)^5·mix(1, C_tint, sheen_tint)
//   η = 2/(1 - √(0.08·specular)) - 1, so that ((η-1)/(η+1))² = 0.08·specular
//   F = (1 - m)(1 - spec_tint)·F_dielectric(c, η) + m·S(C, c) + (1 - m)·spec_tint·S(0.08·specular·C_tint, c)
//     F_dielectric the exact unpolarised Fresnel reflectance of a dielectric of relative index η,
//     S(R0, c) = R0 + (1 - R0)(1 - c)^5 (Schlick)
//   D = GGX, α = max(0.001, roughness²): 1/(π α² ((h_x² + h_y²)/α² + h_z²)²)
//   G = G1(l)·G1(v), G1(w) = 2/(1 + √(1 + α² tan²θw))   (separable Smith; the 1/(4 n·l n·v) is explicit)
//   f_cc = ¼·clearcoat·F_cc·D_cc·G_cc (no 1/(4 n·l n·v): the plugin multiplies by |cosθo| only), with
//     F_cc = S(0.04, c), D_cc = GTR1, a = mix(0.1, 0.001, clearcoat_gloss): (a²-1)/(π ln(a²)(1 + (a²-1) h_z²)),
//     G_cc = G1(l)·G1(v) as above with α = 0.25.
// Where this differs from Burley's (models/principled.h): exact dielectric Fresnel from η rather
// than Schlick of 0.08·specular; Rec. 709 luminance for the tints rather than 0.3/0.6/0.1;
// the metal and dielectric lobes mixed after Fresnel; the diffuse split into diffuse + retro; and
// the clearcoat lobe without 1/(4 n·l n·v), which makes it several times brighter near normal
// incidence and dimmer at grazing angles.
//
// The plugin's f is reciprocal: every term is symmetric in l and v (c = v·h = l·h).
//
// Fitted: base_color, metallic, specular, roughness, spec_tint, sheen, sheen_tint, flatness,
// clearcoat, clearcoat_gloss (sheen_tint flagged not identifiable where there is no sheen). Held,
// and written into the exported file: anisotropic = 0 (the local frame's tangent of a measured
// isotropic table is arbitrary).
// Bounds: roughness ≥ 0.032 so that α = roughness² stays above the plugin's 0.001 clamp (where the
// derivative vanishes); specular ≥ 0.001, the floor the plugin itself applies when transmission is
// on: at specular = 0 exactly, η = 1, F_dielectric = 0 and the plugin skips the whole specular
// lobe, metallic part included (a jump the fitter must not meet).
//
// Nesting: none exact (the diffuse is not Lambert's and the Fresnel keeps a grazing lobe);
// Lambert's albedo as base_color and Burley's principled parameters copied by name are starts only.
#pragma once

#include "brdffit/model.h"
#include "brdffit/models/common.h"

namespace brdffit::models {

struct MitsubaPrincipled {
  static constexpr const char* kName = "mitsuba-principled";
  static constexpr const char* kSummary =
      "Mitsuba 3's principled BSDF as its plugin evaluates it (opaque): exact Fresnel, GGX, sheen, GTR1 clearcoat";
  static constexpr bool kEnergyConserving = false;  // the retro-reflection term exceeds albedo 1 for rough white
  enum : int {
    kBaseColor = 0,
    kMetallic = 3,
    kSpecular,
    kRoughness,
    kSpecTint,
    kSheen,
    kSheenTint,
    kFlatness,
    kClearcoat,
    kClearcoatGloss,
    kNumValues
  };
  static constexpr double kAnisotropic = 0.0;                                    // held (see above)
  static constexpr double kLumR = 0.212671, kLumG = 0.715160, kLumB = 0.072169;  // Rec. 709, as the plugin

  static std::vector<ParamSpec> parameters() {
    return {
        {"base_color", 3, 0.0, 1.0, 0.5, "surface colour (linear RGB): diffuse colour, metal F0", Role::DiffuseColour},
        {"metallic", 1, 0.0, 1.0, 0.0, "0 dielectric, 1 metal (mixes the Fresnel terms)"},
        {"specular", 1, 0.001, 1.0, 0.5, "dielectric Fresnel: eta = 2/(1 - sqrt(0.08 specular)) - 1 (0.5: 1.5)",
         Role::F0},
        {"roughness", 1, 0.032, 1.0, 0.5, "GGX alpha = roughness² (also shapes the retro-reflection)", Role::Roughness,
         false, false, Spacing::Log},
        {"spec_tint", 1, 0.0, 1.0, 0.0, "share of the dielectric Fresnel tinted towards the base colour (Schlick)"},
        {"sheen", 1, 0.0, 1.0, 0.0, "grazing sheen lobe (cloth)"},
        {"sheen_tint", 1, 0.0, 1.0, 0.5, "share of the sheen tinted towards the base colour"},
        {"flatness", 1, 0.0, 1.0, 0.0, "blend of the diffuse towards the Hanrahan-Krueger-like fake subsurface"},
        {"clearcoat", 1, 0.0, 1.0, 0.0, "strength of the GTR1 clearcoat lobe"},
        {"clearcoat_gloss", 1, 0.0, 1.0, 0.0, "clearcoat glossiness: GTR1 a = mix(0.1, 0.001, clearcoat_gloss)"}};
  }

  // Smith's G1 for isotropic GGX: 2/(1 + √(1 + α² tan²θw)); 1 at normal incidence.
  template <class T>
  static T smith_g1(const Vec3& w, const T& alpha) {
    using std::sqrt;
    const double cos2 = w.z() * w.z(), tan2 = (1.0 - cos2) / cos2;
    return 2.0 / (1.0 + sqrt(1.0 + alpha * alpha * tan2));
  }

  // The unpolarised Fresnel reflectance of a dielectric interface of relative index eta ≥ 1,
  // seen from outside at cos c.
  template <class T>
  static T fresnel_dielectric(double c, const T& eta) {
    using std::sqrt;
    const T cos_t = sqrt(1.0 - (1.0 - c * c) / (eta * eta));
    const T rs = (c - eta * cos_t) / (c + eta * cos_t), rp = (cos_t - eta * c) / (cos_t + eta * c);
    return 0.5 * (rs * rs + rp * rp);
  }

  template <class T>
  static Rgb<T> brdf(const T* p, const Vec3& l, const Vec3& v) {
    using std::log;
    using std::sqrt;
    const double nl = l.z(), nv = v.z();
    Rgb<T> f(T(0.0), T(0.0), T(0.0));
    if (nl <= 0.0 || nv <= 0.0) return f;  // the plugin's reflection lobes need both above (at 0 f·n·l is 0)
    const Vec3 h = half_vector(l, v);
    const double nh = h.z(), c = v.dot(h);
    const T* base = p + kBaseColor;
    const T lum = kLumR * base[0] + kLumG * base[1] + kLumB * base[2];
    const T metallic = p[kMetallic], roughness = p[kRoughness], dielectric = 1.0 - metallic;

    // Diffuse, retro-reflection and fake subsurface.
    const double fl = schlick_weight(nl), fv = schlick_weight(nv), fc = schlick_weight(c);
    const T rr = 2.0 * roughness * c * c;
    const T f_diff_retro = (1.0 - 0.5 * fl) * (1.0 - 0.5 * fv) + rr * (fl + fv + fl * fv * (rr - 1.0));
    const T fss = (1.0 + (0.5 * rr - 1.0) * fl) * (1.0 + (0.5 * rr - 1.0) * fv);
    const T f_ss = 1.25 * (fss * (1.0 / (nl + nv) - 0.5) + 0.5);
    const T diffuse_shape = dielectric * kInvPi * (f_diff_retro + (f_ss - f_diff_retro) * p[kFlatness]);

    // Main specular lobe: GGX, separable Smith, the plugin's Fresnel mix.
    const T alpha_squared_roughness = roughness * roughness;
    const T alpha = alpha_squared_roughness > T(0.001) ? alpha_squared_roughness : T(0.001);
    const T alpha2 = alpha * alpha;
    const T q = (h.x() * h.x() + h.y() * h.y()) / alpha2 + nh * nh;
    const T d = 1.0 / (kPi * alpha2 * q * q);
    const T g = smith_g1(l, alpha) * smith_g1(v, alpha);
    const T spec_shape = d * g / (4.0 * nl * nv);
    const T f0_dielectric = 0.08 * p[kSpecular];
    const T eta = 2.0 / (1.0 - sqrt(f0_dielectric)) - 1.0;
    const T f_dielectric = fresnel_dielectric(c, eta);

    // Clearcoat: as the plugin, without 1/(4 n·l n·v).
    const T a = 0.1 + (0.001 - 0.1) * p[kClearcoatGloss];
    const T a2 = a * a;
    const T d_cc = (a2 - 1.0) / (kPi * log(a2) * (1.0 + (a2 - 1.0) * nh * nh));
    const T g_cc = smith_g1(l, T(0.25)) * smith_g1(v, T(0.25));
    const T clearcoat = 0.25 * p[kClearcoat] * (0.04 + 0.96 * fc) * d_cc * g_cc;

    for (int ch = 0; ch < 3; ++ch) {
      const T tint = lum > T(0.0) ? T(base[ch] / lum) : T(1.0);
      const T metal_fresnel = base[ch] + (1.0 - base[ch]) * fc;
      const T tinted_r0 = f0_dielectric * tint;
      const T tinted_fresnel = tinted_r0 + (1.0 - tinted_r0) * fc;
      const T fresnel = dielectric * (1.0 - p[kSpecTint]) * f_dielectric + metallic * metal_fresnel +
                        dielectric * p[kSpecTint] * tinted_fresnel;
      const T sheen = p[kSheen] * dielectric * fc * (1.0 + (tint - 1.0) * p[kSheenTint]);
      f[ch] = diffuse_shape * base[ch] + sheen + fresnel * spec_shape + clearcoat;
    }
    return f;
  }

  // Fits of its own values (model.h): as principled's, except that the exact Fresnel of the eta
  // that specular gives separates metallic from specular: its trade-offs are only other basins of
  // almost equal cost.
  static RecoveryFacts recovery_facts() {
    return {/*material=*/{}, /*not_identifiable=*/{},
            RecoveryFacts::TradeOff{/*max_relative_error=*/0.035, /*max_error_over_truth=*/1.001}};
  }

  static std::vector<Nesting> nestings() {
    return {
        {"lambert",
         {{"base_color", "albedo"}},
         {{"metallic", 0.0}, {"specular", 0.001}, {"roughness", 0.5}},
         /*exact=*/false,
         "Lambert's albedo as base_color, almost no dielectric F0 (the retro-reflection and a grazing lobe remain)"},
        {"principled",
         {{"base_color", "baseColor"},
          {"metallic", "metallic"},
          {"specular", "specular"},
          {"roughness", "roughness"},
          {"spec_tint", "specularTint"},
          {"sheen", "sheen"},
          {"sheen_tint", "sheenTint"},
          {"flatness", "subsurface"},
          {"clearcoat", "clearcoat"},
          {"clearcoat_gloss", "clearcoatGloss"}},
         {},
         /*exact=*/false,
         "Burley's parameters copied by name; the plugin evaluates other Fresnel, tint and clearcoat terms"}};
  }
};

}  // namespace brdffit::models
