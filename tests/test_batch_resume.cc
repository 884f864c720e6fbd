// batch --resume: which prior result documents count as done. Only a document for the same
// input bytes, fitted with the same metric, per-channel and loss settings and holding every
// requested model fitted ok is kept; anything else is fitted again and replaced.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "batch_test_util.h"
#include "brdffit/batch.h"
#include "brdffit/registry.h"
#include "broken_model.h"

namespace brdffit {
namespace {

class BatchResume : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::fresh_dir(std::string("resume-") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    material_ = {"paint", test::write_model_csv(dir_ + "/paint.csv", "lambert", {"albedo=0.4,0.3,0.2"}, 300, 4)};
    options_.models = {find_model("lambert")};
    options_.out_dir = dir_ + "/out";
    options_.resume = true;
    options_.fit.threads = 1;
  }

  MaterialOutcome run(const BatchOptions& options) {
    const std::vector<MaterialOutcome> outcomes = run_batch({material_}, options);
    EXPECT_EQ(outcomes.size(), 1u);
    return outcomes.at(0);
  }
  std::string document() const { return dir_ + "/out/paint.json"; }

  std::string dir_;
  BatchMaterial material_;
  BatchOptions options_;
};

TEST_F(BatchResume, AnUnchangedDocumentIsAlreadyDone) {
  const MaterialOutcome first = run(options_);
  ASSERT_EQ(first.status, MaterialStatus::Ok) << first.error;
  EXPECT_FALSE(first.resumed);
  const std::string written = read_file(document());
  const MaterialOutcome again = run(options_);
  EXPECT_EQ(again.status, MaterialStatus::Ok);
  EXPECT_TRUE(again.resumed);
  ASSERT_EQ(again.fits.size(), 1u);
  EXPECT_NEAR(again.fits[0].values[0], 0.4, 1e-6);  // read back from the document
  EXPECT_EQ(read_file(document()), written);
}

TEST_F(BatchResume, ChangedSettingsAreFittedAgain) {
  ASSERT_EQ(run(options_).status, MaterialStatus::Ok);
  const std::string prior = read_file(document());
  struct Change {
    const char* what;
    std::function<void(BatchOptions&)> apply;
    const char* key;  // the document's field that now differs
  };
  const std::vector<Change> changes = {
      {"metric", [](BatchOptions& o) { o.fit.metric = Metric::Log; }, "metric"},
      {"per-channel", [](BatchOptions& o) { o.fit.per_channel = true; }, "per_channel"},
      {"loss", [](BatchOptions& o) { o.fit.loss = LossKind::Huber; }, "loss"},
  };
  for (const Change& change : changes) {
    SCOPED_TRACE(change.what);
    write_file_atomic(document(), prior);
    BatchOptions changed = options_;
    change.apply(changed);
    const MaterialOutcome outcome = run(changed);
    EXPECT_EQ(outcome.status, MaterialStatus::Ok) << outcome.error;
    EXPECT_FALSE(outcome.resumed);
    const nlohmann::json before = nlohmann::json::parse(prior), after = nlohmann::json::parse(read_file(document()));
    EXPECT_NE(before[change.key], after[change.key]) << "the document was not replaced";
    // And the replaced document is current for the changed settings.
    EXPECT_TRUE(run(changed).resumed);
  }
}

TEST_F(BatchResume, UnreadableDocumentsAreFittedAgain) {
  ASSERT_EQ(run(options_).status, MaterialStatus::Ok);
  const std::string prior = read_file(document());
  for (const std::string& corrupt :
       {std::string("{not json"), prior.substr(0, prior.size() / 2), std::string(), std::string("{\"schema\": 1}")}) {
    SCOPED_TRACE(corrupt.substr(0, 40));
    write_file_atomic(document(), corrupt);
    const MaterialOutcome outcome = run(options_);
    EXPECT_EQ(outcome.status, MaterialStatus::Ok) << outcome.error;
    EXPECT_FALSE(outcome.resumed);
    EXPECT_NEAR(read_fit_document(document()).results.at(0).values.at(0), 0.4, 1e-6);
  }
}

TEST_F(BatchResume, AFailedModelMakesThePartialStatusAndIsFittedAgain) {
  const test::BrokenModel broken;
  BatchOptions with_broken = options_;
  with_broken.models = {&broken, find_model("lambert")};
  const MaterialOutcome partial = run(with_broken);
  EXPECT_EQ(partial.status, MaterialStatus::Partial);
  EXPECT_STREQ(material_status_name(partial.status), "partial");
  EXPECT_EQ(partial.error.rfind("broken: ", 0), 0u) << partial.error;
  ASSERT_EQ(partial.fits.size(), 2u);
  EXPECT_TRUE(partial.fits[1].ok);
  // The document is written, with the failure in it.
  const nlohmann::json written = nlohmann::json::parse(read_file(document()));
  ASSERT_EQ(written["models"].size(), 2u);
  EXPECT_EQ(written["models"][0]["status"], "failed");
  EXPECT_EQ(written["models"][1]["status"], "ok");

  // Asked again for the model that failed: not done, fitted again (and failing again).
  const MaterialOutcome retried = run(with_broken);
  EXPECT_FALSE(retried.resumed);
  EXPECT_EQ(retried.status, MaterialStatus::Partial);

  // A prior document whose requested (registered) model failed is not done either.
  ASSERT_EQ(run(options_).status, MaterialStatus::Ok);
  nlohmann::json failed = nlohmann::json::parse(read_file(document()));
  failed["models"][0]["status"] = "failed";
  failed["models"][0]["verdict"] = "failed";
  failed["models"][0]["error"] = "diverged on purpose";
  write_file_atomic(document(), failed.dump(2));
  const MaterialOutcome refitted = run(options_);
  EXPECT_FALSE(refitted.resumed);
  EXPECT_EQ(refitted.status, MaterialStatus::Ok) << refitted.error;
  EXPECT_TRUE(run(options_).resumed);

  // The summary counts it as partial, with the failed model's error empty.
  const nlohmann::json summary = batch_summary_json({partial}, with_broken, 1.0);
  EXPECT_EQ(summary["counts"]["partial"], 1);
  EXPECT_EQ(summary["counts"]["ok"], 0);
  EXPECT_EQ(summary["materials"][0]["status"], "partial");
  EXPECT_TRUE(summary["materials"][0]["errors"]["broken"].is_null());
  EXPECT_EQ(summary["materials"][0]["best_model"], "lambert");
}

}  // namespace
}  // namespace brdffit
