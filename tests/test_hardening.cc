// Hardening (issue 11): no crash, no clobbered file, bounded resources, on any input. One test
// (or a few) per class of defect the issue lists; each fails on the code before the fix.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "batch_test_util.h"
#include "brdffit/batch.h"
#include "brdffit/compare.h"
#include "brdffit/csv_samples.h"
#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/imaging/capture.h"
#include "brdffit/imaging/image_io.h"
#include "brdffit/imaging/sphere.h"
#include "brdffit/io.h"
#include "brdffit/registry.h"
#include "brdffit/result_json.h"
#include "brdffit/samples.h"
#include "test_util.h"

namespace brdffit::test {
namespace {

SampleSet lambert_samples(double value, size_t count = 50) {
  SampleSet set;
  set.source = "test-table";
  for (size_t i = 0; i < count; ++i)
    set.samples.push_back(
        {dir(0.1 * (i % 5), 0.0, 1.0), dir(0.0, 0.1 * (i % 3), 1.0), Rgb<double>::Constant(value), 1.0});
  return set;
}

// ---- Crashes: finite values that would overflow the residuals are refused before the solver.

TEST(Hardening, ValuesThatOverflowTheSolverAreRefusedBeforeIt) {
  const Model& lambert = *find_model("lambert");
  SampleSet one_huge = lambert_samples(0.5);
  one_huge.samples[7].value[1] = 1e300;  // the MERL bin at 1e300
  std::string message = error_of([&] { fit_model(lambert, one_huge, FitOptions{}); });
  EXPECT_NE(message.find("test-table: sample 8"), std::string::npos) << message;
  EXPECT_NE(message.find("1e+100"), std::string::npos) << message;
  // Every value at 1e80 is below the per-value limit, but 50·3·(1e80)² overflows the cost.
  message = error_of([&] { fit_model(lambert, lambert_samples(1e80), FitOptions{}); });
  EXPECT_NE(message.find("sum of squared values"), std::string::npos) << message;
  // Ordinary values still fit: the check refuses nothing real.
  EXPECT_TRUE(fit_model(lambert, lambert_samples(0.5), FitOptions{}).ok);
}

TEST(Hardening, OneBadMemberNeverKillsABatch) {
  const std::string dir = fresh_dir("hardening-batch-member");
  write_model_csv(dir + "/good.csv", "lambert", {"albedo=0.5"}, 200);
  write_text(dir + "/huge.csv", "lx,ly,lz,vx,vy,vz,r,g,b\n0,0,1,0,0,1,1e300,1e300,1e300\n");
  const CommandResult r =
      run_cli("batch " + dir + "/good.csv " + dir + "/huge.csv --models lambert --out " + dir + "/out");
  EXPECT_EQ(r.exit_code, 1) << r.output;  // a failed member: an error exit, not an abort (134)
  EXPECT_TRUE(fs::exists(dir + "/out/summary.json"));
  EXPECT_TRUE(fs::exists(dir + "/out/good.json"));
  EXPECT_FALSE(fs::exists(dir + "/out/huge.json"));
  EXPECT_NE(slurp(dir + "/out/summary.json").find("beyond the 1e+100"), std::string::npos);
}

// ---- Documents read back are validated against the model's parameter list and bounds.

TEST(Hardening, ResultDocumentsAreValidatedAgainstTheModel) {
  const std::string dir = fresh_dir("hardening-documents");
  const Model& ggx = *find_model("ggx");
  FitResult fit = known_result("ggx", 0.1);
  const std::string good = write_document(dir + "/good.json", dir + "/table.csv", {fit});
  EXPECT_EQ(read_fit_document(good).results.at(0).values, ggx.default_values());

  const nlohmann::json original = nlohmann::json::parse(slurp(good));
  auto rejected = [&](const std::function<void(nlohmann::json&)>& change) {
    nlohmann::json doc = original;
    change(doc["models"][0]);
    write_file_atomic(dir + "/bad.json", doc.dump());
    return error_of([&] { read_fit_document(dir + "/bad.json"); });
  };
  std::string message = rejected([](nlohmann::json& m) {
    m["channel_values"] = {nlohmann::json::array(), nlohmann::json::array(), nlohmann::json::array()};
  });
  EXPECT_NE(message.find("bad.json: models[0].channel_values[0]"), std::string::npos) << message;
  message = rejected([](nlohmann::json& m) { m["channel_values"] = {{0.5}, {0.5}, {0.5}}; });
  EXPECT_NE(message.find("expected an array of the " + std::to_string(ggx.num_values()) + " values"), std::string::npos)
      << message;
  message = rejected([](nlohmann::json& m) { m["values"] = nlohmann::json::array(); });
  EXPECT_NE(message.find("models[0].values"), std::string::npos) << message;
  // roughness is the last ggx value; its upper bound is 1.
  message = rejected([&](nlohmann::json& m) { m["values"][ggx.num_values() - 1] = 7.0; });
  EXPECT_NE(message.find("outside the bounds"), std::string::npos) << message;
  message = rejected([](nlohmann::json& m) { m["parameters"]["roughness"] = {{"value", -3.0}, {"stddev", nullptr}}; });
  EXPECT_NE(message.find("parameters.roughness.value"), std::string::npos) << message;
  message = rejected([](nlohmann::json& m) { m["model"] = "no-such-model"; });
  EXPECT_NE(message.find("models[0].model"), std::string::npos) << message;
  message = rejected([](nlohmann::json& m) { m["warnings"] = 5; });
  EXPECT_NE(message.find("bad.json"), std::string::npos) << message;
  // The fitter's verdict and warnings are accepted.
  EXPECT_EQ(rejected([](nlohmann::json& m) {
              m["verdict"] = "poor";
              m["warnings"] = {"a warning"};
            }),
            "");
}

TEST(Hardening, ExportOfAMalformedDocumentIsAnErrorNotACrash) {
  const std::string dir = fresh_dir("hardening-export");
  nlohmann::json doc =
      nlohmann::json::parse(slurp(write_document(dir + "/r.json", dir + "/t.csv", {known_result("ggx", 0.1)})));
  doc["models"][0]["channel_values"] = {nlohmann::json::array(), nlohmann::json::array(), nlohmann::json::array()};
  write_file_atomic(dir + "/r.json", doc.dump());
  const CommandResult r = run_cli("export " + dir + "/r.json --out " + dir + "/m.gltf");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("channel_values"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir + "/m.gltf"));
}

// ---- Absurd lights, intensities and exposures are refused.

TEST(Hardening, AbsurdLightsIntensitiesAndExposuresAreRefused) {
  const std::string dir = fresh_dir("hardening-lights");
  write_text(dir + "/lights.txt", "0 0 1\n1e300 1e300 1e300\n");
  EXPECT_NE(
      error_of([&] { read_light_directions(dir + "/lights.txt", 2); }).find("lights.txt:2: '1e300' is out of range"),
      std::string::npos);
  write_text(dir + "/intensities.txt", "1 1 1\n1e-300 1 1\n");
  EXPECT_NE(error_of([&] { read_light_intensities(dir + "/intensities.txt", 2); }).find("intensities.txt:2"),
            std::string::npos);
  // Within the range, directions are unit and intensities kept as given.
  write_text(dir + "/ok.txt", "0 0 1e50\n2e-50 2e-50 2e-50\n");
  const std::vector<Vec3> lights = read_light_directions(dir + "/ok.txt", 2);
  EXPECT_NEAR(lights[1].x(), 1 / std::sqrt(3.0), 1e-12);
  EXPECT_DOUBLE_EQ(lights[0].z(), 1.0);

  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_NE(error_of([&] { check_exposure_times({0.01, inf, 0.03}); }).find("--exposures"), std::string::npos);
  EXPECT_NE(error_of([&] { check_exposure_times({1, 1, 1}); }).find("given twice"), std::string::npos);
  EXPECT_NE(error_of([&] { check_exposure_times({0.01, 0.0}); }).find("positive"), std::string::npos);
  EXPECT_EQ(error_of([&] { check_exposure_times({0.01, 0.1, 1.0}); }), "");
}

// ---- Files: no output is an input or another output (by identity), outputs are checked first.

TEST(Hardening, OutputsThatAreInputsOrEachOtherAreRefused) {
  const std::string dir = fresh_dir("hardening-outputs");
  write_text(dir + "/table.csv", "x");
  ASSERT_EQ(::link((dir + "/table.csv").c_str(), (dir + "/hard.csv").c_str()), 0);
  EXPECT_NE(error_of([&] { check_outputs({dir + "/table.csv"}, {dir + "/./hard.csv"}); }).find("is the input"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              check_outputs({dir + "/table.csv"}, {dir + "/x.json", dir + "/../hardening-outputs/x.json"});
            }).find("two outputs"),
            std::string::npos);
  EXPECT_EQ(error_of([&] { check_outputs({dir + "/table.csv"}, {dir + "/x.json", "", dir + "/x.csv"}); }), "");
  EXPECT_NE(error_of([&] { check_outputs({}, {"/dev/zero"}); }).find("a device"), std::string::npos);

  // The CLI refuses before fitting and leaves the table as it was.
  write_model_csv(dir + "/t.csv", "lambert", {"albedo=0.5"}, 100);
  const std::string before = slurp(dir + "/t.csv");
  for (const std::string& args : {"--out " + dir + "/t.csv", "--csv " + dir + "/./../hardening-outputs/t.csv",
                                  "--out " + dir + "/o.json --csv " + dir + "/o.json"}) {
    const CommandResult r = run_cli("fit " + dir + "/t.csv --models lambert " + args);
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.output;
    EXPECT_EQ(r.output.find("samples"), std::string::npos) << "fitted before refusing: " << r.output;
  }
  EXPECT_EQ(slurp(dir + "/t.csv"), before);
  EXPECT_FALSE(fs::exists(dir + "/o.json"));
  // compare --markdown over one of its documents.
  write_document(dir + "/r.json", dir + "/t.csv", {known_result("lambert", 0.1)});
  const std::string document = slurp(dir + "/r.json");
  EXPECT_EQ(run_cli("compare " + dir + "/r.json --markdown " + dir + "/r.json").exit_code, 1);
  EXPECT_EQ(slurp(dir + "/r.json"), document);
}

TEST(Hardening, AtomicWritesCreateTemporariesExclusivelyAndOnlyReplaceRegularFiles) {
  const std::string dir = fresh_dir("hardening-atomic");
  // A FIFO as the output is written through, not replaced: a reader on the other end gets the
  // bytes, and the FIFO stays (issue 22: pipes and terminals are streams, not files to rename over).
  ASSERT_EQ(::mkfifo((dir + "/fifo").c_str(), 0644), 0);
  std::string received;
  std::thread reader([&] { received = slurp(dir + "/fifo"); });  // opening blocks until the writer opens
  write_file_atomic(dir + "/fifo", "x");
  reader.join();
  EXPECT_EQ(received, "x");
  struct stat info;
  ASSERT_EQ(::lstat((dir + "/fifo").c_str(), &info), 0);
  EXPECT_TRUE(S_ISFIFO(info.st_mode));
  // A device other than /dev/null is refused.
  EXPECT_NE(error_of([&] { write_file_atomic("/dev/zero", "x"); }).find("not a regular file"), std::string::npos);
  // A link planted at the old predictable temporary name is not followed.
  write_text(dir + "/victim", "precious");
  const std::string old_temp = dir + "/out.json.tmp." + std::to_string(::getpid());
  fs::create_symlink(dir + "/victim", old_temp);
  write_file_atomic(dir + "/out.json", "new");
  EXPECT_EQ(slurp(dir + "/victim"), "precious");
  EXPECT_EQ(slurp(dir + "/out.json"), "new");
  // A symbolic link (to a regular file) as the output is replaced itself; its target is left alone.
  fs::create_symlink(dir + "/victim", dir + "/link.json");
  write_file_atomic(dir + "/link.json", "via link");
  EXPECT_EQ(slurp(dir + "/victim"), "precious");
  EXPECT_FALSE(fs::is_symlink(dir + "/link.json"));
  // Written files get the usual permissions, not mkstemp's 0600.
  ASSERT_EQ(::stat((dir + "/out.json").c_str(), &info), 0);
  const mode_t mask = ::umask(0);
  ::umask(mask);
  EXPECT_EQ(info.st_mode & 0777, 0666 & ~mask);
  // Images go through the same mechanism.
  EXPECT_NE(error_of([&] {
              write_image("/dev/zero", cv::Mat(4, 4, CV_32FC3, cv::Scalar(0.5, 0.5, 0.5)));
            }).find("not a regular file"),
            std::string::npos);
}

// --resume removing only brdffit's own temporaries: Hardening2.ResumeRemovesOnlyTemporariesBrdffitCreated.

TEST(Hardening, ABatchOutputFolderIsLocked) {
  const std::string dir = fresh_dir("hardening-lock");
  {
    const OutputFolderLock lock(dir + "/out");
    EXPECT_EQ(slurp(dir + "/out/" + OutputFolderLock::kLockName), std::to_string(::getpid()) + "\n");
    EXPECT_NE(error_of([&] {
                OutputFolderLock second(dir + "/out");
              }).find("another batch (pid " + std::to_string(::getpid())),
              std::string::npos);
    // A second batch (another process) gets a clear error while this one holds the folder.
    write_model_csv(dir + "/a.csv", "lambert", {"albedo=0.5"}, 100);
    const CommandResult r = run_cli("batch " + dir + "/a.csv --models lambert --out " + dir + "/out");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.output.find("another batch"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir + "/out/a.json"));
  }
  EXPECT_FALSE(fs::exists(dir + "/out/" + std::string(OutputFolderLock::kLockName)));
  // A lock left by a killed batch (its pid no longer runs) is taken over.
  write_text(dir + "/out/" + OutputFolderLock::kLockName, "999999999\n");
  EXPECT_EQ(error_of([&] { OutputFolderLock taken(dir + "/out"); }), "");
}

TEST(Hardening, AStaleResultDoesNotSurviveAFailedRefit) {
  const std::string dir = fresh_dir("hardening-stale-result");
  write_model_csv(dir + "/a.csv", "lambert", {"albedo=0.5"}, 200);
  ASSERT_EQ(run_cli("batch " + dir + "/a.csv --models lambert --out " + dir + "/out").exit_code, 0);
  ASSERT_TRUE(fs::exists(dir + "/out/a.json"));
  write_text(dir + "/a.csv", "lx,ly,lz,vx,vy,vz,r,g,b\n0,0,1,0,0,1,nan,0,0\n");  // changed, now unreadable
  EXPECT_EQ(run_cli("batch " + dir + "/a.csv --models lambert --resume --out " + dir + "/out").exit_code, 1);
  EXPECT_FALSE(fs::exists(dir + "/out/a.json"));
  const CommandResult r = run_cli("compare " + dir + "/out");
  EXPECT_NE(r.exit_code, 0);  // nothing left to compare: the old result is not taken for this run's
}

TEST(Hardening, DocumentsStoreAbsolutePathsAndComparesRunFromAnywhere) {
  const std::string dir = fresh_dir("hardening-absolute");
  write_model_csv(dir + "/a.csv", "lambert", {"albedo=0.5"}, 100);
  const CommandResult r = run_command("cd " + dir + " && " + BRDFFIT_CLI + " fit a.csv --models lambert --out r.json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json doc = nlohmann::json::parse(slurp(dir + "/r.json"));
  EXPECT_EQ(doc["input"]["path"], fs::weakly_canonical(dir + "/a.csv").string());
  EXPECT_EQ(doc["input"]["sha256"], sha256_file(dir + "/a.csv"));
  const CommandResult batch = run_command("cd " + dir + " && " + BRDFFIT_CLI + " batch a.csv --models lambert --out b");
  ASSERT_EQ(batch.exit_code, 0) << batch.output;
  const nlohmann::json summary = nlohmann::json::parse(slurp(dir + "/b/summary.json"));
  EXPECT_EQ(summary["materials"][0]["result"], fs::weakly_canonical(dir + "/b/a.json").string());
  EXPECT_EQ(run_cli("compare " + dir + "/b/summary.json").exit_code, 0);
}

TEST(Hardening, BatchIntoItsOwnInputFolderSaysWhatIsWrong) {
  const std::string dir = fresh_dir("hardening-dot");
  write_model_csv(dir + "/a.csv", "lambert", {"albedo=0.5"}, 100);
  const CommandResult r = run_command("cd " + dir + " && " + BRDFFIT_CLI + " batch . --out .");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("inside the output folder"), std::string::npos) << r.output;
}

// ---- Bounded resources: regular files only, sizes checked before reading.

TEST(Hardening, OnlyRegularFilesWithinTheLimitAreRead) {
  const std::string dir = fresh_dir("hardening-read");
  EXPECT_NE(error_of([] { read_file("/dev/zero"); }).find("/dev/zero: cannot read: a device"), std::string::npos);
  ASSERT_EQ(::mkfifo((dir + "/fifo").c_str(), 0644), 0);  // would block forever if opened for a blocking read
  EXPECT_NE(error_of([&] { read_file(dir + "/fifo"); }).find("a FIFO"), std::string::npos);
  EXPECT_NE(error_of([&] { sha256_file(dir + "/fifo"); }).find("a FIFO"), std::string::npos);
  EXPECT_NE(error_of([&] { read_file(dir); }).find("a folder"), std::string::npos);
  write_text(dir + "/eleven", "0123456789A");
  EXPECT_NE(error_of([&] { read_file(dir + "/eleven", 10); }).find("11 bytes, more than the limit of 10"),
            std::string::npos);
  EXPECT_EQ(read_file(dir + "/eleven", 11), "0123456789A");
  const CommandResult r = run_cli("info " + dir + "/fifo");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("not a regular file"), std::string::npos) << r.output;
}

TEST(Hardening, AMerlTableLargerThanTheFormatAllowsIsRefusedBeforeReading) {
  const std::string dir = fresh_dir("hardening-merl-size");
  const int32_t header[3] = {90, 90, 180};
  write_text(dir + "/t.binary", std::string(reinterpret_cast<const char*>(header), sizeof header));
  fs::resize_file(dir + "/t.binary", uint64_t{1} << 30);  // sparse: 1 GiB that takes no disk
  const CommandResult r = run_cli("info " + dir + "/t.binary");
  EXPECT_EQ(r.exit_code, 1);
  // 12 + 3·90·90·360·8 bytes: the largest MERL table.
  EXPECT_NE(r.output.find("1073741824 bytes, more than the limit of 69984012 bytes"), std::string::npos) << r.output;
}

TEST(Hardening, SphereAndCaptureRefuseToWriteOverTheirInputs) {
  const std::string dir = fresh_dir("hardening-sphere-outputs");
  const cv::Mat grey(16, 16, CV_32FC3, cv::Scalar(0.5, 0.5, 0.5));
  write_image(dir + "/photo.png", grey);
  write_image(dir + "/frame_00.png", grey);
  write_image(dir + "/frame_01.png", grey);
  write_text(dir + "/lights.txt", "0 0 1\n");
  const std::string photo = slurp(dir + "/photo.png"), frame = slurp(dir + "/frame_01.png");
  CommandResult r = run_cli("sphere " + dir + "/photo.png --lights " + dir + "/lights.txt --out " + dir + "/photo.png");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("the output is the input"), std::string::npos) << r.output;
  r = run_cli("sphere " + dir + "/photo.png --lights " + dir + "/lights.txt --out " + dir + "/lights.txt");
  EXPECT_NE(r.output.find("the output is the input"), std::string::npos) << r.output;
  r = run_cli("capture " + dir + "/frame_%02d.png --out " + dir + "/frame_01.png");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("the output is the input"), std::string::npos) << r.output;
  EXPECT_EQ(slurp(dir + "/photo.png"), photo);
  EXPECT_EQ(slurp(dir + "/frame_01.png"), frame);
}

TEST(Hardening, CsvIsStreamedLineByLineWithTheSameResult) {
  const std::string text =
      "# unit: degrees\ntheta_i,phi_i,theta_o,phi_o,r,g,b\n30,0,30,180,0.5,0.25,0.125\n\n60,0,0,0,1,1,1\n";
  std::istringstream lines(text);
  const SampleSet streamed = read_csv_samples(lines, "s.csv");
  ASSERT_EQ(streamed.size(), 2u);
  // f·cosθi with θi = 30°: 0.5·cos30° = 0.4330127...
  EXPECT_NEAR(streamed.samples[0].value[0], 0.5 * std::sqrt(3.0) / 2, 1e-15);
  EXPECT_NEAR(streamed.samples[1].value[2], 0.5, 1e-15);
  EXPECT_EQ(parse_csv_samples(text, "s.csv").samples[0].value, streamed.samples[0].value);
}

TEST(Hardening, ImagesAboveThePixelLimitAreRefusedBeforeDecoding) {
  const std::string dir = fresh_dir("hardening-pixels");
  write_image(dir + "/img.exr", cv::Mat(20, 30, CV_32FC3, cv::Scalar(0.25, 0.5, 0.75)), Encoding::Float);
  const uint64_t saved = get_max_image_pixels();
  set_max_image_pixels(599);
  const std::string message = error_of([&] { read_image(dir + "/img.exr"); });
  set_max_image_pixels(600);
  const cv::Mat image = read_image(dir + "/img.exr");
  set_max_image_pixels(saved);
  EXPECT_NE(message.find("30x20 pixels, more than the limit of 599 pixels (raise it with --max-pixels)"),
            std::string::npos)
      << message;
  EXPECT_EQ(image.cols, 30);
}

// ---- Output hygiene.

TEST(Hardening, CompareMarkdownEscapesNames) {
  const std::string dir = fresh_dir("hardening-markdown");
  nlohmann::json doc =
      nlohmann::json::parse(slurp(write_document(dir + "/r.json", dir + "/t.csv", {known_result("lambert", 0.1)})));
  doc["material"] = "<script>alert(1)</script>|*x*";
  write_file_atomic(dir + "/r.json", doc.dump());
  const std::string md = comparison_markdown(compare_results({read_fit_document(dir + "/r.json")}, Metric::Cosine));
  EXPECT_EQ(md.find("<script>"), std::string::npos) << md;
  EXPECT_NE(md.find("| &lt;script&gt;alert(1)&lt;/script&gt;\\|\\*x\\* |"), std::string::npos) << md;
  EXPECT_EQ(escape_markdown("a\nb_c`d[e]"), "a b\\_c\\`d\\[e\\]");
}

TEST(Hardening, ErrorMessagesEscapeControlCharactersAndKeepWhatFollowsANul) {
  const std::string raw = std::string("bad \x1b[31mred") + '\0' + "after\x7f\r";
  const Error e(raw);
  EXPECT_EQ(std::string(e.what()), "bad \\x1b[31mred\\x00after\\x7f\\x0d");
  const std::string dir = fresh_dir("hardening-escape");
  write_text(dir + "/t.csv", "\x1b]0;owned\x07,x\n");
  const CommandResult r = run_cli("fit " + dir + "/t.csv");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.output.find('\x1b'), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\\x1b]0;owned\\x07,x"), std::string::npos) << r.output;
}

TEST(Hardening, NegativeOrAbsurdOptionValuesAreRefused) {
  const std::string dir = fresh_dir("hardening-options");
  write_model_csv(dir + "/t.csv", "lambert", {"albedo=0.5"}, 50);
  for (std::string command :
       {"fit T --max-samples -1", "fit T --threads -5", "fit T --threads 100000", "fit T --seed -1",
        "batch T --jobs -2 --out D/o", "batch T --threads -1 --out D/o", "report D --top -3 --out D/r.html",
        "sphere T --max-samples -1", "capture 0 --frames -1 --out D/x.exr"}) {
    for (const auto& [placeholder, value] :
         {std::pair<std::string, std::string>{" T", " " + dir + "/t.csv"}, {" D", " " + dir}})
      for (size_t at; (at = command.find(placeholder)) != std::string::npos;)
        command.replace(at, placeholder.size(), value);
    SCOPED_TRACE(command);
    const CommandResult r = run_cli(command);
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.output.find("not in range"), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(dir + "/o"));
}

}  // namespace
}  // namespace brdffit::test
