// The fitter's starts (fit_starts.cc): the coordinate search and the solved costs its searches
// share, which must give the same points as evaluating them again.
#include <gtest/gtest.h>

#include <atomic>

#include "brdffit/fit_stages.h"
#include "brdffit/importance_subset.h"
#include "brdffit/registry.h"
#include "test_util.h"

namespace brdffit {
namespace {

using fitting::coordinate_search;
using fitting::grid_starts;
using fitting::importance_subset_draws;
using fitting::later_start_surely_costlier;
using fitting::same_cost;
using fitting::same_optimum;
using fitting::solved_cost;
using fitting::SolvedCosts;
using fitting::Start;
using fitting::subset_covers;

// A registered model that counts its evaluations with doubles; optionally with its parameters'
// only_scales left out (the coordinate search then tries those parameters' values too).
class CountingModel final : public Model {
 public:
  explicit CountingModel(const Model& model, bool only_scales_declared = true)
      : model_(model), parameters_(model.parameters()) {
    if (!only_scales_declared)
      for (ParamSpec& p : parameters_) p.only_scales = nullptr;
  }
  const std::string& name() const override { return model_.name(); }
  const std::string& summary() const override { return model_.summary(); }
  const std::vector<ParamSpec>& parameters() const override { return parameters_; }
  bool has_brdf() const override { return model_.has_brdf(); }
  bool energy_conserving() const override { return model_.energy_conserving(); }
  Rgb<double> shade(const double* values, const Vec3& l, const Vec3& v) const override {
    ++evaluations;
    return model_.shade(values, l, v);
  }
  std::optional<Rgb<double>> brdf(const double* values, const Vec3& l, const Vec3& v) const override {
    return model_.brdf(values, l, v);
  }
  Rgb<double> shade_with_jacobian(const double* values, const Vec3& l, const Vec3& v, double* jacobian) const override {
    return model_.shade_with_jacobian(values, l, v, jacobian);
  }
  Rgb<double> shade_linear_parts(const double* values, const Vec3& l, const Vec3& v,
                                 Rgb<double>* basis) const override {
    ++evaluations;
    return model_.shade_linear_parts(values, l, v, basis);
  }

  mutable std::atomic<long> evaluations{0};

 private:
  const Model& model_;
  std::vector<ParamSpec> parameters_;
};

TEST(SolvedCosts, FindsAPointByItsShapeValuesWhateverItsLinearValuesAndABoundWhereItSettles) {
  const Model& ggx = *find_model("ggx");
  SolvedCosts known(ggx);
  const std::vector<double> point = parameter_values(ggx, {"albedo=0.2", "roughness=0.3", "f0=0.04"});
  known.add({point, 1.5});
  const Start* found = known.find(parameter_values(ggx, {"albedo=0.7,0.1,0", "roughness=0.3", "f0=0.9"}));
  ASSERT_NE(found, nullptr);
  EXPECT_EQ(found->values, point);  // as solved, not as asked
  EXPECT_EQ(found->cost, 1.5);
  EXPECT_EQ(known.find(parameter_values(ggx, {"albedo=0.2", "roughness=0.30000001", "f0=0.04"})), nullptr);

  // A solve given up left a lower bound of the cost: found only where that says the point is
  // costlier than the one asked for; costed again, the point's cost replaces the bound.
  const std::vector<double> given_up = parameter_values(ggx, {"albedo=0.2", "roughness=0.5", "f0=0.04"});
  known.add({given_up, 2.0}, /*cost_exact=*/false);
  ASSERT_NE(known.find(given_up, 1.9), nullptr);
  EXPECT_EQ(known.find(given_up, 1.9)->cost, 2.0);
  EXPECT_EQ(known.find(given_up, 2.1), nullptr);
  EXPECT_EQ(known.find(given_up), nullptr);
  known.add({given_up, 2.5});
  ASSERT_NE(known.find(given_up, 2.6), nullptr);
  EXPECT_EQ(known.find(given_up, 2.6)->cost, 2.5);
}

// The grid keeps its cheapest points, and gives up a point's solve once it is known to cost more
// than the cheapest kept so far: the points it keeps are the cheapest of the whole grid costed in
// full, to the bit, on one thread or two. gltf+sheen (one linear colour, and a grid over the
// non-linear colours too) and blinn-phong (two), on 1 500 noisy samples of a material off their
// defaults.
TEST(GridStarts, KeepTheCheapestPointsOfTheWholeGrid) {
  for (const auto& [name, material] : std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"gltf+sheen", {"baseColor=0.6,0.3,0.1", "roughness=0.2", "sheenColorFactor=0.3,0.1,0.1"}},
           {"blinn-phong", {"albedo=0.3,0.5,0.1", "gloss=300"}}}) {
    SCOPED_TRACE(name);
    const CountingModel model(*find_model(name));
    const SampleSet data = test::model_table(model, parameter_values(model, material), 1500, 0.02, 17, 0.05);
    for (int threads : {1, 2}) {
      FitOptions options;
      options.threads = threads;
      for (bool colours : {false, true}) {
        model.evaluations = 0;
        const std::vector<Start> all = grid_starts(model, model.default_values(), data.samples, options.metric,
                                                   kAllChannels, options, colours, 100000);
        const long evaluations_of_all = model.evaluations.exchange(0);
        const std::vector<Start> kept =
            grid_starts(model, model.default_values(), data.samples, options.metric, kAllChannels, options, colours, 3);
        EXPECT_LT(model.evaluations, 0.85 * evaluations_of_all);  // solves given up
        ASSERT_GT(all.size(), 10u);
        ASSERT_EQ(kept.size(), 3u);
        for (size_t i = 0; i < kept.size(); ++i) {
          EXPECT_EQ(kept[i].values, all[i].values) << i;
          EXPECT_EQ(kept[i].cost, all[i].cost) << i;
        }
      }
    }
  }
}

// A coordinate search's setting: sgd's published-fit material on 2 000 samples (1 % noise, the
// given seed) and its start, sgd's defaults with their linear values solved.
struct SgdSearch {
  SampleSet data;
  FitOptions options;
  Start start;
};
SgdSearch sgd_search(const Model& sgd, uint64_t seed) {
  SgdSearch search;
  const std::vector<double> truth = parameter_values(sgd, find_model("sgd")->recovery_facts().material);
  search.data = test::model_table(sgd, truth, 2000, 0.01, seed, 0.05);
  search.options.threads = 1;
  search.start = {sgd.default_values(), 0.0};
  search.start.cost = solved_cost(sgd, search.start.values, search.data.samples, search.options.metric, kAllChannels);
  return search;
}

TEST(CoordinateSearch, APointMetBeforeIsNotEvaluatedAgainAndGivesTheSameResult) {
  // sgd's published-fit material, searched from its defaults on 2 000 samples: a second search
  // from the same start with what the first met evaluates nothing and ends where it ended; a
  // search with nothing known ends there too, at the cost a fresh solve gives.
  const CountingModel sgd(*find_model("sgd"));
  const auto [data, options, start] = sgd_search(sgd, 5);

  SolvedCosts known(sgd);
  const Start first = coordinate_search(sgd, start, data.samples, options.metric, kAllChannels, options, known);
  EXPECT_LT(first.cost, 0.5 * start.cost);
  std::vector<double> again = first.values;
  EXPECT_EQ(solved_cost(sgd, again, data.samples, options.metric, kAllChannels), first.cost);

  sgd.evaluations = 0;
  const Start second = coordinate_search(sgd, start, data.samples, options.metric, kAllChannels, options, known);
  EXPECT_EQ(sgd.evaluations, 0);
  EXPECT_EQ(second.values, first.values);
  EXPECT_EQ(second.cost, first.cost);

  SolvedCosts nothing_known(sgd);
  const Start fresh = coordinate_search(sgd, start, data.samples, options.metric, kAllChannels, options, nothing_known);
  EXPECT_GT(sgd.evaluations, 0);
  EXPECT_EQ(fresh.values, first.values);
}

TEST(CoordinateSearch, EndsWhereNoParameterIsBetterWithinTwoStepsOfItsValue) {
  // After its first pass the search tries each parameter only near its current value (and
  // farther on while the window's end is the best): where it stops, every parameter's values
  // within two steps of the axis value nearest its own (colours set alike in every channel, as
  // the search sets them) must cost no less. sgd's published-fit material from its defaults.
  const Model& sgd = *find_model("sgd");
  const auto [data, options, start] = sgd_search(sgd, 7);
  SolvedCosts known(sgd);
  const Start end = coordinate_search(sgd, start, data.samples, options.metric, kAllChannels, options, known);
  ASSERT_LT(end.cost, 0.5 * start.cost);

  int neighbours = 0;
  for (const ParamSpec& p : sgd.parameters()) {
    if (p.linear) continue;
    const std::vector<double> axis = fitting::grid_axis(p, 24);
    const double value = end.values[sgd.offset_of(p.name)];
    size_t at = 0;
    for (size_t k = 1; k < axis.size(); ++k)
      if (std::fabs(axis[k] - value) < std::fabs(axis[at] - value)) at = k;
    for (size_t k = at - std::min<size_t>(at, 2); k <= std::min(axis.size() - 1, at + 2); ++k) {
      std::vector<double> values = end.values;
      std::fill_n(values.begin() + sgd.offset_of(p.name), p.channels, axis[k]);
      if (values == end.values) continue;
      EXPECT_GE(solved_cost(sgd, values, data.samples, options.metric, kAllChannels), end.cost * (1 - 1e-9))
          << p.name << " = " << axis[k];
      ++neighbours;
    }
  }
  EXPECT_GE(neighbours, 9 * 2);  // at least two neighbours of each of the nine shape colours
}

TEST(CoordinateSearch, DoesNotTryTheValuesOfAScaleOfALinearParameter) {
  // sgd's K only scales specular, which every point of the search solves exactly, so each K on
  // its axis costs the same, to rounding: the search does not try them (ParamSpec::only_scales).
  // From the same start, a search told nothing of it ends at the same point and cost, after
  // trying K's 24 values and more.
  const CountingModel sgd(*find_model("sgd")), sgd_undeclared(*find_model("sgd"), false);
  auto [data, options, start] = sgd_search(sgd, 9);
  const int k = sgd.offset_of("K");
  std::fill_n(start.values.begin() + k, 3, 40.0);
  start.cost = solved_cost(sgd, start.values, data.samples, options.metric, kAllChannels);
  SolvedCosts known(sgd), known_undeclared(sgd_undeclared);
  sgd.evaluations = 0;
  const Start end = coordinate_search(sgd, start, data.samples, options.metric, kAllChannels, options, known);
  const Start end_undeclared =
      coordinate_search(sgd_undeclared, start, data.samples, options.metric, kAllChannels, options, known_undeclared);
  ASSERT_LT(end.cost, 0.5 * start.cost);
  EXPECT_EQ(end.values, end_undeclared.values);
  EXPECT_EQ(end.cost, end_undeclared.cost);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(end.values[k + c], 40.0);
  EXPECT_GE(sgd_undeclared.evaluations, sgd.evaluations + 23);
  for (double value : fitting::grid_axis(*sgd.find_parameter("K"), 24)) {
    std::vector<double> values = end.values;
    std::fill_n(values.begin() + k, 3, value);
    EXPECT_NEAR(solved_cost(sgd, values, data.samples, options.metric, kAllChannels), end.cost, 1e-9 * end.cost)
        << "K = " << value;
  }
}

// Candidates within 1e-5 of every parameter's range are one optimum: ggx's roughness is spaced by
// ratio over [0.01, 1], albedo and f0 linearly over [0, 1].
TEST(SameOptimum, EveryValueWithinAHundredThousandthOfItsRange) {
  const Model& ggx = *find_model("ggx");
  const std::vector<fitting::ValueSlot> slots = fitting::value_slots(ggx);
  const ParamSpec& roughness = *ggx.find_parameter("roughness");
  ASSERT_EQ(roughness.spacing, Spacing::Log);
  const std::vector<double> fitted = parameter_values(ggx, {"albedo=0.3,0.4,0.5", "roughness=0.2", "f0=0.04"});
  const int r = ggx.offset_of("roughness"), f0 = ggx.offset_of("f0"), green = ggx.offset_of("albedo") + 1;
  const double log_range = std::log(roughness.upper / roughness.lower);
  auto moved = [&](int i, double to) {
    std::vector<double> values = fitted;
    values[i] = to;
    return values;
  };
  EXPECT_TRUE(same_optimum(slots, fitted, fitted));
  EXPECT_TRUE(same_optimum(slots, fitted, moved(green, 0.4 + 0.9e-5)));
  EXPECT_FALSE(same_optimum(slots, fitted, moved(green, 0.4 + 1.1e-5)));
  EXPECT_TRUE(same_optimum(slots, fitted, moved(f0, 0.04 - 0.9e-5)));
  EXPECT_FALSE(same_optimum(slots, fitted, moved(f0, 0.04 - 1.1e-5)));
  // By ratio, within e^(±1e-5·ln 100) of the roughness: near its top that is more than 1e-5 of the
  // range linearly, near its bottom far less.
  EXPECT_TRUE(same_optimum(slots, moved(r, 0.9), moved(r, 0.9 * std::exp(0.9e-5 * log_range))));
  EXPECT_FALSE(same_optimum(slots, moved(r, 0.02), moved(r, 0.02 * std::exp(1.1e-5 * log_range))));
}

TEST(SameCost, WithinAMillionthOfTheLarger) {
  EXPECT_TRUE(same_cost(0.0214645, 0.0214645));
  EXPECT_TRUE(same_cost(0.0214645, 0.0214645 * (1 + 0.9e-6)));
  EXPECT_FALSE(same_cost(0.0214645, 0.0214645 * (1 + 1.1e-6)));
  EXPECT_FALSE(same_cost(0.0214645 * (1 - 1.1e-6), 0.0214645));
  EXPECT_FALSE(same_cost(0.0214645, HUGE_VAL));
}

// A continued start is left uncosted on all samples only where the subset's draws, paired with
// the best's, put it more than four standard errors and the best's optimism above the best.
// Hand values: draws whose differences alternate mean ± 0.1 have a standard error of
// ½·0.1·√(n·n/(n−1)), against a difference of ½·n·mean.
TEST(LaterStarts, SurelyCostlierOnlyPastFourStandardErrorsAndTheOptimism) {
  auto alternating = [](size_t n, double mean, std::vector<double>& terms, std::vector<double>& best) {
    terms.assign(n, 1.0);
    best.assign(n, 1.0);
    for (size_t i = 0; i < n; ++i) terms[i] += mean + (i % 2 ? -0.1 : 0.1);
  };
  std::vector<double> terms, best;
  // n = 1600, mean 0.01: difference 8, standard error ½·0.1·√(1600·1600/1599) = 2.00063, 4 of
  // them 8.0025: not surely costlier. n = 3600: difference 18 against 12.0017.
  alternating(1600, 0.01, terms, best);
  EXPECT_FALSE(later_start_surely_costlier(terms, best, 100.0, 0));
  alternating(3600, 0.01, terms, best);
  EXPECT_TRUE(later_start_surely_costlier(terms, best, 100.0, 0));
  // The optimism: 2·(free values)/draws of the best's cost. Six values, a best costing 200:
  // 2·6/3600·200 = 0.667 more, 12.67 < 18 still; a best costing 600 adds 2.0, 14.0 < 18; 1800, 6.0:
  // 18.0017 > 18.
  EXPECT_TRUE(later_start_surely_costlier(terms, best, 200.0, 6));
  EXPECT_TRUE(later_start_surely_costlier(terms, best, 600.0, 6));
  EXPECT_FALSE(later_start_surely_costlier(terms, best, 1800.0, 6));
  // Cheaper on the draws, or the same: never surely costlier, nor with no draws to tell.
  alternating(3600, -0.01, terms, best);
  EXPECT_FALSE(later_start_surely_costlier(terms, best, 100.0, 0));
  EXPECT_FALSE(later_start_surely_costlier(best, best, 100.0, 0));
  EXPECT_FALSE(later_start_surely_costlier({}, {}, 100.0, 0));
}

// Ten times the subsample, then ten times the one before, below the number of samples; the last
// raised to polish_after only where the samples are twice that.
TEST(ImportanceSubsetDraws, TenfoldBelowTheSamplesTheLastAtLeastPolishAfterWhereTheSamplesAllowIt) {
  using V = std::vector<size_t>;
  EXPECT_EQ(importance_subset_draws(12000, 1096216, 100000), V({120000}));  // a full MERL table
  EXPECT_EQ(importance_subset_draws(7799, 277182, 100000), V({100000}));    // a glossy RGL table
  EXPECT_EQ(importance_subset_draws(11000, 277182, 100000), V({110000}));   // a matte one
  EXPECT_EQ(importance_subset_draws(7799, 150000, 100000), V({77990}));     // not twice polish_after
  EXPECT_EQ(importance_subset_draws(3000, 1096216, 100000), V({30000, 300000}));
  EXPECT_EQ(importance_subset_draws(300, 1096216, 100000), V({3000, 30000, 300000}));
  EXPECT_EQ(importance_subset_draws(300, 250000, 100000), V({3000, 100000}));
  EXPECT_EQ(importance_subset_draws(12000, 110000, 100000), V());  // the subsample is a tenth or more
  EXPECT_EQ(importance_subset_draws(0, 50, 100000), V({10}));      // no endless ladder from nothing
  // --converge never polishes (polish_after = SIZE_MAX): the ladder stays tenfold.
  EXPECT_EQ(importance_subset_draws(7799, 277182, SIZE_MAX), V({77990}));
  EXPECT_EQ(importance_subset_draws(7799, 277182, SIZE_MAX / 2 + 1), V({77990}));  // twice it would wrap to 0
}

// 50 000 samples of value 0.02 and weight 1, and errors of 0.01 except on 500 where a start's spike
// errs by 1000: scored by their errors those take all but a few of the draws.
TEST(SubsetCovers, AnUnbiasedSubsetDoesASpikeOfErrorsDoesNot) {
  std::vector<Sample> samples(50000);
  for (Sample& s : samples) {
    s.l = s.v = Vec3(0, 0, 1);
    s.value = Rgb<double>(0.02, 0.02, 0.02);
  }
  std::vector<double> errors(samples.size(), 0.01);
  EXPECT_TRUE(subset_covers(importance_subset(samples, 5000, 3, errors), samples));
  for (size_t i = 1000; i < 1500; ++i) errors[i] = 1000.0;
  const std::vector<Sample> spike = importance_subset(samples, 5000, 3, errors);
  EXPECT_LT(spike.size(), 600u);  // the subset as the fitter draws it: the spike and a few more
  EXPECT_FALSE(subset_covers(spike, samples));
  // 10 % either way, as the shared tables' subsets are within 5 %.
  std::vector<Sample> scaled = samples;
  for (Sample& s : scaled) s.weight = 1.09;
  EXPECT_TRUE(subset_covers(scaled, samples));
  for (Sample& s : scaled) s.weight = 0.89;
  EXPECT_FALSE(subset_covers(scaled, samples));
  EXPECT_FALSE(subset_covers({}, samples));
}

}  // namespace
}  // namespace brdffit
