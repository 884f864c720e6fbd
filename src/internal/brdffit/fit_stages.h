// The generic fitter's stages, shared by its units (the strategy: fit.h):
//   fit_starts.cc     the multi-start grid and the coordinate search, evaluated with doubles
//   least_squares.cc  Ceres' trust-region refinements, values held on bounds, the covariance
//   fit_verdict.cc    a fitted result's verdict and warnings, bounds as reported
//   fit.cc            the orchestration: the stages per set of channels, nested models, held parameters
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Core>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/fit_objective.h"
#include "brdffit/memoized_cost.h"
#include "brdffit/model.h"
#include "brdffit/samples.h"

namespace brdffit::fitting {

// Where each flattened value comes from: its parameter and its channel (0 for scalars).
struct ValueSlot {
  const ParamSpec* param;
  int channel;
};

// FitOptions::cancel is looked at before and after every grid, coordinate-search pass and solve,
// and by Ceres at each iteration (AtEachIteration).
inline void stop_if_cancelled(const FitOptions& options) {
  if (options.cancel && options.cancel->load()) throw Cancelled();
}

inline std::vector<ValueSlot> value_slots(const Model& model) {
  std::vector<ValueSlot> slots;
  for (const ParamSpec& p : model.parameters())
    for (int c = 0; c < p.channels; ++c) slots.push_back({&p, c});
  return slots;
}

// A value is fitted in a channel-restricted fit when it is a scalar, or a colour component of
// a fitted channel.
inline bool is_fitted(const ValueSlot& slot, const Channels& channels) {
  return slot.param->channels == 1 || channels[slot.channel];
}

std::unique_ptr<ceres::LossFunction> make_loss(LossKind kind, double scale);

// ---------------------------------------------------------------------------------------------
// Starts (fit_starts.cc).

struct Start {
  std::vector<double> values;
  double cost;
};

// Values for one shape parameter in the grid and the coordinate search: n points spread over its
// range (log-spaced for exponents and roughness), or every integer for integer parameters.
std::vector<double> grid_axis(const ParamSpec& p, int n);

// Solves the linear parameters of `values` and returns the cost there (cost_of without a loss):
// from the solve's normal equations where they give it, which saves a pass over the samples per
// grid point and search step (a quarter of those stages for a model with two linear colours).
// Given up once known to pass give_up_above, as solve_linear and cost_of are.
double solved_cost(const Model& model, std::vector<double>& values, const std::vector<Sample>& samples, Metric metric,
                   const Channels& channels, double give_up_above = HUGE_VAL);

// The `keep` cheapest grid points on `samples`, their linear parameters solved, cheapest first.
// The grid spans the scalar non-linear parameters, and with `colours` the non-linear colours too,
// a colour taking the same value in every channel (a start: the refinement separates them).
std::vector<Start> grid_starts(const Model& model, const std::vector<double>& initial,
                               const std::vector<Sample>& samples, Metric metric, const Channels& channels,
                               const FitOptions& options, bool colours, size_t keep);

// Whether a model has a colour that is not solved linearly (the grid then also spans colours).
bool has_non_linear_colour(const Model& model);

// Where the coordinate search runs: more than five shape parameters, most of them colours (sgd's
// nine). The grid over the scalar shape parameters, a lattice, then has little or nothing to span,
// and the grid over the colours is a Halton design that sets each colour alike in every channel.
// Elsewhere (openpbr, principled, mitsuba-principled, gltf+clearcoat+sheen: four to eight scalars,
// one or two colours) the search was half their fit. It left their cosine errors unchanged on the
// three MERL proxies and four of the six RGL tables but for gltf+clearcoat+sheen on
// gold-metallic-paint, which it made 2.2 % worse; it made gltf+clearcoat+sheen 0.7 % better on
// paper_white and mitsuba-principled 1.7 % better on cc_iris_purple_gem. sgd needs it: without it,
// its cosine error doubles on blue-acrylic (0.068 against 0.034) and is 15 % worse on paper_white.
bool shape_mostly_in_colours(const Model& model);

// The solved costs a fit's coordinate searches have met, by shape values (the linear values do not
// change them: they are solved). A search often tries a point again: a parameter's axis in a pass
// where no other parameter has changed since its last, or a point on another search's path, after
// which it walks that path (openpbr's six searches, when it searched, ended at three points). A
// point met again is not evaluated again; the searches' results are the same.
class SolvedCosts {
 public:
  explicit SolvedCosts(const Model& model);
  // The point with these shape values (its linear values solved) and its cost, or one whose cost
  // is known to be above `chosen_below` (it cannot be chosen), or nullptr.
  const Start* find(const std::vector<double>& values, double chosen_below = HUGE_VAL) const;
  // A point and its cost, or a lower bound of its cost (a solve given up).
  void add(const Start& point, bool cost_exact = true);

 private:
  struct Known {
    Start point;
    bool cost_exact;
  };
  std::vector<double> shape_of(const std::vector<double>& values) const;  // linear values at 0
  std::vector<bool> linear_;                                              // per flattened value
  std::map<std::vector<double>, Known> known_;
};

// Coordinate search from a grid point, where the shape is mostly colours: each parameter in
// turn is tried at values spread over its range (the others held, colours set in every channel,
// the linear parameters solved), keeping any improvement, until a pass changes nothing; after
// the first pass, only the values near the parameter's current one (fit_starts.cc). A
// 256-point design in nine dimensions (sgd) rarely lands in the basin of a material's optimum;
// the search walks there one parameter at a time, at the cost of a few hundred evaluations on
// the subsample, before the trust region takes over. (Profiled on sgd, its evaluations with
// doubles are most of the fit's time. Searching a third of the subsample instead cost sgd 8 %
// in error on blue-acrylic: the search needs the subsample's grazing samples.)
Start coordinate_search(const Model& model, Start start, const std::vector<Sample>& samples, Metric metric,
                        const Channels& channels, const FitOptions& options, SolvedCosts& known);

// ---------------------------------------------------------------------------------------------
// Trust-region least squares with Ceres (least_squares.cc).

struct Refinement {
  std::vector<double> values;
  double cost = HUGE_VAL;  // Ceres' cost: ½ Σ r²
  int iterations = 0;
  double trust_region_radius = 0.0;  // at the last step: where a continuation starts
  bool usable = false;
  std::string termination;
  Eigen::MatrixXd covariance;      // over the free values, unscaled (JᵀJ)⁻¹; empty if not computed
  std::vector<bool> identifiable;  // per free value
  std::vector<int> free_index;
  std::vector<int> held;      // free values held on a bound (indices into values)
  bool held_checked = false;  // `held` is what the cost asks for at `values`, not only where the run started
};

class LeastSquares {
 public:
  // end_jacobian_read: the Jacobian where a run ends on its iteration limit is read afterwards (a
  // covariance estimated there finds it in the memo); otherwise it is not computed
  // (RunWatch, memoized_cost.h).
  LeastSquares(const Model& model, const std::vector<Sample>& samples, Metric metric, const Channels& channels,
               const ceres::LossFunction* loss, const FitOptions& options, bool end_jacobian_read = false)
      : model_(model),
        samples_(samples),
        metric_(metric),
        channels_(channels),
        loss_(loss),
        options_(options),
        end_jacobian_read_(end_jacobian_read) {}

  // Trust-region least squares from `start`; function_tolerance: relative cost change at which it
  // stops. A continuation of an earlier run on the same samples passes that run's last trust-region
  // radius, so that it goes on with the steps the run had reached rather than starting over from
  // Ceres' default (a converged run's radius would stop a run on other samples at once). A run
  // from an earlier run's end (`earlier`) starts with the values that run held on their bounds.
  Refinement run(const std::vector<double>& start, int max_iterations, double function_tolerance = 1e-10,
                 double trust_region_radius = 0.0, const Refinement* earlier = nullptr) const;

  // At most `steps` steps from the end of a run on other samples (the largest importance subset's
  // optimum, on all samples), with the values that run held. The bounds are not looked at again:
  // each look costs a gradient on these samples, and a few steps cannot crawl along one.
  Refinement polish(const Refinement& from, int steps) const;

  // Fills r.covariance and r.identifiable at r.values.
  void estimate_covariance(Refinement& r) const;

  // Values the solver optimises: all but integer parameters and the colour components of channels
  // this fit leaves alone.
  std::vector<int> free_values() const;

 private:
  // How a solve ended: where a value it moved reached a bound (RunMonitor, least_squares.cc),
  // the steps it tried and those it took.
  struct SolveEnd {
    bool reached_bound = false;
    int steps_tried = 0;
    int successful_steps = 0;
  };
  // Runs Ceres from r.values with the values r.held held, and puts its result in r (its
  // iterations added to r's).
  SolveEnd solve(Refinement& r, int max_iterations, double function_tolerance, double trust_region_radius) const;

  // The free values (indices into the model's values) on a bound with the cost's gradient pointing
  // out of the box at r.values; none when that would be every free value. One gradient evaluation,
  // and none when no free value is on a bound.
  std::vector<int> held_on_bounds(const Refinement& r) const;
  // The free values on a bound at r.values.
  std::vector<int> on_bounds(const Refinement& r) const;

  // One residual block per batch of samples over the free values x, with the bounds; a run's
  // batches skip what `watch` tells them cannot change where it goes (RunWatch, memoized_cost.h).
  void build_problem(Refinement& r, std::vector<double>& x, ceres::Problem& problem, RunWatch* watch = nullptr) const;

  // The covariance (JᵀJ)⁺ of the free values from the Jacobian Ceres evaluates at the
  // optimum. Values the data do not determine (their direction lies partly in the numerical
  // null space of the column-scaled JᵀJ, e.g. two parameters that only matter through their
  // ratio) are flagged rather than given a meaningless number; the others get theirs from the
  // pseudo-inverse, which drops that null space.
  static void estimate_covariance(ceres::Problem& problem, std::vector<double>& x, int threads, Refinement& out);

  const Model& model_;
  const std::vector<Sample>& samples_;
  Metric metric_;
  Channels channels_;
  const ceres::LossFunction* loss_;
  const FitOptions& options_;
  const bool end_jacobian_read_;

  // The last evaluations of each batch of samples: every run over these samples cuts them into the
  // same batches (build_problem).
  mutable std::vector<CostMemo> memos_;
};

// ---------------------------------------------------------------------------------------------
// Verdicts (fit_verdict.cc).

// On a bound to within a millionth of the parameter's range, measured as the grid spaces it: in
// log space for log-spaced parameters (c of sgd spans 1e-8 to 1e4; a linear millionth, 0.01,
// would call 0.006 a value at its lower bound).
bool at_upper_bound(const ParamSpec& p, double value);
bool at_bound(const ParamSpec& p, double value);

// Whether two fitted values are the same optimum: every value within 1e-5 of its parameter's range,
// measured as the grid spaces it (log-spaced parameters by ratio). Refinements from several starts
// often end there (openpbr's five continued starts on red-fabric, 1e-8 to 1e-5 apart, their costs
// on all samples 5e-7 apart), and the fitter costs such a candidate on all samples only once.
bool same_optimum(const std::vector<ValueSlot>& slots, const std::vector<double>& a, const std::vector<double>& b);

// Whether two refinements on the same samples ended at the same cost, to a millionth: the same
// optimum, or the same valley along values the samples hardly determine, whose candidates
// same_optimum keeps apart (gltf+sheen's six continued starts on gold-metallic-paint: the same
// cost on the subsample to six digits, on all samples to 7e-5). The fitter costs such a
// candidate on all samples only once.
bool same_cost(double a, double b);

// Whether a continued start surely costs more than the best candidate on all samples, from their
// terms on the same importance subset (cost_per_sample) and the best's cost on all samples: the
// difference of their sums, ½Σ(candidate − best), above kLaterStartErrors (4) standard errors (the
// terms' differences as independent draws) plus the optimism of a best walked on this subset (its
// cost there is below its cost elsewhere by about 2·(free values)/draws of itself, as a least-squares
// fit's in-sample residual is). Paired draw by draw, the two estimates' errors cancel where the
// two fits err alike: on the nine shared tables (all 36 models, ggx+ggx, 199 continued starts within
// kLaterStartMargin, docs/performance.md twentieth round) the paired estimate missed the difference on
// all samples by −2.7 to +1.3 of its standard errors, and the five starts that beat the best were
// estimated at most 0.12 standard errors above it.
bool later_start_surely_costlier(const std::vector<double>& terms, const std::vector<double>& best_terms,
                                 double best_cost, size_t free_values);

// The sizes (draws) of the importance subsets walked between the subsample, of `subsample`
// distinct samples, and all `samples`: ten times the subsample's, then ten times the one before,
// while below the number of samples. The last is raised to polish_after where the samples are at
// least twice that many, so that the stage on all samples polishes (FitOptions::polish_after)
// instead of walking: a glossy RGL table's subsample holds few distinct samples (cc_iris_purple_gem:
// 7 799 in 12 000 draws), its one subset had 77 990 draws, and sgd then walked 49 steps on all
// 277 182 samples, two thirds of its fit (docs/performance.md, twenty-second round).
std::vector<size_t> importance_subset_draws(size_t subsample, size_t samples, size_t polish_after);

// Whether an importance subset covers the samples it was drawn from: its weights, each divided by
// its expected number of draws, sum to within kSubsetCoverage (10 %) of all samples' weights, as
// the sum of any unbiased subset does (0.95 to 1.05 on the sixteen shared tables, 36 models). A
// start whose spike errs thousands of times the data draws nearly every draw there
// (gltf+clearcoat on red-fabric: 3 422 distinct samples in 120 000 draws, their weights 0.002 %
// of all; on paper_white 1 550, 64 %). Such a subset says nothing of the rest of the table: the
// covariance estimated on it gave the base's values 80 to 1 700 times the standard deviations of
// the same values fitted as gltf (docs/performance.md, twenty-third round), and the other continued
// starts are not judged on it.
bool subset_covers(const std::vector<Sample>& subset, const std::vector<Sample>& samples);

// The verdict and the warning lines of a fitted result (see Verdict in fit.h). A fit is poor
// when any of these holds:
//   - its error in any judged metric (kJudgedMetrics: cosine, log, relative and l2, whichever was
//     minimised) is more than kPoorRatio times that of the baseline, Lambert fitted to the same
//     samples: every reflectance model should do at least as well as a diffuse term alone, and
//     models with a Lambert base contain it. Judging the fitted metric alone let a mirror-like
//     gltf fit of white paper (log minimised; cosine error 1960 against Lambert's 0.047) and
//     glossy fits 2-14x Lambert's relative error on acrylics pass as good. `max` is one sample's
//     error and is reported, not judged;
//   - it removes less than 1 - kPoorUnexplained of the data's own scale in that metric (the
//     error of predicting zero): it misses what dominates the data, e.g. a diffuse model on a
//     glossy coating;
//   - its typical sample is off by more than kPoorTypical times its own value (Metrics::typical):
//     it misses the body of the data, e.g. a lobe with no diffuse term on a coloured paint;
//   - a colour or scale it solves linearly sits at its upper bound in every channel while it
//     leaves more than kPoorClampedUnexplained of the data's scale: the data are brighter than
//     the model can be (a stylised shader's output in place of a reflectance), and the values
//     it reports are its limits, not the material's.
// The thresholds were set on the shared RGL and MERL tables, where they flag the diffuse models
// on glossy materials, toon on measured ones and single lobes that capture < 15% of a
// mirror-like peak, and leave every model on white paper and red fabric good.
void judge(const Model& model, const FitResult* baseline, double zero_error, Metric metric, bool isotropic_data,
           FitResult& r);

}  // namespace brdffit::fitting
