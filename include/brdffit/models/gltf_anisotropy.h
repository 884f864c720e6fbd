// glTF 2.0 metallic-roughness (models/gltf.h) with the anisotropic specular lobe of
// KHR_materials_anisotropy (KhronosGroup/glTF, extensions/2.0/Khronos/KHR_materials_anisotropy,
// "Anisotropy" and its "Implementation"): brushed metals, satins. The core BRDF's V·D becomes
//
//   D = 1 / (π α_t α_b ((h·t)²/α_t² + (h·b)²/α_b² + (h·n)²)²)                (Burley's, the spec's)
//   V = 1 / (2 (n·l |(α_t v·t, α_b v·b, n·v)| + n·v |(α_t l·t, α_b l·b, n·l)|))  (height-correlated Smith)
//   α_t = mix(α, 1, anisotropyStrength²),  α_b = α = roughness²
//   t = cos(anisotropyRotation)·x + sin(anisotropyRotation)·y,  b = n × t
// with x the tangent, y the bitangent and n the normal of the local frame. Everything else is
// the core material's (the Fresnels, the diffuse and its 1 - F weight). V is the one the
// extension's implementation gives, without its clamp at 1: the clamp is non-normative, the core
// glTF V (Appendix B) has none, and three.js's anisotropic V has none either. At strength 0,
// |(α v·t, α v·b, n·v)| = √(α² + (1 - α²)(n·v)²): Appendix B's V and D exactly.
//
// The tangent: a table's x axis (φ = 0) is the mesh's TANGENT of the exported glTF; on a sphere
// `brdffit render` draws, the tangent runs along the longitude, as a UV sphere's u
// (imaging/sphere.h's LocalFrame), which is where three.js puts it too.
//
// anisotropyRotation is in radians as in glTF, over [-π/4, 3π/4]: the lobe is the same turned by
// π, so any interval of length π holds every lobe once, and this one keeps both axis-aligned
// orientations (0 and π/2, the usual brushing directions of a measured sample) off its bounds.
// The strength stretches along t only; a lobe wider along y is a rotation of π/2.
//
// On isotropic data (every MERL table, isotropic RGL files) the fitter fits the isotropic form,
// `gltf` (strength 0, rotation held): such data cannot tell the widths apart or orient them, and
// a free fit would report a stretch the material does not have (model.h's isotropic_form).
//
// Reciprocal (D and V are symmetric in l and v, so is the core). Not energy conserving, only
// because the core is not (gltf.h).
//
// Nesting (exact): `gltf` with anisotropyStrength 0 (then α_t = α_b and the rotation changes
// nothing).
#pragma once

#include <cmath>

#include "brdffit/models/gltf.h"

namespace brdffit::models {

// The extension's V·D for roughness r (α = r²), strength s and rotation (radians) of the
// tangent t about the normal, for l and v above the surface.
template <class T>
T gltf_anisotropic_vd(const T& roughness, const T& strength, const T& rotation, const Vec3& l, const Vec3& v) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const double nl = l.z(), nv = v.z();
  const Vec3 h = half_vector(l, v);
  const T alpha_b = roughness * roughness, alpha_t = alpha_b + (1.0 - alpha_b) * (strength * strength);
  const T cos_t = cos(rotation), sin_t = sin(rotation);
  // Components along t and b = n × t = (-sin, cos, 0).
  const auto along_t = [&](const Vec3& d) { return cos_t * d.x() + sin_t * d.y(); };
  const auto along_b = [&](const Vec3& d) { return cos_t * d.y() - sin_t * d.x(); };
  const T ht = along_t(h) / alpha_t, hb = along_b(h) / alpha_b;
  const T stretched = ht * ht + hb * hb + h.z() * h.z();
  const T d = 1.0 / (kPi * alpha_t * alpha_b * stretched * stretched);
  const auto smith = [&](const Vec3& w) {
    const T wt = alpha_t * along_t(w), wb = alpha_b * along_b(w);
    return sqrt(wt * wt + wb * wb + w.z() * w.z());
  };
  return d / (2.0 * (nl * smith(v) + nv * smith(l)));
}

struct GltfAnisotropy {
  static constexpr const char* kName = "gltf+anisotropy";
  static constexpr const char* kSummary =
      "core glTF + KHR_materials_anisotropy: the GGX lobe stretched along the tangent, α_t = mix(α, 1, strength²)";
  static constexpr bool kEnergyConserving = false;  // as gltf's core
  static constexpr bool kSeparateChannels = true;
  static constexpr int kNumParameters = 5;
  enum : int {
    kBaseColor = 0,
    kMetallic = 3,
    kRoughness = 4,
    kAnisotropyStrength = 5,
    kAnisotropyRotation = 6,
    kNumValues = 7
  };

  static std::vector<ParamSpec> parameters() {
    return {gltf_base_color_param(),
            gltf_metallic_param(),
            gltf_roughness_param(),
            {"anisotropyStrength", 1, 0.0, 1.0, 0.5,
             "KHR_materials_anisotropy anisotropyStrength: stretches the lobe along the tangent, "
             "α_t = mix(roughness², 1, strength²) (0: isotropic)",
             Role::Anisotropy},
            {"anisotropyRotation", 1, -0.25 * kPi, 0.75 * kPi, 0.25 * kPi,
             "KHR_materials_anisotropy anisotropyRotation: the stretch's direction, radians counter-clockwise from "
             "the tangent (the table's x axis)",
             Role::Orientation}};
  }

  template <class T>
  static Rgb<T> brdf(const T* p, const Vec3& l, const Vec3& v) {
    if (l.z() <= 0.0 || v.z() <= 0.0) return Rgb<T>(T(0.0), T(0.0), T(0.0));
    const T specular = gltf_anisotropic_vd(p[kRoughness], p[kAnisotropyStrength], p[kAnisotropyRotation], l, v);
    return gltf_metallic_roughness(p + kBaseColor, p[kMetallic], specular, Rgb<double>(0.04, 0.04, 0.04), 1.0, l, v);
  }

  // The recovery tests' material (model.h): gltf's glossy roughness, stretched to α_t = 0.37
  // along a rotation off both axes.
  static RecoveryFacts recovery_facts() {
    return {/*material=*/{"roughness=0.4", "anisotropyStrength=0.5", "anisotropyRotation=0.6"}};
  }

  static std::vector<Nesting> nestings() {
    return {{"gltf",
             {{"baseColor", "baseColor"}, {"metallic", "metallic"}, {"roughness", "roughness"}},
             {{"anisotropyStrength", 0.0}, {"anisotropyRotation", 0.0}},
             /*exact=*/true,
             "anisotropyStrength 0: the core material's isotropic lobe"}};
  }
};

}  // namespace brdffit::models
