// compare, report and export on result documents a user did not plan for: material names with
// markup characters (<, &, ", --), a failed fit, a model missing from some documents, and
// metrics that rank the models differently.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "batch_test_util.h"
#include "brdffit/compare.h"
#include "brdffit/error.h"
#include "brdffit/imaging/report.h"
#include "brdffit/registry.h"

namespace brdffit {
namespace {

const std::string kHostile = "x<y&z\"--w";  // a material name with every markup character

// Two materials (the errors are cosine / log; see known_result for the other metrics):
//   hostile: ward 0.1 / 0.5, ggx 0.2 / 0.3, lambert 0.3 / 0.4
//   plain:   ward 0.1 / 0.1, ggx failed, no lambert
// By cosine ward wins both; by log ggx wins the hostile one and lambert comes before ward.
std::vector<std::string> write_documents(const std::string& dir) {
  FitResult ggx = test::known_result("ggx", 0.2, 0.3);
  ggx.values = parameter_values(*find_model("ggx"), {"albedo=0.1", "roughness=0.3", "f0=0.9,0.6,0.3"});
  return {test::write_document(dir + "/hostile.json", "/nowhere/" + kHostile + ".binary",
                               {test::known_result("ward", 0.1, 0.5), ggx, test::known_result("lambert", 0.3, 0.4)}),
          test::write_document(dir + "/plain.json", "/nowhere/plain.binary",
                               {test::known_result("ward", 0.1, 0.1), test::known_result("ggx", NAN)})};
}

std::vector<FitDocument> read_documents(const std::vector<std::string>& paths) {
  std::vector<FitDocument> documents;
  for (const std::string& path : paths) documents.push_back(read_fit_document(path));
  return documents;
}

std::vector<std::string> ranking(const MaterialRanking& material) {
  std::vector<std::string> models;
  for (const RankedModel& m : material.models) models.push_back(m.model + " " + std::to_string(m.rank));
  return models;
}

TEST(HostileOutputs, TheMetricChosenChangesTheRanking) {
  const std::vector<FitDocument> documents = read_documents(write_documents(test::fresh_dir("hostile-metric")));
  const Comparison cosine = compare_results(documents, Metric::Cosine), log = compare_results(documents, Metric::Log);
  ASSERT_EQ(cosine.materials.size(), 2u);
  EXPECT_EQ(cosine.materials[0].material, kHostile);
  EXPECT_EQ(ranking(cosine.materials[0]), (std::vector<std::string>{"ward 1", "ggx 2", "lambert 3"}));
  EXPECT_EQ(ranking(log.materials[0]), (std::vector<std::string>{"ggx 1", "lambert 2", "ward 3"}));
  // The failed ggx ranks after ward; lambert is not there at all.
  EXPECT_EQ(ranking(log.materials[1]), (std::vector<std::string>{"ward 1", "ggx 2"}));
  EXPECT_EQ(log.materials[1].find("lambert"), nullptr);
  // Errors are the chosen metric's: l2 is three times the cosine error in these documents.
  EXPECT_NEAR(compare_results(documents, Metric::L2).materials[0].models[0].error, 0.3, 1e-12);

  // Per model under log: ggx wins 1 of 2 with mean rank 1.5; lambert has one material only.
  const auto summary = [&](const std::string& model) {
    for (const ModelSummary& s : log.models)
      if (s.model == model) return s;
    ADD_FAILURE() << model << " not summarised";
    return ModelSummary{};
  };
  EXPECT_EQ(summary("ggx").wins, 1);
  EXPECT_EQ(summary("ggx").failed, 1);
  EXPECT_NEAR(summary("ggx").mean_rank, 1.5, 1e-12);
  EXPECT_NEAR(summary("ggx").mean_error, 0.3, 1e-12);
  EXPECT_EQ(summary("lambert").materials, 1);
  EXPECT_NEAR(summary("ward").mean_error, 0.3, 1e-12);  // (0.5 + 0.1) / 2
  EXPECT_NEAR(summary("ward").mean_rank, 2.0, 1e-12);
}

TEST(HostileOutputs, CompareCliRanksByMetricAndQuotesNames) {
  const std::string dir = test::fresh_dir("hostile-compare");
  const std::vector<std::string> documents = write_documents(dir);
  const auto by_log =
      test::run_cli("compare " + documents[0] + " " + documents[1] + " --metric log --csv " + dir + "/c.csv");
  ASSERT_EQ(by_log.exit_code, 0) << by_log.output;
  EXPECT_NE(by_log.output.find("ranked by the log metric over 2 materials"), std::string::npos) << by_log.output;
  EXPECT_NE(by_log.output.find(kHostile + ":  1. ggx 0.3  2. lambert 0.4  3. ward 0.5"), std::string::npos)
      << by_log.output;
  const auto by_cosine = test::run_cli("compare " + documents[0] + " " + documents[1]);
  ASSERT_EQ(by_cosine.exit_code, 0) << by_cosine.output;
  EXPECT_NE(by_cosine.output.find(kHostile + ":  1. ward 0.1  2. ggx 0.2  3. lambert 0.3"), std::string::npos)
      << by_cosine.output;

  // The material's name is a CSV field with its quote doubled, in quotes; lambert has no
  // numbers for the plain material.
  const std::string csv = read_file(dir + "/c.csv");
  EXPECT_NE(csv.find(",\"x<y&z\"\"--w\",\"x<y&z\"\"--w rank\","), std::string::npos) << csv;
  EXPECT_NE(csv.find("\nlambert,1,0,0,0.4,0.4,2,0,0.4,2,,\n"), std::string::npos) << csv;
}

// The text of an HTML or XML document with every comment removed; fails the test on a comment
// that holds "--" or is not closed.
std::string without_comments(const std::string& text) {
  std::string out;
  size_t at = 0;
  for (size_t open = text.find("<!--"); open != std::string::npos; open = text.find("<!--", at)) {
    out += text.substr(at, open - at);
    const size_t close = text.find("-->", open + 4);
    if (close == std::string::npos) {
      ADD_FAILURE() << "unclosed comment at " << open;
      return out;
    }
    EXPECT_EQ(text.find("--", open + 4), close) << "'--' inside the comment: " << text.substr(open, close + 3 - open);
    at = close + 3;
  }
  return out + text.substr(at);
}

// Every '&' starts an entity (a raw name's '&' would not).
void expect_escaped_markup(const std::string& text) {
  for (size_t at = text.find('&'); at != std::string::npos; at = text.find('&', at + 1)) {
    const size_t end = text.find(';', at);
    ASSERT_NE(end, std::string::npos) << text.substr(at, 40);
    const std::string entity = text.substr(at, end + 1 - at);
    EXPECT_TRUE(entity == "&lt;" || entity == "&gt;" || entity == "&amp;" || entity == "&quot;" || entity == "&#39;" ||
                entity == "&apos;")
        << "'&' not starting an entity: " << text.substr(at, 40);
  }
}

TEST(HostileOutputs, ReportEscapesNamesAndRanksByTheMetricAsked) {
  const std::vector<FitDocument> documents = read_documents(write_documents(test::fresh_dir("hostile-report")));
  ReportOptions options;
  options.metric = Metric::Log;
  options.sphere_size = 16;
  options.slice_size = 16;
  options.incidence_deg = {45.0};
  const std::string html = report_html(documents, options);
  const std::string text = without_comments(html);
  EXPECT_EQ(text.find(kHostile), std::string::npos) << "the raw name is on the page";
  EXPECT_NE(text.find("x&lt;y&amp;z&quot;--w"), std::string::npos);
  // Only <script> and <style> may hold raw markup characters; the rest is escaped.
  std::string markup = text;
  for (const char* element : {"script", "style"})
    for (size_t open = markup.find(std::string("<") + element); open != std::string::npos;
         open = markup.find(std::string("<") + element, open + 1)) {
      const size_t close = markup.find(std::string("</") + element + ">", open);
      ASSERT_NE(close, std::string::npos);
      markup.erase(open, close - open);
    }
  expect_escaped_markup(markup);

  // The hostile material's pictures follow the log ranking: ggx first, ward last; the failed
  // ggx of the plain one gets no picture.
  const size_t section = html.find("x&lt;y&amp;z&quot;--w", html.find("<h2"));
  ASSERT_NE(section, std::string::npos);
  const size_t ggx = html.find("alt=\"1. ggx sphere\"", section), ward = html.find("alt=\"3. ward sphere\"", section);
  EXPECT_NE(ggx, std::string::npos);
  EXPECT_NE(ward, std::string::npos);
  EXPECT_LT(ggx, ward);
  EXPECT_EQ(html.find("ggx sphere\"", html.find("plain", ward)), std::string::npos);
}

TEST(HostileOutputs, ExportEscapesTheName) {
  const std::string dir = test::fresh_dir("hostile-export");
  // Export writes the renderer model's own fit unchanged (a conversion would read the table).
  const std::string document =
      test::write_document(dir + "/hostile.json", "/nowhere/" + kHostile + ".binary",
                           {test::known_result("gltf", 0.2), test::known_result("mitsuba-principled", 0.2)});
  const auto gltf = test::run_cli("export " + document + " --out " + dir + "/m.gltf");
  ASSERT_EQ(gltf.exit_code, 0) << gltf.output;
  EXPECT_EQ(nlohmann::json::parse(read_file(dir + "/m.gltf"))["materials"][0]["name"], kHostile);

  const auto xml = test::run_cli("export " + document + " --out " + dir + "/m.xml");
  ASSERT_EQ(xml.exit_code, 0) << xml.output;
  const std::string text = read_file(dir + "/m.xml");
  const std::string body = without_comments(text);
  expect_escaped_markup(body.substr(body.find("<scene")));
  EXPECT_EQ(body.find(kHostile), std::string::npos);
  // The comment names the input, escaped, and the id the scene refers to.
  const std::string comment = text.substr(text.find("<!--"), text.find("-->") - text.find("<!--"));
  EXPECT_NE(comment.find("x&lt;y&amp;z&quot;"), std::string::npos) << comment;
  const size_t id_at = body.find("id=\"") + 4;
  const std::string id = body.substr(id_at, body.find('"', id_at) - id_at);
  EXPECT_NE(comment.find("<ref id=\"" + id + "\"/>"), std::string::npos) << comment;
}

}  // namespace
}  // namespace brdffit
