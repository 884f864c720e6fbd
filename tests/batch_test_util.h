// Helpers for the batch, compare, render, report and export tests: sample files from a known
// model, and result documents with known numbers.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "brdffit/batch.h"
#include "brdffit/csv_samples.h"
#include "brdffit/fit.h"
#include "brdffit/io.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"
#include "brdffit/result_json.h"
#include "test_util.h"

namespace brdffit::test {

namespace fs = std::filesystem;

// A CSV of `count` samples of a model at the given parameters (random directions, seeded).
inline std::string write_model_csv(const std::string& path, const std::string& model_name,
                                   const std::vector<std::string>& assignments, int count = 2000, uint64_t seed = 5) {
  const Model& model = *find_model(model_name);
  const std::vector<double> values = parameter_values(model, assignments);
  SampleSet set;
  std::mt19937_64 rng(seed);
  for (int i = 0; i < count; ++i) {
    const Vec3 l = random_upper_direction(rng, 0.1), v = random_upper_direction(rng, 0.1);
    set.samples.push_back({l, v, model.shade(values.data(), l, v), 1.0});
  }
  write_file_atomic(path, format_csv_samples(set));
  return path;
}

// A fit result with a known cosine error (ok) or a failure (NaN error). The other metrics are
// `log` when given (so that ranking by log can differ from ranking by cosine), else the cosine
// error; relative, l2 and max are the cosine error times 2, 3 and 4.
inline FitResult known_result(const std::string& model, double cosine, std::optional<double> log = std::nullopt) {
  FitResult r;
  r.model = model;
  r.ok = !std::isnan(cosine);
  if (!r.ok) r.error = "diverged on purpose";
  r.verdict = r.ok ? Verdict::Good : Verdict::Failed;
  r.metrics.cosine = cosine;
  r.metrics.log = log.value_or(cosine);
  r.metrics.relative = 2 * cosine;
  r.metrics.l2 = 3 * cosine;
  r.metrics.max = 4 * cosine;
  if (const Model* m = find_model(model)) r.values = m->default_values();
  return r;
}

// A fit with known values and a good verdict.
inline FitResult fit_of(const std::string& model, const std::vector<std::string>& assignments, double cosine = 0.0123) {
  FitResult fit = known_result(model, cosine);
  fit.values = parameter_values(*find_model(model), assignments);
  fit.verdict = Verdict::Good;
  return fit;
}

// A result document for `input` holding the given results, written to `path`.
inline std::string write_document(const std::string& path, const std::string& input,
                                  const std::vector<FitResult>& results) {
  write_file_atomic(path, fit_document_json(input, SampleSet{}, FitOptions{}, results).dump(2));
  return path;
}

// A result document without its timings: what two runs of the same batch must agree on.
inline nlohmann::json without_seconds(nlohmann::json document) {
  for (auto& model : document["models"]) model.erase("seconds");
  return document;
}

// Four small materials (two ward, two lambert CSVs) in dir/in, for batches split several ways.
inline std::string write_shard_inputs(const std::string& dir) {
  const std::string in = dir + "/in";
  fs::create_directories(in);
  write_model_csv(in + "/red.csv", "ward", {"albedo=0.5,0.1,0.1", "specular=0.08", "alpha=0.2"}, 600, 1);
  write_model_csv(in + "/blue.csv", "lambert", {"albedo=0.1,0.2,0.6"}, 500, 2);
  write_model_csv(in + "/green.csv", "ward", {"albedo=0.1,0.5,0.1", "specular=0.05", "alpha=0.3"}, 400, 3);
  write_model_csv(in + "/grey.csv", "lambert", {"albedo=0.4"}, 300, 4);
  return in;
}

// The four materials of write_shard_inputs fitted into `out` as one process fitted them into
// `single`: the same documents but for timings, and the same summary, all four ok.
inline void expect_same_batch(const std::string& out, const std::string& single) {
  for (const char* material : {"red", "blue", "green", "grey"}) {
    SCOPED_TRACE(material);
    EXPECT_EQ(without_seconds(nlohmann::json::parse(read_file(out + "/" + material + ".json"))),
              without_seconds(nlohmann::json::parse(read_file(single + "/" + material + ".json"))));
  }
  const nlohmann::json one = nlohmann::json::parse(read_file(single + "/summary.json"));
  const nlohmann::json all = nlohmann::json::parse(read_file(out + "/summary.json"));
  ASSERT_EQ(all["materials"].size(), 4u);
  for (size_t i = 0; i < 4; ++i)
    for (const char* key : {"material", "input", "status", "best_model", "errors"})
      EXPECT_EQ(all["materials"][i][key], one["materials"][i][key]) << key;
  EXPECT_EQ(all["counts"]["ok"], 4);
}

// The materials' names, in order.
inline std::vector<std::string> names(const std::vector<BatchMaterial>& materials) {
  std::vector<std::string> out;
  for (const BatchMaterial& m : materials) out.push_back(m.name);
  return out;
}

}  // namespace brdffit::test
