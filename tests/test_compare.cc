// compare: rankings, means, medians, mean ranks and wins on result documents with known numbers.
#include <gtest/gtest.h>

#include "batch_test_util.h"
#include "brdffit/compare.h"
#include "brdffit/io.h"
#include "brdffit/result_json.h"

namespace brdffit {
namespace {

// Three materials, three models; on m2 ward and ggx tie, on m3 ward fails:
//   m1: ward 0.1 (1), ggx 0.2 (2), lambert 0.3 (3)
//   m2: ward 0.2 (1), ggx 0.2 (1), lambert 0.4 (3)
//   m3: ggx 0.1 (1), lambert 0.5 (2), ward failed (3)
std::string write_known_documents(const std::string& dir) {
  test::write_document(
      dir + "/m1.json", "/data/m1.binary",
      {test::known_result("lambert", 0.3), test::known_result("ward", 0.1), test::known_result("ggx", 0.2)});
  test::write_document(
      dir + "/m2.json", "/data/m2.binary",
      {test::known_result("lambert", 0.4), test::known_result("ward", 0.2), test::known_result("ggx", 0.2)});
  test::write_document(
      dir + "/m3.json", "/data/m3.binary",
      {test::known_result("lambert", 0.5), test::known_result("ward", NAN), test::known_result("ggx", 0.1)});
  write_file_atomic(dir + "/summary.json", "{\"not\": \"a result\"}");  // a batch's summary is skipped in folders
  return dir;
}

std::vector<FitDocument> read_known(const std::string& dir) {
  return {read_fit_document(dir + "/m1.json"), read_fit_document(dir + "/m2.json"),
          read_fit_document(dir + "/m3.json")};
}

TEST(Compare, RanksEachMaterialWithTiesAndFailures) {
  const Comparison c =
      compare_results(read_known(write_known_documents(test::fresh_dir("compare-ranks"))), Metric::Cosine);
  ASSERT_EQ(c.materials.size(), 3u);
  EXPECT_EQ(c.materials[0].material, "m1");
  const auto ranks = [](const MaterialRanking& m) {
    std::vector<std::pair<std::string, int>> out;
    for (const RankedModel& r : m.models) out.push_back({r.model, r.rank});
    return out;
  };
  using Ranks = std::vector<std::pair<std::string, int>>;
  EXPECT_EQ(ranks(c.materials[0]), (Ranks{{"ward", 1}, {"ggx", 2}, {"lambert", 3}}));
  EXPECT_EQ(ranks(c.materials[1]), (Ranks{{"ward", 1}, {"ggx", 1}, {"lambert", 3}}));
  EXPECT_EQ(ranks(c.materials[2]), (Ranks{{"ggx", 1}, {"lambert", 2}, {"ward", 3}}));
  EXPECT_FALSE(c.materials[2].find("ward")->ok);
}

TEST(Compare, SummarisesEachModelOverTheSet) {
  const Comparison c =
      compare_results(read_known(write_known_documents(test::fresh_dir("compare-summary"))), Metric::Cosine);
  ASSERT_EQ(c.models.size(), 3u);
  // Ordered by mean rank: ggx (2+1+1)/3, ward (1+1+3)/3, lambert (3+3+2)/3.
  const ModelSummary &ggx = c.models[0], &ward = c.models[1], &lambert = c.models[2];
  EXPECT_EQ(ggx.model, "ggx");
  EXPECT_EQ(ward.model, "ward");
  EXPECT_EQ(lambert.model, "lambert");
  EXPECT_NEAR(ggx.mean_error, 0.5 / 3, 1e-12);
  EXPECT_NEAR(ggx.median_error, 0.2, 1e-12);
  EXPECT_NEAR(ggx.mean_rank, 4.0 / 3, 1e-12);
  EXPECT_EQ(ggx.wins, 2);
  EXPECT_EQ(ggx.failed, 0);
  // ward's failure counts in its rank, not in its errors.
  EXPECT_NEAR(ward.mean_error, 0.15, 1e-12);
  EXPECT_NEAR(ward.median_error, 0.15, 1e-12);
  EXPECT_NEAR(ward.mean_rank, 5.0 / 3, 1e-12);
  EXPECT_EQ(ward.wins, 2);
  EXPECT_EQ(ward.materials, 3);
  EXPECT_EQ(ward.failed, 1);
  EXPECT_NEAR(lambert.mean_error, 0.4, 1e-12);
  EXPECT_NEAR(lambert.median_error, 0.4, 1e-12);
  EXPECT_NEAR(lambert.mean_rank, 8.0 / 3, 1e-12);
  EXPECT_EQ(lambert.wins, 0);
}

TEST(Compare, NamesMaterialsThatShareAFileNameByTheirDocument) {
  const std::string dir = test::fresh_dir("compare-names");
  test::write_document(dir + "/first.json", "/a/paint.binary", {test::known_result("lambert", 0.1)});
  test::write_document(dir + "/second.json", "/b/paint.binary", {test::known_result("lambert", 0.2)});
  const Comparison c = compare_results(
      {read_fit_document(dir + "/first.json"), read_fit_document(dir + "/second.json")}, Metric::Cosine);
  EXPECT_EQ(c.materials[0].material, "first");
  EXPECT_EQ(c.materials[1].material, "second");
}

TEST(CompareCli, PrintsAndWritesCsvAndMarkdown) {
  const std::string dir = write_known_documents(test::fresh_dir("compare-cli"));
  const auto r = test::run_cli("compare " + dir + " --csv " + dir + "/c.csv --markdown " + dir + "/c.md");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("ranked by the cosine metric over 3 materials"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("m2:  1. ward 0.2  1. ggx 0.2  3. lambert 0.4"), std::string::npos) << r.output;

  const std::string csv = read_file(dir + "/c.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "model,fitted,poor,failed,mean,median,mean_rank,wins,m1,m1 rank,m2,m2 rank,m3,m3 rank");
  EXPECT_NE(csv.find("\nggx,3,0,0,0.166666667,0.2,1.33333,2,0.2,2,0.2,1,0.1,1\n"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\nward,2,0,1,0.15,0.15,1.66667,2,0.1,1,0.2,1,,3\n"), std::string::npos) << csv;

  const std::string md = read_file(dir + "/c.md");
  EXPECT_NE(md.find("| ggx | 3 | 0 | 0 | 0.1667 | 0.2 | 1.33 | 2 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| m3 | **0.1** (1) | failed | 0.5 (2) |"), std::string::npos) << md;

  // Another metric is another ranking; a file that is not a result is named.
  EXPECT_EQ(test::run_cli("compare " + dir + "/m1.json --metric log").exit_code, 0);
  const auto bad = test::run_cli("compare " + dir + "/m1.json " + dir + "/summary.json");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("summary.json: not a brdffit result"), std::string::npos) << bad.output;
}

// A fit the document judges poor is still ranked by its error, and marked as poor everywhere
// the comparison is shown: the text, the CSV's count and the Markdown matrix.
TEST(CompareCli, MarksPoorFits) {
  const std::string dir = write_known_documents(test::fresh_dir("compare-poor"));
  nlohmann::json m1 = nlohmann::json::parse(read_file(dir + "/m1.json"));
  for (auto& model : m1["models"])
    if (model["model"] == "lambert") model["verdict"] = "poor";
  write_file_atomic(dir + "/m1.json", m1.dump());
  const auto r = test::run_cli("compare " + dir + " --csv " + dir + "/c.csv --markdown " + dir + "/c.md");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("m1:  1. ward 0.1  2. ggx 0.2  3. lambert 0.3 poor"), std::string::npos) << r.output;
  EXPECT_NE(read_file(dir + "/c.csv").find("\nlambert,3,1,0,"), std::string::npos);
  EXPECT_NE(read_file(dir + "/c.md").find(" 0.3 (3) poor |"), std::string::npos);
}

}  // namespace
}  // namespace brdffit
