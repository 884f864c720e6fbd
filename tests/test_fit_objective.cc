// The fitter's objective and the reported metrics, against values computed by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/fit_objective.h"
#include "brdffit/registry.h"
#include "brdffit/result_json.h"
#include "test_util.h"

namespace brdffit {
namespace {

// Two samples at normal light and view, measured 0.4 (weight 1) and 0.8 (weight 3), and Lambert
// with albedo 1, which predicts 1/π for both.
SampleSet two_samples() {
  SampleSet set;
  set.samples.push_back({Vec3(0, 0, 1), Vec3(0, 0, 1), Rgb<double>(0.4, 0.4, 0.4), 1.0});
  set.samples.push_back({Vec3(0, 0, 1), Vec3(0, 0, 1), Rgb<double>(0.8, 0.8, 0.8), 3.0});
  return set;
}

constexpr double kPredicted = 1.0 / kPi;

TEST(Metrics, MatchHandComputedValuesOnATinyTable) {
  const Metrics m = evaluate_metrics(*find_model("lambert"), {1.0, 1.0, 1.0}, two_samples());
  const double d1 = kPredicted - 0.4, d2 = kPredicted - 0.8;
  EXPECT_NEAR(m.cosine, std::sqrt((1 * d1 * d1 + 3 * d2 * d2) / 4), 1e-12);
  EXPECT_NEAR(m.l2, std::sqrt((d1 * d1 + d2 * d2) / 2), 1e-12);
  const double l1 = std::log1p(kPredicted) - std::log1p(0.4), l2 = std::log1p(kPredicted) - std::log1p(0.8);
  EXPECT_NEAR(m.log, std::sqrt((l1 * l1 + 3 * l2 * l2) / 4), 1e-12);
  const double r1 = d1 / (0.4 + kRelativeEpsilon), r2 = d2 / (0.8 + kRelativeEpsilon);
  EXPECT_NEAR(m.relative, std::sqrt((r1 * r1 + 3 * r2 * r2) / 4), 1e-12);
  EXPECT_NEAR(m.max, 0.8 - kPredicted, 1e-12);
  // typical: the weighted median of |p−m|/(|m| + m̄/10), m̄ = (0.4 + 3·0.8)/4 = 0.7; the sample of
  // weight 3 holds the median. Read from a histogram with 1.2 % bins.
  EXPECT_NEAR(m.typical, std::fabs(d2) / (0.8 + 0.07), 0.012 * std::fabs(d2) / 0.87);
}

TEST(Metrics, TypicalIsTheWeightedMedianOfRelativeErrorsOverTenDecades) {
  // Relative errors |p−m|/(|m| + m̄/10) from 1e-5 to 1e5 at random weights: the reported typical
  // value is the centre of the histogram bin (1/200 of a decade) that holds their weighted median.
  // Many small sets: each median lands at another place within its bin.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> exponent(-4.0, 3.0), weight(0.5, 2.0);
  for (int trial = 0; trial < 300; ++trial) {
    SampleSet set;
    double weighted_sum = 0.0, weight_sum = 0.0;
    for (int i = 0; i < 21; ++i) {
      const double measured = std::pow(10.0, exponent(rng)), w = weight(rng);
      set.samples.push_back({Vec3(0, 0, 1), Vec3(0, 0, 1), Rgb<double>::Constant(measured), w});
      weighted_sum += w * measured;
      weight_sum += w;
    }
    const double floor = 0.1 * weighted_sum / weight_sum;
    std::vector<std::pair<double, double>> relative;  // error, weight
    for (const Sample& s : set.samples)
      relative.emplace_back(std::fabs(kPredicted - s.value[0]) / (s.value[0] + floor), s.weight);
    std::sort(relative.begin(), relative.end());
    double below = 0.0, median = NAN;
    for (const auto& [error, w] : relative)
      if ((below += w) >= 0.5 * weight_sum) {
        median = error;
        break;
      }
    const Metrics m = evaluate_metrics(*find_model("lambert"), {1.0, 1.0, 1.0}, set);
    ASSERT_LE(std::fabs(std::log10(m.typical) - std::log10(median)), 0.5 / 200 + 1e-12)
        << "trial " << trial << ": typical " << m.typical << ", weighted median " << median;
  }
}

// kMetrics (metric.h) is the one list parsing, naming, documents, tables and help read: each entry
// names its own field, the minimisable ones round-trip through their names, and `get` reads the
// field the entry names.
TEST(Metrics, TheTableNamesEachFieldOnceAndGetReadsIt) {
  Metrics m;
  m.cosine = 1, m.log = 2, m.relative = 3, m.l2 = 4, m.max = 5, m.typical = 6;
  std::vector<std::string> names, minimisable;
  for (const MetricInfo& info : kMetrics) {
    names.push_back(info.name);
    if (info.minimised) {
      minimisable.push_back(info.name);
      EXPECT_EQ(m.get(*info.minimised), m.*info.value) << info.name;
      EXPECT_STREQ(metric_name(*info.minimised), info.name);
      EXPECT_EQ(parse_metric(info.name), info.minimised);
    } else {
      EXPECT_FALSE(parse_metric(info.name)) << info.name << " is reported, not minimised";
    }
  }
  EXPECT_EQ(names, (std::vector<std::string>{"cosine", "log", "relative", "l2", "max", "typical"}));
  EXPECT_EQ(minimisable, (std::vector<std::string>{"cosine", "log", "relative", "l2"}));
  EXPECT_EQ(m.get(Metric::Relative), 3.0);
  EXPECT_EQ(m.get(Metric::L2), 4.0);
  EXPECT_EQ(minimisable_metrics_text(), "cosine, log, relative, l2");
  EXPECT_EQ(judged_metrics(), (std::vector<Metric>{Metric::Cosine, Metric::Log, Metric::Relative, Metric::L2}));
  // The result document's "metrics": every entry under its name, read back; a metric a document
  // lacks (written before it existed) and null read as NaN.
  const nlohmann::json written = metrics_json(m);
  EXPECT_EQ(written.size(), names.size());
  const Metrics read = metrics_from_json(written);
  for (const MetricInfo& info : kMetrics) EXPECT_EQ(read.*info.value, m.*info.value) << info.name;
  const Metrics partial = metrics_from_json({{"cosine", 0.5}, {"log", nullptr}});
  EXPECT_EQ(partial.cosine, 0.5);
  EXPECT_TRUE(std::isnan(partial.log));
  EXPECT_TRUE(std::isnan(partial.typical));
}

// The names users type, with the command line's messages: the option named, a near miss
// suggested, the accepted names listed.
TEST(Metrics, MetricAndLossNamesParseWithTheCommandLinesMessages) {
  EXPECT_EQ(metric_from_name("log", "--metric"), Metric::Log);
  EXPECT_EQ(loss_from_name("cauchy", "--loss"), LossKind::Cauchy);
  for (LossKind loss : {LossKind::None, LossKind::Huber, LossKind::Cauchy})
    EXPECT_EQ(loss_from_name(loss_name(loss), "loss"), loss);
  auto message = [](const auto& parse) {
    try {
      parse();
    } catch (const UsageError& e) {
      return std::string(e.what());
    }
    return std::string("no UsageError");
  };
  EXPECT_EQ(message([] { metric_from_name("cosin", "--metric"); }),
            "--metric: unknown metric 'cosin'; did you mean 'cosine'? (cosine, log, relative, l2)");
  EXPECT_EQ(message([] { metric_from_name("max", "metric"); }),
            "metric: unknown metric 'max' (cosine, log, relative, l2)");
  EXPECT_EQ(message([] { loss_from_name("hubr", "--loss"); }),
            "--loss: unknown loss 'hubr'; did you mean 'huber'? (none, huber, cauchy)");
}

// The variable projection's weight makes w'·(p−m)² the metric's weighted squared residual to
// first order at p = m: w' = metric weight × (∂residual/∂p)², the slope taken numerically here.
TEST(Metrics, LinearWeightIsTheMetricWeightTimesTheResidualsSlopeSquared) {
  for (const MetricInfo& info : kMetrics) {
    if (!info.minimised) continue;
    const Metric metric = *info.minimised;
    for (double measured : {0.02, 0.5, 7.0}) {
      const double h = 1e-6 * std::max(measured, 1e-3);
      const double slope =
          (metric_residual(metric, measured + h, measured) - metric_residual(metric, measured - h, measured)) / (2 * h);
      EXPECT_NEAR(metric_linear_weight(metric, 2.5, measured), metric_weight(metric, 2.5) * slope * slope,
                  1e-6 * metric_weight(metric, 2.5) * slope * slope)
          << info.name << " at " << measured;
    }
  }
}

TEST(FitObjective, CostIsTheWeightedSumOfSquaresOverTheFittedChannels) {
  const Model& lambert = *find_model("lambert");
  const SampleSet set = two_samples();
  const double d1 = kPredicted - 0.4, d2 = kPredicted - 0.8;
  EXPECT_NEAR(cost_of(lambert, {1, 1, 1}, set.samples, Metric::Cosine, kAllChannels, nullptr),
              3 * (d1 * d1 + 3 * d2 * d2), 1e-12);
  EXPECT_NEAR(cost_of(lambert, {1, 1, 1}, set.samples, Metric::L2, {true, false, false}, nullptr), d1 * d1 + d2 * d2,
              1e-12);
  // Huber with scale 0.1: ρ(s) = s up to 0.1², 2·0.1·√s − 0.01 beyond. |d1| = 0.082 is inside,
  // √3·|d2| = 0.83 beyond.
  const ceres::HuberLoss huber(0.1);
  const double r1 = std::fabs(d1), r2 = std::sqrt(3.0) * std::fabs(d2);
  EXPECT_NEAR(cost_of(lambert, {1, 1, 1}, set.samples, Metric::Cosine, {true, false, false}, &huber),
              r1 * r1 + (0.2 * r2 - 0.01), 1e-12);
  // A model that is not finite never wins.
  EXPECT_EQ(cost_of(lambert, {NAN, 1, 1}, set.samples, Metric::Cosine, kAllChannels, nullptr), HUGE_VAL);
}

// A candidate's cost is given up once it passes the best kept (fit.cc): exact below the bound,
// and past it, a part of the sum already above the bound. 64 000 samples (64 chunks), a quarter
// of the sum in each of the first four chunks.
TEST(FitObjective, CostGivenUpPastABoundIsAboveItAndOnlyPartOfTheSum) {
  const Model& lambert = *find_model("lambert");
  std::vector<Sample> samples(64000, {Vec3(0, 0, 1), Vec3(0, 0, 1), Rgb<double>(0.3, 0.3, 0.3), 1.0});
  for (size_t i = 0; i < samples.size() / 16; ++i) samples[i].value = Rgb<double>(0.9, 0.9, 0.9);
  const std::vector<double> albedo{1, 1, 1};
  const double full = cost_of(lambert, albedo, samples, Metric::Cosine, kAllChannels, nullptr);
  const double d_far = 0.9 - kPredicted, d_near = 0.3 - kPredicted;
  EXPECT_NEAR(full, 3 * 4000 * d_far * d_far + 3 * 60000 * d_near * d_near, 1e-9 * full);
  EXPECT_EQ(cost_of(lambert, albedo, samples, Metric::Cosine, kAllChannels, nullptr, 1, 1.01 * full), full);
  for (int threads : {1, 2}) {
    const double given_up =
        cost_of(lambert, albedo, samples, Metric::Cosine, kAllChannels, nullptr, threads, 0.2 * full);
    EXPECT_GT(given_up, 0.2 * full) << threads << " threads";
    EXPECT_LT(given_up, 0.5 * full) << threads << " threads";
  }
}

// Fewer than 50 000 samples are one chunk (a grid's 4 000): the sum is given up within it, at the
// first look (every 256 samples) past the bound. 16 000 samples, the first 1 000 far off.
TEST(FitObjective, CostOfOneChunkGivenUpWithinItAtTheFirstLookPastTheBound) {
  const Model& lambert = *find_model("lambert");
  std::vector<Sample> samples(16000, {Vec3(0, 0, 1), Vec3(0, 0, 1), Rgb<double>(0.3, 0.3, 0.3), 1.0});
  for (size_t i = 0; i < 1000; ++i) samples[i].value = Rgb<double>(0.9, 0.9, 0.9);
  const std::vector<double> albedo{1, 1, 1};
  const double full = cost_of(lambert, albedo, samples, Metric::Cosine, kAllChannels, nullptr);
  const double d_far = 0.9 - kPredicted, d_near = 0.3 - kPredicted;
  EXPECT_NEAR(full, 3 * 1000 * d_far * d_far + 3 * 15000 * d_near * d_near, 1e-9 * full);
  EXPECT_EQ(cost_of(lambert, albedo, samples, Metric::Cosine, kAllChannels, nullptr, 1, 1.01 * full), full);
  const double bound = 0.2 * full;
  const double given_up = cost_of(lambert, albedo, samples, Metric::Cosine, kAllChannels, nullptr, 1, bound);
  EXPECT_GT(given_up, bound);
  EXPECT_LE(given_up, bound + 256 * 3 * d_far * d_far * (1 + 1e-12));  // one look later at most
}

TEST(FitObjective, MedianResidualAbsoluteErrorsAndTheZeroPrediction) {
  const Model& lambert = *find_model("lambert");
  const SampleSet set = two_samples();
  const double d1 = kPredicted - 0.4, d2 = kPredicted - 0.8;
  // |residual|·√w on the red channel: |d1| and √3|d2|; with two, the upper middle.
  EXPECT_NEAR(median_abs_residual(lambert, {1, 1, 1}, set.samples, Metric::Cosine, {true, false, false}),
              std::max(std::fabs(d1), std::sqrt(3.0) * std::fabs(d2)), 1e-12);
  const std::vector<double> error = absolute_errors(lambert, {1, 0, 1}, set.samples, {true, true, false}, 2);
  EXPECT_NEAR(error[0], (std::fabs(d1) + 0.4) / 2, 1e-12);
  EXPECT_NEAR(error[1], (std::fabs(d2) + 0.8) / 2, 1e-12);
  // Predicting zero: √(Σ w m² / Σ w) = √((0.16 + 3·0.64)/4).
  EXPECT_NEAR(zero_prediction_error(set, Metric::Cosine), std::sqrt((0.16 + 3 * 0.64) / 4), 1e-12);
}

// The fitter costs its subsample's best start and draws the importance subset from its errors in
// one pass (fit.cc): the same cost and errors, bit for bit, as the two passes give, on a table of
// 64 chunks (70 000 samples, sum order and parallel chunks included) with a robust loss.
TEST(FitObjective, CostAndAbsoluteErrorsInOnePassAreThoseOfTheTwo) {
  const Model& ggx = *find_model("ggx");
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Sample> samples;
  for (int i = 0; i < 70000; ++i) {
    const double a = 2 * kPi * unit(rng), b = 2 * kPi * unit(rng), tl = 1.5 * unit(rng), tv = 1.5 * unit(rng);
    const Vec3 l(std::sin(tl) * std::cos(a), std::sin(tl) * std::sin(a), std::cos(tl));
    const Vec3 v(std::sin(tv) * std::cos(b), std::sin(tv) * std::sin(b), std::cos(tv));
    samples.push_back({l, v, Rgb<double>(unit(rng), unit(rng), unit(rng)), 0.5 + unit(rng)});
  }
  const std::vector<double> values = {0.3, 0.2, 0.1, 0.25, 0.04, 0.05, 0.06};  // albedo, roughness, f0
  const ceres::HuberLoss huber(0.05);
  for (const Channels& channels : {kAllChannels, Channels{false, true, true}}) {
    std::vector<double> errors;
    const double cost = cost_and_absolute_errors(ggx, values, samples, Metric::Log, channels, &huber, 2, errors);
    EXPECT_EQ(cost, cost_of(ggx, values, samples, Metric::Log, channels, &huber, 2));
    EXPECT_EQ(errors, absolute_errors(ggx, values, samples, channels, 2));
    EXPECT_GT(cost, 0.0);
  }
}

// cost_of's terms one per sample, as the fitter pairs two fits' draws on an importance subset
// (fit.cc): on the two samples by hand, with a robust loss, and summing to cost_of on 70 000
// samples in 64 chunks on two threads.
TEST(FitObjective, CostPerSampleIsEachSamplesShareOfTheCost) {
  const Model& lambert = *find_model("lambert");
  const SampleSet set = two_samples();
  const double d1 = kPredicted - 0.4, d2 = kPredicted - 0.8;
  const std::vector<double> terms =
      cost_per_sample(lambert, {1, 1, 1}, set.samples, Metric::Cosine, kAllChannels, nullptr);
  ASSERT_EQ(terms.size(), 2u);
  EXPECT_NEAR(terms[0], 3 * d1 * d1, 1e-12);
  EXPECT_NEAR(terms[1], 3 * 3 * d2 * d2, 1e-12);
  const ceres::HuberLoss huber(0.1);  // as in CostIsTheWeightedSumOfSquaresOverTheFittedChannels
  const double r2 = std::sqrt(3.0) * std::fabs(d2);
  EXPECT_NEAR(cost_per_sample(lambert, {1, 1, 1}, set.samples, Metric::Cosine, {true, false, false}, &huber)[1],
              0.2 * r2 - 0.01, 1e-12);

  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Sample> samples;
  for (int i = 0; i < 70000; ++i)
    samples.push_back({Vec3(0, 0, 1), Vec3(0.6, 0, 0.8), Rgb<double>(unit(rng), unit(rng), unit(rng)), unit(rng)});
  const std::vector<double> many =
      cost_per_sample(lambert, {0.5, 0.4, 0.3}, samples, Metric::Cosine, kAllChannels, &huber, 2);
  double sum = 0.0;
  for (double term : many) sum += term;
  EXPECT_NEAR(sum, cost_of(lambert, {0.5, 0.4, 0.3}, samples, Metric::Cosine, kAllChannels, &huber, 2), 1e-9 * sum);
}

// fit_models takes a contained model's objective on all samples from its reported error (an exact
// nesting's start is not costed again): ½·error²·metric_weight_sum must be ½ cost_of in every
// metric, the metrics' weighted RMS and the fitter's sum computed apart (metrics.cc and
// fit_objective.cc).
TEST(FitObjective, TheObjectiveOfEveryChannelFollowsFromTheReportedError) {
  const Model& ggx = *find_model("ggx");
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  SampleSet data;
  for (int i = 0; i < 5000; ++i) {
    const Vec3 l = test::random_upper_direction(rng, 0.05), v = test::random_upper_direction(rng, 0.05);
    data.samples.push_back({l, v, Rgb<double>(unit(rng), 0.5 * unit(rng), 2.0 * unit(rng)), 0.2 + unit(rng)});
  }
  const std::vector<double> values = {0.3, 0.2, 0.1, 0.25, 0.04, 0.05, 0.06};  // albedo, roughness, f0
  const Metrics metrics = evaluate_metrics(ggx, values, data);
  for (Metric metric : {Metric::Cosine, Metric::Log, Metric::Relative, Metric::L2}) {
    SCOPED_TRACE(metric_name(metric));
    const double objective = 0.5 * cost_of(ggx, values, data.samples, metric, kAllChannels, nullptr);
    ASSERT_GT(objective, 0.0);
    EXPECT_NEAR(0.5 * std::pow(metrics.get(metric), 2) * metric_weight_sum(data.samples, metric), objective,
                1e-12 * objective);
  }
}

}  // namespace
}  // namespace brdffit
