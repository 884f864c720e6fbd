// The Disney "principled" BRDF of Burley 2012, "Physically-Based Shading at Disney", as
// published with BRDF Explorer (wdas/brdf, src/brdfs/disney.brdf):
//
//   f = ((1/π)·mix(F_d, ss, subsurface)·C + F_sheen)·(1 - metallic) + G_s·F_s·D_s + ¼·clearcoat·G_r·F_r·D_r
//   F_L, F_V = (1 - n·l)^5, (1 - n·v)^5;  F_H = (1 - l·h)^5
//   F_d = mix(1, F_d90, F_L)·mix(1, F_d90, F_V),  F_d90 = 0.5 + 2 (l·h)² roughness
//   ss  = 1.25 (F_ss (1/(n·l + n·v) - 0.5) + 0.5),  F_ss = mix(1, F_ss90, F_L)·mix(1, F_ss90, F_V), F_ss90 = (l·h)²
//   C_tint = C / lum(C) (lum = 0.3 R + 0.6 G + 0.1 B; 1 when lum = 0)
//   C_spec0 = mix(0.08·specular·mix(1, C_tint, specularTint), C, metallic);  F_s = mix(C_spec0, 1, F_H)
//   D_s = GTR2 (GGX) with αx = max(0.001, roughness²/aspect), αy = max(0.001, roughness²·aspect),
//         aspect = √(1 - 0.9 anisotropic)
//   G_s = separable Smith GGX written as 1/(n·w + √((w·x αx)² + (w·y αy)² + (n·w)²)) per direction
//         (the 1/(4 n·l n·v) is folded in)
//   x, y: the frame's tangent and bitangent turned by anisotropicRotation about n
//   F_sheen = F_H·sheen·mix(1, C_tint, sheenTint)
//   D_r = GTR1 with a = mix(0.1, 0.001, clearcoatGloss): (a²-1)/(π ln(a²)(1 + (a²-1)(n·h)²))
//   F_r = mix(0.04, 1, F_H),  G_r = Smith GGX as above with α = 0.25 for both directions
//
// C = baseColor is linear RGB here: BRDF Explorer's shader applies mon2lin (x^2.2) to its colour
// pickers, a display convention; renderers (Mitsuba 3's `principled`, Blender's) take linear colour.
//
// Fitted: every parameter of the shader: baseColor, metallic, subsurface, specular, roughness,
// specularTint, anisotropic, sheen, sheenTint, clearcoat, clearcoatGloss; and anisotropicRotation,
// which the shader takes from the mesh's tangent (Blender's principled BSDF has it as "Anisotropic
// Rotation", a fraction of a turn). sheenTint only matters where sheen does: with no sheen the fit
// flags it not identifiable rather than report its start (0.5, the published default). On
// isotropic data (every MERL table, isotropic RGL files) anisotropic is held at 0 and the rotation
// at its default (model.h's isotropic_holds): such data cannot tell a stretch from a wider lobe
// or orient it. The rotation spans [-π/4, 3π/4], radians: the lobe is the same turned by π, and
// both axis-aligned orientations stay off the bounds (as gltf+anisotropy's). roughness is bounded
// below by 0.032 so that α = roughness² stays above the shader's 0.001 clamp, where the
// derivative would vanish.
//
// Nesting: none exact (even with specular 0 the Fresnel F_H keeps a grazing specular lobe, and
// F_d is not Lambert's); Lambert's albedo as baseColor with specular 0 is a start only.
#pragma once

#include "brdffit/model.h"
#include "brdffit/models/common.h"

namespace brdffit::models {

struct Principled {
  static constexpr const char* kName = "principled";
  static constexpr const char* kSummary =
      "Disney principled BRDF (Burley 2012, wdas/brdf disney.brdf): diffuse+subsurface, GGX, sheen, GTR1 clearcoat";
  static constexpr bool kEnergyConserving = false;  // Burley's diffuse exceeds albedo 1 at grazing for rough white
  enum : int {
    kBaseColor = 0,
    kMetallic = 3,
    kSubsurface,
    kSpecular,
    kRoughness,
    kSpecularTint,
    kSheen,
    kSheenTint,
    kClearcoat,
    kClearcoatGloss,
    kAnisotropic,
    kAnisotropicRotation,
    kNumValues
  };

  static std::vector<ParamSpec> parameters() {
    return {
        {"baseColor", 3, 0.0, 1.0, 0.5, "surface colour (linear RGB): diffuse colour, metal F0", Role::DiffuseColour},
        {"metallic", 1, 0.0, 1.0, 0.0, "0 dielectric, 1 metal (linear blend)"},
        {"subsurface", 1, 0.0, 1.0, 0.0, "blend of the diffuse towards Hanrahan-Krueger-like subsurface"},
        {"specular", 1, 0.0, 1.0, 0.5, "dielectric specular amount; F0 = 0.08·specular (0.5 = 4%, ior 1.5)", Role::F0},
        {"roughness", 1, 0.032, 1.0, 0.5, "perceptual roughness, GGX alpha = roughness² (also shapes the diffuse)",
         Role::Roughness, false, false, Spacing::Log},
        {"specularTint", 1, 0.0, 1.0, 0.0, "tints the dielectric F0 towards the base colour's hue"},
        {"sheen", 1, 0.0, 1.0, 0.0, "grazing retro-reflective sheen (cloth)"},
        {"sheenTint", 1, 0.0, 1.0, 0.5, "tints the sheen towards the base colour's hue"},
        {"clearcoat", 1, 0.0, 1.0, 0.0, "strength of the second, fixed-roughness GTR1 specular lobe"},
        {"clearcoatGloss", 1, 0.0, 1.0, 1.0, "clearcoat glossiness: GTR1 a = mix(0.1, 0.001, clearcoatGloss)"},
        {"anisotropic", 1, 0.0, 1.0, 0.0,
         "stretches the specular lobe along the tangent: aspect = √(1 - 0.9 anisotropic) (0: isotropic)",
         Role::Anisotropy},
        {"anisotropicRotation", 1, -0.25 * kPi, 0.75 * kPi, 0.0,
         "the stretch's direction, radians counter-clockwise from the tangent (the table's x axis)",
         Role::Orientation}};
  }

  // 1 / (n·w + √((w·x αx)² + (w·y αy)² + (n·w)²)): Smith G1/(2 n·w) for anisotropic GGX, with
  // (w·x, w·y) = `along` (the frame's tangent and bitangent).
  template <class T>
  static T smith_g_ggx(const TangentXY<T>& along, double nw, const T& ax, const T& ay) {
    using std::sqrt;
    const T sx = along.x * ax, sy = along.y * ay;
    return 1.0 / (nw + sqrt(sx * sx + sy * sy + nw * nw));
  }

  template <class T>
  static Rgb<T> brdf(const T* p, const Vec3& l, const Vec3& v) {
    using std::log;
    using std::sqrt;
    const double nl = l.z(), nv = v.z();
    Rgb<T> f(T(0.0), T(0.0), T(0.0));
    if (nl <= 0.0 || nv <= 0.0) return f;  // the shader tests < 0; at 0 the shaded value is 0 anyway
    const Vec3 h = half_vector(l, v);
    const double nh = h.z(), lh = l.dot(h);
    const T* base = p + kBaseColor;
    const T lum = 0.3 * base[0] + 0.6 * base[1] + 0.1 * base[2];
    const T metallic = p[kMetallic], roughness = p[kRoughness];

    const double fl = schlick_weight(nl), fv = schlick_weight(nv), fh = schlick_weight(lh);
    const T fd90 = 0.5 + 2.0 * lh * lh * roughness;
    const T fd = (1.0 + (fd90 - 1.0) * fl) * (1.0 + (fd90 - 1.0) * fv);
    const T fss90 = lh * lh * roughness;
    const T fss = (1.0 + (fss90 - 1.0) * fl) * (1.0 + (fss90 - 1.0) * fv);
    const T ss = 1.25 * (fss * (1.0 / (nl + nv) - 0.5) + 0.5);
    const T diffuse_shape = kInvPi * (fd + (ss - fd) * p[kSubsurface]);

    const T aspect = sqrt(1.0 - p[kAnisotropic] * 0.9);
    const T alpha = roughness * roughness;
    const T ax = alpha / aspect > T(0.001) ? T(alpha / aspect) : T(0.001);
    const T ay = alpha * aspect > T(0.001) ? T(alpha * aspect) : T(0.001);
    const T rotation_degrees = p[kAnisotropicRotation] * (180.0 / kPi);
    const TangentXY<T> ht = in_tangent_frame(h, rotation_degrees);
    const T hx = ht.x / ax, hy = ht.y / ay;
    const T q = hx * hx + hy * hy + nh * nh;
    const T ds = 1.0 / (kPi * ax * ay * q * q);
    const T gs = smith_g_ggx(in_tangent_frame(l, rotation_degrees), nl, ax, ay) *
                 smith_g_ggx(in_tangent_frame(v, rotation_degrees), nv, ax, ay);

    const T a = 0.1 + (0.001 - 0.1) * p[kClearcoatGloss];
    const T a2 = a * a;
    const T dr = (a2 - 1.0) / (kPi * log(a2) * (1.0 + (a2 - 1.0) * nh * nh));
    const double fr = 0.04 + 0.96 * fh;
    // The clear coat is isotropic: any frame gives the same G_r.
    const TangentXY<T> lxy{T(l.x()), T(l.y())}, vxy{T(v.x()), T(v.y())};
    const T gr = smith_g_ggx(lxy, nl, T(0.25), T(0.25)) * smith_g_ggx(vxy, nv, T(0.25), T(0.25));
    const T clearcoat = 0.25 * p[kClearcoat] * gr * fr * dr;

    for (int c = 0; c < 3; ++c) {
      const T tint = lum > T(0.0) ? T(base[c] / lum) : T(1.0);
      const T spec0_dielectric = p[kSpecular] * 0.08 * (1.0 + (tint - 1.0) * p[kSpecularTint]);
      const T spec0 = spec0_dielectric + (base[c] - spec0_dielectric) * metallic;
      const T fs = spec0 + (1.0 - spec0) * fh;
      const T sheen = fh * p[kSheen] * (1.0 + (tint - 1.0) * p[kSheenTint]);
      f[c] = (diffuse_shape * base[c] + sheen) * (1.0 - metallic) + gs * fs * ds + clearcoat;
    }
    return f;
  }

  // Fits of its own values (model.h): specular against specularTint and metallic shape F0 and
  // its tint together (Schlick F0 = mix(0.08·specular·tint, baseColor, metallic)), so metallic and
  // specular are flagged locally, and baseColor with them: the direction along which the cost
  // stays flat moves it too (17 % of that direction in blue at this material; 3-12 % at others,
  // where it is not flagged). Fits also end in other basins of almost equal cost, 2.3 % from the
  // material on fresh directions. A stretched lobe of a glossy roughness: a sharper one (the
  // middle of the log range, 0.18) is rarely seen by random directions.
  static RecoveryFacts recovery_facts() {
    return {/*material=*/{"roughness=0.5", "anisotropic=0.6"},
            /*not_identifiable=*/{"baseColor", "metallic", "specular"},
            RecoveryFacts::TradeOff{/*max_relative_error=*/0.035, /*max_error_over_truth=*/1.001}};
  }

  static std::vector<Nesting> nestings() {
    return {{"lambert",
             {{"baseColor", "albedo"}},
             {{"metallic", 0.0}, {"specular", 0.0}, {"roughness", 0.5}},
             /*exact=*/false,
             "Lambert's albedo as baseColor, no dielectric F0 (Burley's diffuse and a grazing lobe remain)"}};
  }
};

}  // namespace brdffit::models
