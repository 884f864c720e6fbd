// Published per-material fits in the text format of the BBM benchmark (bsdfbenchmark/bbm,
// fits/*.fit; a copy is in ../shared/reference/published-fits), mapped onto brdffit's models so
// that published parameters can be evaluated and scored on the same tables as our own fits.
//
// Format: one material a line, '#' starts a comment line, blank lines are skipped:
//
//   material = Aggregate(Lambertian(albedo = [r, g, b]), NganWard(albedo = [r, g, b], roughness = 0.1))
//
// A term is Name(key = value, ...) with a value either a number or a list [v, v, ...] (lists may
// nest, as Bagher's complex eta = [[re, re, re], [im, im, im]]: they are read flattened);
// Aggregate(term, term, ...) sums terms (it may also be left out when there is one term).
//
// Which published terms map onto which model (the conventions are in each model's header):
//   cook-torrance      Lambertian + NganCookTorrance(albedo, eta, roughness)        ngan_cooktorrance.fit
//   ward               Lambertian + NganWard(albedo, roughness)                       ngan_ward.fit
//   ashikhmin-shirley  Lambertian + NganAshikhminShirley(albedo, fresnelReflectance, sharpness)
//                                                                                     ngan_ashikhminshirley.fit
//   lafortune          Lambertian + NganLafortune(albedo, Cxy, Cz, sharpness)          ngan_lafortune.fit
//   low-smooth         Lambertian + LowSmooth(A, B, C, eta)                           low_lowsmooth_E2.fit
//   low-microfacet     Lambertian + LowMicrofacetFit(A, B, C, eta)                    low_lowmicrofacet_E2.fit
//   low-cook-torrance  Lambertian + LowCookTorrance(albedo, roughness, eta)           low_cooktorrance_E1/E2.fit
//   low-ashikhmin-shirley  Lambertian + LowAshikhminShirley(albedo, sharpness, fresnelReflectance)
//                                                                                     low_ashikhminshirley_E1/E2.fit
//   sgd                Lambertian + Bagher(albedo, alpha, p, eta = [[f0], [f1]], K, Lambda, c, k, theta0)
//                                                                                     bagher_sgd.fit
// Lambertian(albedo) is our albedo as it is (both are f = albedo/π); a missing Lambertian term
// maps to albedo 0. Every published lobe "albedo" is our `specular`; other names are the
// published ones (A, B, C, eta, ...) or their lower-case forms. NganWardDuer (ngan_wardduer.fit)
// is a different lobe (1/(n·l n·v) instead of 1/√(n·l n·v)) and maps onto none of our models; so
// do Ngan's Blinn-Phong and He, and any fit with more than one lobe (we fit one).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "brdffit/model.h"

namespace brdffit {

// One model term of a published fit: its BBM name and its parameters (scalars have one value).
struct PublishedTerm {
  std::string model;
  std::map<std::string, std::vector<double>> parameters;
};

// Every material of a .fit file with its terms (Aggregate flattened), in file order of
// materials' names. Throws Error naming the file and line when the file cannot be read, a line
// is malformed, a number is not finite, or a material or a term's parameter appears twice.
std::map<std::string, std::vector<PublishedTerm>> read_published_fits(const std::string& path);

// The flattened values of `model` for a published fit, or nullopt when the terms are not
// exactly one Lambertian (optional) plus the one lobe this model maps (table above) with all of
// its parameters, each of the right number of channels. Values are not clamped to our bounds.
std::optional<std::vector<double>> to_model_values(const Model& model, const std::vector<PublishedTerm>& terms);

// A published fit mapped onto one of our models.
struct PublishedFit {
  std::string material;
  std::string model;           // our model's name, e.g. "ward"
  std::string term;            // the published lobe's BBM name, e.g. "NganWard"
  std::vector<double> values;  // flattened values of `model`, in the order of its parameters()
};

// Reads `fit_file` and maps `material`'s fit onto `model`: nullopt when the file has no such
// material or that material's fit does not map onto `model` (see to_model_values). Throws Error
// (naming the file and line) when the file is malformed.
std::optional<PublishedFit> find_published_fit(const std::string& fit_file, const std::string& material,
                                               const Model& model);

// `material`'s fit in `fit_file` mapped onto every one of our models it maps onto (usually one),
// in the registry's order. Throws Error naming the file when it is malformed, has no such
// material (listing a few it has), or when the fit maps onto none of our models (naming its terms).
std::vector<PublishedFit> find_published_fits(const std::string& fit_file, const std::string& material);

}  // namespace brdffit
