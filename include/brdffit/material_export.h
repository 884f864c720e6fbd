// A ggx fit as a material for renderers: a glTF 2.0 metallic-roughness material and a Mitsuba 3
// principled BSDF. The library side of `brdffit export`.
//
// Our ggx (models/ggx.h):  f = albedo/π + D·F·G/(4 n·l n·v),  D GGX with α = roughness²,
//                          F = f0 + (1 - f0)(1 - l·h)^5 per channel,  G Schlick-Smith (k = α/2).
// glTF 2.0 (spec, appendix B): f = (1-m)·[(1 - F_d)·base/π + F_d·D·V] + m·F_m·D·V, with D GGX of
//                          α = roughnessFactor², V the height-correlated Smith term, F_d Schlick
//                          with F0 = 0.04 (dielectric) and F_m Schlick with F0 = base (metal).
//
// Mapping (the same numbers for both formats):
//   roughness   roughnessFactor = roughness: both square it into the GGX α.
//   metallic m  glTF's material at normal incidence has diffuse reflectance (1-m)·0.96·base
//               (0.96 = 1 - 0.04, the light the dielectric coat lets through) and specular F0
//               0.04·(1-m) + m·base. Requiring both to equal the fit's albedo a and f0 f for the
//               luminance (Rec. 709) of each colour gives, with t = 1 - m,
//                   0.0384 t² - (a + 0.96 f) t + a = 0,
//               a root of which is t = 1 for a dielectric (f = 0.04) and t = 0 for a metal
//               (a = 0). The other root is L/0.04 for the base colour's luminance L, beyond 1
//               unless the colour is very dark; when both lie in [0, 1] the larger is taken (the
//               least metallic match). m = 1 - t, clamped to [0, 1]; m = 0 when there is no real
//               root (f0 below any dielectric's).
//   baseColor   per channel, with m fixed, the b in [0, 1] that best matches both equations
//               (least squares): b = ((1-m)·0.96·a + m·(f - 0.04(1-m))) / (((1-m)·0.96)² + m²).
// A fit whose colours are those of a glTF material (a grey-specular dielectric, a metal, or a
// blend of the two) is reproduced exactly at normal incidence; otherwise the albedo and f0 the
// material implies are reported beside the fitted ones. What the formats cannot carry: their
// shadowing term (height-correlated Smith) differs slightly from ours, glTF dims the diffuse
// term by 1 - F(v·h) rather than a constant, and coloured dielectric f0 has no place (a metallic
// blend approximates it). Per-channel fits export the mean of their three roughness values.
//
// Mitsuba 3: the `principled` BSDF, whose main lobe is GGX with α = roughness² (Disney's
// convention, as ours) and which takes glTF's parameters: base_color = baseColor, metallic = m,
// roughness = roughness, specular = 0.5 (its dielectric IOR 1.5, F0 = 0.04, as glTF's); sheen,
// clearcoat, spec_tint, anisotropic and spec_trans stay at 0. Its diffuse is Disney's (a slight
// retro-reflection at grazing angles) and its dielectric Fresnel the exact one for IOR 1.5.
// `roughconductor` (GGX, but no diffuse term, Fresnel from complex IOR) and `roughplastic` (GGX
// over a diffuse base, but one grey IOR and internal scattering that changes the diffuse colour)
// each capture only one side of the fit, and Mitsuba has no BSDF that adds two lobes
// (`blendbsdf` interpolates), so principled is the closest single plugin.
#pragma once

#include <string>

#include "brdffit/math.h"
#include "brdffit/result_json.h"

namespace brdffit {

struct MetallicRoughness {
  Rgb<double> base_color = Rgb<double>::Zero();
  double metallic = 0.0;
  double roughness = 0.5;
  // What the material implies at normal incidence (see above), to compare with the fit.
  Rgb<double> albedo = Rgb<double>::Zero();
  Rgb<double> f0 = Rgb<double>::Zero();
};

MetallicRoughness metallic_roughness(const Rgb<double>& albedo, const Rgb<double>& f0, double roughness);

// The ggx fit of a result document as metallic-roughness parameters. Throws Error naming the
// document when it has no ggx result or the ggx fit failed.
MetallicRoughness metallic_roughness_of(const FitDocument& document);

// A glTF 2.0 document (JSON text) holding one material named after the document's material,
// with the fitted values, the implied ones and the metrics under extras.brdffit.
std::string gltf_material(const FitDocument& document);
// A Mitsuba 3 scene file holding one principled BSDF with the material's name as its id, to be
// included in a scene (<include filename="..."/>) and referred to by <ref id="..."/>.
std::string mitsuba_bsdf(const FitDocument& document);

}  // namespace brdffit
