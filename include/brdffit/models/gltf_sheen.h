// glTF 2.0 metallic-roughness (models/gltf.h) under the sheen of KHR_materials_sheen
// (KhronosGroup/glTF, extensions/2.0/Khronos/KHR_materials_sheen, the ratified text: "Sheen" and
// its "Implementation Notes"), with the formulas written there:
//
//   f = f_sheen + material · sheenAlbedoScaling
//   material  = the core glTF BRDF (Appendix B, models/gltf.h) of baseColor, metallic, roughness
//   f_sheen   = sheenColor · D_S · V_S                           (sheen Fresnel omitted, F = 1)
//   D_S       = (2 + 1/α) · sin²θh^(1/(2α)) / (2π),   α = sheenRoughness²    ("Charlie", Conty & Kulla 2017)
//   V_S       = 1 / ((1 + Λ(n·v) + Λ(n·l)) · 4 n·v n·l)        ("Charlie" visibility, the spec's first choice)
//   Λ(μ)      = exp(L(μ)) for μ < 0.5, exp(2 L(0.5) - L(1 - μ)) else,
//   L(x)      = a/(1 + b x^c) + d x + e, a..e mixed between the spec's two sets by (1 - α)²
//   sheenAlbedoScaling = min(1 - max3(sheenColor)·E(n·v), 1 - max3(sheenColor)·E(n·l))
// where E(μ) is the sheen's directional albedo: ∫ D_S V_S (n·l) dω_l for sheenColor 1, which the
// spec says to look up in a table (Enterprise PBR 2021x, §6.2.3, for the Charlie visibility) at
// x = n·v, y = sheenRoughness. Textures are not fitted (factors only).
//
// The albedo scaling: the spec's full form, min over both directions, not its "simplified" one
// with E(n·v) alone. Both are the spec's; the full one is what the spec gives first, what three.js
// computes for a direct light (1 - max3·max(E(n·v), E(n·l)) is the same number), and it keeps
// the model reciprocal: f_sheen, Appendix B and the min over {l, v} are each symmetric in l and
// v, so f(l, v) = f(v, l). E: integrated here from its definition (the spec's D_S and V_S),
// once per process, on a table of 49 n·v × 37 sheenRoughness nodes (√(n·v) from √0.001 to 1,
// sheenRoughness 0.1 to 1; Gauss-Legendre in √(n·l) × midpoints in φ, 32 × 32) with Catmull-Rom
// interpolation in both, so the fit differentiates it in sheenRoughness: within 1e-3 of the
// integral (5e-4 away from E = 1). Two departures, both where the spec's numbers stop being a
// reflectance: E is read at n·v = 0.001 below it (Λ's fit makes μ·Λ(μ) fall to 0 and E grow
// without bound as μ → 0); and E is at most 1: with Conty and Kulla's fitted Λ, E exceeds 1 for
// sheenRoughness below 0.26 near grazing (1.15 at sheenRoughness 0.2 and n·v 0.03), where
// 1 - max3·E would make the base negative. three.js clamps its E to [0, 1] too.
//
// Not energy conserving, only because the base is not (gltf.h): sheenColor 0 is gltf.
//
// Nesting (exact): `gltf` with sheenColorFactor 0 ("the whole sheen layer is disabled").
// sheenRoughnessFactor's lower bound is 0.1 (the extension's default 0 is a lobe at exactly
// grazing half vectors; at 0.1 the sheen is within 10° of grazing already, D_S ∝ sin¹⁰⁰θh).
//
// gltf+clearcoat+sheen (GltfClearcoatSheen): both extensions, the clear coat layered on top of the
// sheen as KHR_materials_sheen says ("clearcoat is layered on top of sheen"): the coat's mix
// (models/gltf_clearcoat.h) applied to this model's f.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "brdffit/models/gltf.h"
#include "brdffit/models/gltf_clearcoat.h"

namespace brdffit::models {

// The Charlie sheen of the spec at one sheenRoughness r (α = r²): its distribution D_S and the
// Λ of its visibility, with what depends on r alone (1/α, Λ's coefficients, each a mix in α, and
// 2 L(0.5)) computed once.
template <class T>
class SheenCharlie {
 public:
  explicit SheenCharlie(const T& sheen_roughness) : inv_alpha_(1.0 / (sheen_roughness * sheen_roughness)) {
    const T alpha = sheen_roughness * sheen_roughness;
    const T t = (1.0 - alpha) * (1.0 - alpha);
    const auto mix = [&t](double x, double y) { return x + (y - x) * t; };
    a_ = mix(21.5473, 25.3245);
    b_ = mix(3.82987, 3.32435);
    c_ = mix(0.19823, 0.16801);
    d_ = mix(-1.97760, -1.27393);
    e_ = mix(-4.32054, -4.85967);
    twice_at_half_ = 2.0 * l(0.5);
  }

  // D_S at n·h.
  T d(double nh) const {
    return (2.0 + inv_alpha_) * pow_of_direction_term(1.0 - nh * nh, 0.5 * inv_alpha_) / (2.0 * kPi);
  }
  // Λ at a cosine μ in (0, 1].
  T lambda(double mu) const {
    using std::exp;
    return mu < 0.5 ? T(exp(l(mu))) : T(exp(twice_at_half_ - l(1.0 - mu)));
  }

 private:
  T l(double x) const { return a_ / (1.0 + b_ * pow_of_direction_term(x, c_)) + d_ * x + e_; }
  T inv_alpha_, a_, b_, c_, d_, e_, twice_at_half_;
};

// E(μ, sheenRoughness), the directional albedo of D_S·V_S, tabulated once (see the head of this file).
class SheenAlbedo {
 public:
  static constexpr int kMuNodes = 49, kRoughnessNodes = 37;
  static constexpr double kMinMu = 0.001, kMinRoughness = 0.1;

  static const SheenAlbedo& table() {
    static const SheenAlbedo instance;
    return instance;
  }

  // E from its definition, by quadrature: Gauss-Legendre in u = √(n·l) (Λ's x^c is steep at n·l → 0),
  // midpoints in φ over [0, π] (the integrand is even in φ).
  static double integrate(double mu, double sheen_roughness, int nodes) {
    std::vector<double> u, w;
    gauss_legendre(nodes, u, w);
    const Vec3 v(std::sqrt(1.0 - mu * mu), 0.0, mu);
    const SheenCharlie<double> sheen(sheen_roughness);
    const double lambda_v = sheen.lambda(mu);
    double sum = 0.0;
    for (int i = 0; i < nodes; ++i) {
      const double nl = u[i] * u[i], sin_l = std::sqrt(1.0 - nl * nl);
      // D_S·V_S·(n·l) = D_S / ((1 + Λ(n·v) + Λ(n·l)) · 4 n·v): Λ(n·l) once per ring.
      const double ring_factor = 1.0 / ((1.0 + lambda_v + sheen.lambda(nl)) * 4.0 * mu);
      double ring = 0.0;
      for (int j = 0; j < nodes; ++j) {
        const double phi = kPi * (j + 0.5) / nodes;
        const Vec3 l(sin_l * std::cos(phi), sin_l * std::sin(phi), nl);
        ring += sheen.d(half_vector(l, v).z());
      }
      sum += w[i] * 2.0 * u[i] * ring * ring_factor * (2.0 * kPi / nodes);
    }
    return sum;
  }

  // The table blended in sheenRoughness (in [kMinRoughness, 1]) into one row over μ, which read()
  // reads at any μ: the same bicubic surface as blending μ first. A pass over the samples is at one
  // sheenRoughness, so the sheen builds its row once per pass (gltf_sheen_layer).
  template <class T>
  using Row = std::array<T, kMuNodes + 2>;
  template <class T>
  Row<T> row_at(const T& sheen_roughness) const {
    const T y = (sheen_roughness - kMinRoughness) / kStepRoughness;
    const int j = std::clamp(static_cast<int>(std::floor(value_of(y))), 0, kRoughnessNodes - 2);
    Row<T> row;
    for (int i = 0; i < kMuNodes + 2; ++i) {
      const std::array<double, 4> column = {nodes_[j][i], nodes_[j + 1][i], nodes_[j + 2][i], nodes_[j + 3][i]};
      row[i] = catmull_rom(column.data(), T(y - double(j)));  // rows j-1 .. j+2
    }
    return row;
  }
  // E at μ (clamped to [kMinMu, 1]) from a row of row_at, at most 1.
  template <class T>
  static T read(const Row<T>& row, double mu) {
    const double x = std::clamp((std::sqrt(std::clamp(mu, kMinMu, 1.0)) - kMinT) / kStepT, 0.0, kMuNodes - 1.0);
    const int i = std::min(static_cast<int>(x), kMuNodes - 2);
    const T e = catmull_rom(&row[i], x - i);
    return e > T(1.0) ? T(1.0) : (e < T(0.0) ? T(0.0) : e);
  }
  // E at μ and a sheenRoughness.
  template <class T>
  T operator()(double mu, const T& sheen_roughness) const {
    return read(row_at(sheen_roughness), mu);
  }

 private:
  static constexpr double kMinT = 0.031622776601683794;  // √kMinMu
  static constexpr double kStepT = (1.0 - kMinT) / (kMuNodes - 1);
  static constexpr double kStepRoughness = (1.0 - kMinRoughness) / (kRoughnessNodes - 1);
  static constexpr int kQuadrature = 32;

  // nodes_[j + 1][i + 1] = E at t_i = kMinT + i·kStepT, s_j = kMinRoughness + j·kStepRoughness, with one node
  // beyond each end: in roughness integrated there (0.075 and 1.025 are valid roughnesses), in t (below 0,
  // above 1) extrapolated quadratically, which is what Catmull-Rom's end segments need.
  SheenAlbedo() {
    for (int j = -1; j <= kRoughnessNodes; ++j) {
      for (int i = 0; i < kMuNodes; ++i) {
        const double t = kMinT + i * kStepT;
        nodes_[j + 1][i + 1] = integrate(std::min(t * t, 1.0), kMinRoughness + j * kStepRoughness, kQuadrature);
      }
      auto& row = nodes_[j + 1];
      row[0] = 3.0 * row[1] - 3.0 * row[2] + row[3];
      row[kMuNodes + 1] = 3.0 * row[kMuNodes] - 3.0 * row[kMuNodes - 1] + row[kMuNodes - 2];
    }
  }

  // Catmull-Rom through p[0..3] between p[1] and p[2], at fraction t (node values P and fraction
  // T each a double or a Jet).
  template <class P, class T>
  static auto catmull_rom(const P* p, const T& t) {
    return p[1] + 0.5 * t *
                      (p[2] - p[0] +
                       t * (2.0 * p[0] - 5.0 * p[1] + 4.0 * p[2] - p[3] + t * (3.0 * (p[1] - p[2]) + p[3] - p[0])));
  }

  // Nodes and weights of n-point Gauss-Legendre quadrature on [0, 1] (Newton on the Legendre polynomial).
  static void gauss_legendre(int n, std::vector<double>& nodes, std::vector<double>& weights) {
    nodes.assign(n, 0.0);
    weights.assign(n, 0.0);
    for (int i = 0; i < n; ++i) {
      double x = std::cos(kPi * (i + 0.75) / (n + 0.5)), derivative = 1.0;
      for (int iteration = 0; iteration < 100; ++iteration) {
        double p0 = 1.0, p1 = x;
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        derivative = n * (x * p1 - p0) / (x * x - 1.0);
        const double step = p1 / derivative;
        x -= step;
        if (std::abs(step) < 1e-15) break;
      }
      nodes[i] = 0.5 * (1.0 - x);
      weights[i] = 1.0 / ((1.0 - x * x) * derivative * derivative);
    }
  }

  double nodes_[kRoughnessNodes + 2][kMuNodes + 2];
};

// What the sheen takes of sheenRoughness alone: its albedo table's row and the Charlie terms,
// built once per pass over the samples (math.h's once_per_parameters).
template <class T>
struct SheenAtRoughness {
  explicit SheenAtRoughness(const T& sheen_roughness)
      : albedo(SheenAlbedo::table().row_at(sheen_roughness)), charlie(sheen_roughness) {}
  SheenAlbedo::Row<T> albedo;
  SheenCharlie<T> charlie;
};

// f_sheen + material · sheenAlbedoScaling, for l and v above the surface.
template <class T>
Rgb<T> gltf_sheen_layer(const Rgb<T>& material, const T* sheen_color, const T& sheen_roughness, const Vec3& l,
                        const Vec3& v) {
  // No sheen: the material as it is (math.h).
  if (constant_zero(sheen_color[0]) && constant_zero(sheen_color[1]) && constant_zero(sheen_color[2])) return material;
  T strongest = sheen_color[0];  // max3(sheenColor)
  for (int c = 1; c < 3; ++c)
    if (sheen_color[c] > strongest) strongest = sheen_color[c];
  // Both terms of sheenRoughness alone, on Jets of its one derivative (math.h): the larger of the
  // two directions' albedos, since min(1 - s·E(n·v), 1 - s·E(n·l)) = 1 - s·max(E(n·v), E(n·l)) for
  // s = max3(sheenColor) ≥ 0, and D_S·V_S (sheenColor 1).
  const double nl = l.z(), nv = v.z(), nh = half_vector(l, v).z();
  const auto [larger_albedo, sheen] = of_parameters(
      [&](const auto& r) {
        using R = std::decay_t<decltype(r)>;
        const SheenAtRoughness<R>& at = once_per_parameters([](const R& r) { return SheenAtRoughness<R>(r); }, r);
        const R albedo_v = SheenAlbedo::read(at.albedo, nv), albedo_l = SheenAlbedo::read(at.albedo, nl);
        const R visibility = 1.0 / ((1.0 + at.charlie.lambda(nv) + at.charlie.lambda(nl)) * (4.0 * nv * nl));
        return std::array<R, 2>{albedo_v > albedo_l ? albedo_v : albedo_l, R(at.charlie.d(nh) * visibility)};
      },
      sheen_roughness);
  const T scaling = 1.0 - strongest * larger_albedo;
  Rgb<T> f;
  for (int c = 0; c < 3; ++c) f[c] = sheen_color[c] * sheen + material[c] * scaling;
  return f;
}

inline ParamSpec gltf_sheen_color_param() {
  // Not linear: max3(sheenColor) scales the base.
  return {"sheenColorFactor",
          3,
          0.0,
          1.0,
          0.5,
          "KHR_materials_sheen sheenColorFactor (linear RGB): the sheen's colour (0: the core material)",
          Role::SpecularColour};
}
inline ParamSpec gltf_sheen_roughness_param() {
  return {"sheenRoughnessFactor",
          1,
          SheenAlbedo::kMinRoughness,
          1.0,
          0.5,
          "KHR_materials_sheen sheenRoughnessFactor; the Charlie distribution's alpha is roughness²",
          Role::Roughness,
          false,
          false,
          Spacing::Log};
}

// The core material under the sheen, of a model's first five values (gltf's layout). The sheen's
// models do not declare kSeparateChannels (max over the sheen's colour): their Jets hold one slot
// per value, and the core's run on Jets of its five values' derivatives only (math.h).
template <class T>
Rgb<T> gltf_core(const T* p, const Vec3& l, const Vec3& v) {
  return on_leading_slots<Gltf::kNumValues, Gltf::kNumValues>([&l, &v](const auto* q) { return Gltf::brdf(q, l, v); },
                                                              p);
}

struct GltfSheen {
  static constexpr const char* kName = "gltf+sheen";
  static constexpr const char* kSummary =
      "core glTF + KHR_materials_sheen: metallic-roughness under a Charlie sheen, the base scaled by 1 - max(sheen)·E";
  static constexpr bool kEnergyConserving = false;  // as gltf's base
  enum : int { kBaseColor = 0, kMetallic = 3, kRoughness = 4, kSheenColor = 5, kSheenRoughness = 8, kNumValues = 9 };
  static_assert(int{kBaseColor} == int{Gltf::kBaseColor} && int{kMetallic} == int{Gltf::kMetallic} &&
                    int{kRoughness} == int{Gltf::kRoughness},
                "the base's values are laid out as gltf's, so that Gltf::brdf evaluates them");

  static std::vector<ParamSpec> parameters() {
    return {gltf_base_color_param(), gltf_metallic_param(), gltf_roughness_param(), gltf_sheen_color_param(),
            gltf_sheen_roughness_param()};
  }

  template <class T>
  static Rgb<T> brdf(const T* p, const Vec3& l, const Vec3& v) {
    if (l.z() <= 0.0 || v.z() <= 0.0) return Rgb<T>(T(0.0), T(0.0), T(0.0));
    return gltf_sheen_layer(gltf_core(p, l, v), p + kSheenColor, p[kSheenRoughness], l, v);
  }

  static RecoveryFacts recovery_facts() { return Gltf::recovery_facts(); }

  static std::vector<Nesting> nestings() {
    return {{"gltf",
             {{"baseColor", "baseColor"}, {"metallic", "metallic"}, {"roughness", "roughness"}},
             {{"sheenColorFactor", 0.0}},
             /*exact=*/true,
             "sheenColorFactor 0 disables the sheen: the core material"}};
  }
};

// Both extensions: the coat over the sheen over the core material.
struct GltfClearcoatSheen {
  static constexpr const char* kName = "gltf+clearcoat+sheen";
  static constexpr const char* kSummary =
      "core glTF + KHR_materials_sheen + KHR_materials_clearcoat: the coat's mix over the sheen over the base";
  static constexpr bool kEnergyConserving = false;  // as gltf's base
  enum : int {
    kBaseColor = 0,
    kMetallic = 3,
    kRoughness = 4,
    kClearcoat = 5,
    kClearcoatRoughness = 6,
    kSheenColor = 7,
    kSheenRoughness = 10,
    kNumValues = 11
  };
  static_assert(int{kClearcoat} == int{GltfClearcoat::kClearcoat} &&
                    int{kClearcoatRoughness} == int{GltfClearcoat::kClearcoatRoughness},
                "the base's and the coat's values are laid out as gltf+clearcoat's");

  static std::vector<ParamSpec> parameters() {
    std::vector<ParamSpec> params = GltfClearcoat::parameters();
    params.push_back(gltf_sheen_color_param());
    params.push_back(gltf_sheen_roughness_param());
    return params;
  }

  template <class T>
  static Rgb<T> brdf(const T* p, const Vec3& l, const Vec3& v) {
    if (l.z() <= 0.0 || v.z() <= 0.0) return Rgb<T>(T(0.0), T(0.0), T(0.0));
    const Rgb<T> sheened = gltf_sheen_layer(gltf_core(p, l, v), p + kSheenColor, p[kSheenRoughness], l, v);
    return gltf_clearcoat_mix(sheened, p[kClearcoat], p[kClearcoatRoughness], l, v);
  }

  static RecoveryFacts recovery_facts() { return GltfClearcoat::recovery_facts(); }

  static std::vector<Nesting> nestings() {
    const std::vector<Nesting::Copy> base = {
        {"baseColor", "baseColor"}, {"metallic", "metallic"}, {"roughness", "roughness"}};
    auto with_coat = base, with_sheen = base;
    with_coat.push_back({"clearcoatFactor", "clearcoatFactor"});
    with_coat.push_back({"clearcoatRoughnessFactor", "clearcoatRoughnessFactor"});
    with_sheen.push_back({"sheenColorFactor", "sheenColorFactor"});
    with_sheen.push_back({"sheenRoughnessFactor", "sheenRoughnessFactor"});
    return {{"gltf+clearcoat",
             with_coat,
             {{"sheenColorFactor", 0.0}},
             /*exact=*/true,
             "sheenColorFactor 0 disables the sheen: the coat over the core material"},
            {"gltf+sheen",
             with_sheen,
             {{"clearcoatFactor", 0.0}},
             /*exact=*/true,
             "clearcoatFactor 0 disables the coat: the sheen over the core material"}};
  }
};

}  // namespace brdffit::models
