// The fitter's starts, evaluated with doubles on the subsample: a multi-start grid over the shape
// parameters, and a coordinate search from its best points (fit_stages.h).
#include <algorithm>
#include <cmath>
#include <mutex>

#include "brdffit/fit_stages.h"
#include "brdffit/parallel.h"
#include "brdffit/variable_projection.h"

namespace brdffit::fitting {

namespace {

// One shape parameter's value at coordinate t ∈ (0, 1) of its range, log-spaced for
// exponents and roughness.
double at_fraction(const ParamSpec& p, double t) {
  const double value =
      p.spacing == Spacing::Log ? p.lower * std::pow(p.upper / p.lower, t) : p.lower + t * (p.upper - p.lower);
  return p.integer ? std::round(value) : value;
}

// The i-th point (from 1) of the Halton sequence in base `base`: a low-discrepancy coordinate in (0, 1).
double halton(size_t i, int base) {
  double value = 0.0, digit = 1.0 / base;
  for (; i > 0; i /= base, digit /= base) value += digit * static_cast<double>(i % base);
  return value;
}

}  // namespace

std::vector<double> grid_axis(const ParamSpec& p, int n) {
  std::vector<double> axis;
  if (p.integer) {
    const int lo = static_cast<int>(std::ceil(p.lower)), hi = static_cast<int>(std::floor(p.upper));
    const int step = std::max(1, (hi - lo + 1) / std::max(n, 1));
    for (int k = lo; k <= hi; k += step) axis.push_back(k);
    return axis;
  }
  for (int k = 0; k < n; ++k) axis.push_back(at_fraction(p, (k + 0.5) / n));
  return axis;
}

double solved_cost(const Model& model, std::vector<double>& values, const std::vector<Sample>& samples, Metric metric,
                   const Channels& channels, double give_up_above) {
  const double cost = solve_linear(model, values, samples, metric, channels, nullptr, give_up_above);
  return std::isnan(cost) ? cost_of(model, values, samples, metric, channels, nullptr, 1, give_up_above) : cost;
}

std::vector<Start> grid_starts(const Model& model, const std::vector<double>& initial,
                               const std::vector<Sample>& samples, Metric metric, const Channels& channels,
                               const FitOptions& options, bool colours, size_t keep) {
  std::vector<const ParamSpec*> axes_params;
  for (const ParamSpec& p : model.parameters())
    if (!p.linear && (colours || p.channels == 1)) axes_params.push_back(&p);
  const int dims = static_cast<int>(axes_params.size());
  const int per_axis =
      dims == 0 ? 1 : std::clamp(static_cast<int>(std::floor(std::pow(options.grid_points, 1.0 / dims))), 2, 24);
  // A lattice with 2 points per axis only tries each parameter near a quarter and three quarters
  // of its range; with that many dimensions a Halton design spreads the same budget over more
  // distinct values of every parameter.
  const bool lattice = per_axis >= 3 || dims <= 2;
  std::vector<std::vector<double>> axes;
  size_t total = 1;
  if (lattice) {
    for (const ParamSpec* p : axes_params) {
      axes.push_back(grid_axis(*p, per_axis));
      total *= axes.back().size();
    }
  } else {
    total = static_cast<size_t>(std::max(options.grid_points, 1));
  }
  static constexpr int kPrimes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61, 67, 71};
  auto set = [&](std::vector<double>& values, const ParamSpec& p, double value) {
    const int offset = model.offset_of(p.name);
    std::fill_n(values.begin() + offset, p.channels, value);
  };

  // The `keep` lowest costs met so far, a max-heap: a point's solve is given up once it is known to
  // cost more than the highest of them, which only falls, so that point could not be kept.
  std::mutex lowest_mutex;
  std::vector<double> lowest;
  auto give_up_above = [&] {
    const std::lock_guard<std::mutex> lock(lowest_mutex);
    return lowest.size() < keep ? HUGE_VAL : lowest.front();
  };
  auto met = [&](double cost) {
    const std::lock_guard<std::mutex> lock(lowest_mutex);
    if (lowest.size() == keep && !(cost < lowest.front())) return;
    if (lowest.size() == keep) std::pop_heap(lowest.begin(), lowest.end()), lowest.pop_back();
    lowest.push_back(cost);
    std::push_heap(lowest.begin(), lowest.end());
  };

  std::vector<Start> starts(total + 1);
  // The last entry starts from `initial` itself (the defaults), so the grid never does worse.
  parallel_for(total + 1, thread_count(options.threads), [&](size_t index) {
    std::vector<double> values = initial;
    size_t rest = index;
    if (index < total && lattice)
      for (int d = 0; d < dims; ++d) {
        set(values, *axes_params[d], axes[d][rest % axes[d].size()]);
        rest /= axes[d].size();
      }
    else if (index < total)
      for (int d = 0; d < dims; ++d)
        set(values, *axes_params[d], at_fraction(*axes_params[d], halton(index + 1, kPrimes[d % std::size(kPrimes)])));
    const double cost = solved_cost(model, values, samples, metric, channels, give_up_above());
    met(cost);
    starts[index] = {std::move(values), cost};
  });
  stop_if_cancelled(options);
  // Equal costs (a stylised model's steps) stay in the grid's order: which are kept does not depend on
  // the costs of the points given up.
  std::stable_sort(starts.begin(), starts.end(), [](const Start& a, const Start& b) { return a.cost < b.cost; });
  starts.resize(std::min(starts.size(), keep));
  return starts;
}

bool has_non_linear_colour(const Model& model) {
  const auto& params = model.parameters();
  return std::any_of(params.begin(), params.end(), [](const ParamSpec& p) { return !p.linear && p.channels > 1; });
}

bool shape_mostly_in_colours(const Model& model) {
  int scalars = 0, colours = 0;
  for (const ParamSpec& p : model.parameters())
    if (!p.linear) ++(p.channels == 1 ? scalars : colours);
  return scalars + colours > 5 && colours > scalars;
}

SolvedCosts::SolvedCosts(const Model& model) {
  for (const ParamSpec& p : model.parameters()) linear_.insert(linear_.end(), p.channels, p.linear);
}

std::vector<double> SolvedCosts::shape_of(const std::vector<double>& values) const {
  std::vector<double> shape = values;
  for (size_t i = 0; i < shape.size(); ++i)
    if (linear_[i]) shape[i] = 0.0;
  return shape;
}

const Start* SolvedCosts::find(const std::vector<double>& values, double chosen_below) const {
  const auto it = known_.find(shape_of(values));
  if (it == known_.end() || !(it->second.cost_exact || it->second.point.cost > chosen_below)) return nullptr;
  return &it->second.point;
}

void SolvedCosts::add(const Start& point, bool cost_exact) {
  Known& known = known_[shape_of(point.values)];  // a point computed again replaces a bound
  known = {point, cost_exact};
}

Start coordinate_search(const Model& model, Start start, const std::vector<Sample>& samples, Metric metric,
                        const Channels& channels, const FitOptions& options, SolvedCosts& known) {
  constexpr int kValuesPerParameter = 24, kMaxPasses = 10;
  constexpr size_t kWindow = 2;
  std::vector<const ParamSpec*> shape;
  for (const ParamSpec& p : model.parameters())
    if (!p.linear && !p.only_scales) shape.push_back(&p);  // a scale of a linear one: every value costs alike
  known.add(start);
  bool improved = false;  // in the current pass
  // Moves `start` to the best of parameter p's values axis[first..last] if it is better than
  // `start`; returns whether it moved.
  auto move_to_best = [&](const ParamSpec& p, const std::vector<double>& axis, size_t first, size_t last) {
    // A try is chosen only below this (and below every try chosen before it): a solve known to
    // pass it is given up, and the try kept as costlier.
    const double chosen_below = start.cost * (1 - 1e-9);
    std::vector<Start> tries(last - first + 1);
    std::vector<size_t> unknown;
    for (size_t i = 0; i < tries.size(); ++i) {
      tries[i].values = start.values;
      std::fill_n(tries[i].values.begin() + model.offset_of(p.name), p.channels, axis[first + i]);
      if (const Start* met = known.find(tries[i].values, chosen_below))
        tries[i] = *met;
      else
        unknown.push_back(i);
    }
    parallel_for(unknown.size(), thread_count(options.threads), [&](size_t i) {
      Start& t = tries[unknown[i]];
      t.cost = solved_cost(model, t.values, samples, metric, channels, chosen_below);
    });
    // A cost above the bound may only be a lower bound of it.
    for (size_t i : unknown) known.add(tries[i], !(tries[i].cost > chosen_below));
    bool moved = false;
    for (Start& t : tries)
      if (t.cost < start.cost * (1 - 1e-9)) {
        start = std::move(t);
        moved = improved = true;
      }
    return moved;
  };
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    improved = false;
    for (const ParamSpec* p : shape) {
      stop_if_cancelled(options);
      const std::vector<double> axis = grid_axis(*p, kValuesPerParameter);
      // The first pass tries every value of the axis. In the later ones the parameter's best
      // value has moved only a step or two with the others: they try the values within kWindow
      // steps of the current one, and go on past the window's end while that end is the best.
      // (Every value in every pass made sgd's searches 2.5 to 3.5 times as long, for the same
      // fits on eight of nine tables and 0.25 % better on one.)
      if (pass == 0) {
        move_to_best(*p, axis, 0, axis.size() - 1);
        continue;
      }
      auto value = [&] { return start.values[model.offset_of(p->name)]; };  // moves replace start
      const double now = value();
      const size_t at = static_cast<size_t>(
          std::min_element(axis.begin(), axis.end(),
                           [&](double a, double b) { return std::fabs(a - now) < std::fabs(b - now); }) -
          axis.begin());
      size_t lo = at - std::min(at, kWindow), hi = std::min(axis.size() - 1, at + kWindow);
      if (!move_to_best(*p, axis, lo, hi)) continue;
      while (lo > 0 && value() == axis[lo] && move_to_best(*p, axis, lo - 1, lo - 1)) --lo;
      while (hi + 1 < axis.size() && value() == axis[hi] && move_to_best(*p, axis, hi + 1, hi + 1)) ++hi;
    }
    if (!improved) break;
  }
  return start;
}

}  // namespace brdffit::fitting
