// Hardening, second round (issue 22): each class of defect fixed at its root, each test building
// its input from scratch and failing on the code before the fix.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "batch_test_util.h"
#include "brdffit/batch.h"
#include "brdffit/batch_shard.h"
#include "brdffit/compressed.h"
#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/imaging/capture.h"
#include "brdffit/imaging/image_io.h"
#include "brdffit/imaging/sphere_fit.h"
#include "brdffit/io.h"
#include "brdffit/material_export.h"
#include "brdffit/measured.h"
#include "brdffit/merl.h"
#include "brdffit/published_fits.h"
#include "brdffit/registry.h"
#include "brdffit/result_json.h"
#include "brdffit/samples.h"
#include "test_util.h"

namespace brdffit::test {
namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// ---- Crashes and whole-run failures

TEST(Hardening2, JsonDepthIsCountedOutsideStrings) {
  EXPECT_EQ(json_depth("1"), 0u);
  EXPECT_EQ(json_depth(R"({"a": [1, {"b": "[[[{{{"}], "c": "\"]"})"), 3u);
  EXPECT_EQ(json_depth(std::string(500, '[') + std::string(500, ']')), 500u);
}

TEST(Hardening2, DeeplyNestedJsonIsRefusedNamingTheFile) {
  const std::string dir = fresh_dir("hardening2-nested");
  const std::string brackets = std::string(200000, '[') + std::string(200000, ']');
  const std::string document = dir + "/doc.json", gltf = dir + "/m.gltf", summary = dir + "/summary.json";
  write_text(document, R"({"schema": 1, "input": {"path": "x"}, "models": )" + brackets + "}");
  write_text(gltf, R"({"materials": [{"extras": )" + brackets + "}]}");
  write_text(summary, R"({"materials": )" + brackets + "}");
  const std::string limit = "nested 200003 levels deep, more than the limit of 64";
  const std::string deep = "nested 200001 levels deep, more than the limit of 64";
  EXPECT_TRUE(contains(error_of([&] { read_fit_document(document); }), document + ": not a JSON file: nested 200001"));
  std::vector<std::string> warnings;
  EXPECT_TRUE(contains(error_of([&] { read_materials(gltf, warnings); }), gltf + ": not a glTF (JSON) file: " + limit));
  EXPECT_TRUE(contains(error_of([&] { read_summary_results(summary); }), summary + ": not a batch summary: " + deep));
  // compare reads summaries and documents the same way: an error, not a crash.
  const CommandResult r = run_cli("compare " + summary);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(contains(r.output, deep)) << r.output;
}

TEST(Hardening2, NamesThatAreNotUtf8AreStoredLosslessly) {
  const std::string name = "m\xff\xfe\xc0\xaf.csv";
  nlohmann::json object = nlohmann::json::object();
  put_name(object, "input", name);
  EXPECT_EQ(object["input_bytes"], "6dfffec0af2e637376");
  EXPECT_EQ(get_name(nlohmann::json::parse(json_text(object)), "input", "x"), name);
  nlohmann::json plain = nlohmann::json::object();
  put_name(plain, "input", "plain.csv");
  EXPECT_FALSE(plain.contains("input_bytes"));

  // A batch over a folder holding such a name fits it and writes its summary; fit --out too.
  const std::string dir = fresh_dir("hardening2-names");
  fs::create_directories(dir + "/in");
  write_model_csv(dir + "/in/" + name, "lambert", {"albedo=0.5"}, 200);
  write_model_csv(dir + "/in/good.csv", "lambert", {"albedo=0.3"}, 200);
  const CommandResult batch = run_cli("batch " + dir + "/in --models lambert --out " + dir + "/out");
  EXPECT_EQ(batch.exit_code, 0) << batch.output;
  const std::vector<std::string> results = read_summary_results(dir + "/out/summary.json");
  ASSERT_EQ(results.size(), 2u);
  const std::vector<FitDocument> documents = read_fit_documents({dir + "/out/summary.json"});
  std::set<std::string> inputs;
  for (const FitDocument& d : documents) inputs.insert(d.input_path);
  EXPECT_TRUE(inputs.count(absolute_path(dir + "/in/" + name)));
  const CommandResult fit = run_cli("fit '" + dir + "/in/" + name + "' --models lambert --out " + dir + "/one.json");
  EXPECT_EQ(fit.exit_code, 0) << fit.output;
  EXPECT_EQ(read_fit_document(dir + "/one.json").input_path, absolute_path(dir + "/in/" + name));
}

TEST(Hardening2, ImagesAreCappedByTheBytesTheyDecodeTo) {
  const std::string dir = fresh_dir("hardening2-channels");
  const auto write_tiff = [&](const std::string& path, int channels) {
    const std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, OIIO::ImageSpec(8, 8, channels, OIIO::TypeDesc::UINT8)));
    const std::vector<uint8_t> pixels(8 * 8 * channels, 100);
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
    out->close();
  };
  write_tiff(dir + "/rgba.tif", 4);
  write_tiff(dir + "/many.tif", 16);
  const uint64_t saved = get_max_image_pixels();
  set_max_image_pixels(100);  // 64 pixels pass; 100 × 4 channels × 4 bytes = 1600 bytes of floats
  EXPECT_EQ(read_image(dir + "/rgba.tif").cols, 8);  // 64 × 4 × 4 = 1024 bytes
  const std::string message = error_of([&] { read_image(dir + "/many.tif"); });
  set_max_image_pixels(saved);
  EXPECT_TRUE(contains(message, "8x8 pixels of 16 channels decode to 4096 bytes, more than the limit of 1600 bytes"))
      << message;
}

TEST(Hardening2, SpherePanelsAreCheckedAgainstThePhotographsBeforeAnyWork) {
  const std::string dir = fresh_dir("hardening2-panels");
  SphereInput input;
  // The first photograph's panel would land on the second photograph.
  input.images = {dir + "/shot.png", dir + "/photos/lambert/001_shot.png"};
  const PanelOutput panels{dir + "/photos", "png"};
  const std::vector<const Model*> models = {find_model("lambert")};
  EXPECT_EQ(panel_paths(panels, input, models),
            (std::vector<std::string>{dir + "/photos/lambert/001_shot.png", dir + "/photos/lambert/002_001_shot.png"}));
  fs::create_directories(dir + "/photos/lambert");
  write_text(input.images[1], "a photograph");
  EXPECT_TRUE(contains(error_of([&] { check_outputs(sphere_input_files(input), panel_paths(panels, input, models)); }),
                       "the output is the input"));
}

// ---- Files touched that were never named as outputs

TEST(Hardening2, OutputsThatAreLinksToPipesAreWrittenThrough) {
  const std::string dir = fresh_dir("hardening2-pipe");
  ASSERT_EQ(::mkfifo((dir + "/fifo").c_str(), 0644), 0);
  fs::create_symlink(dir + "/fifo", dir + "/stdout");  // as /dev/stdout → /proc/self/fd/1 → a pipe
  std::string received;
  std::thread reader([&] { received = slurp(dir + "/fifo"); });
  check_outputs({}, {dir + "/stdout"});
  write_file_atomic(dir + "/stdout", "a,b\n1,2\n");
  reader.join();
  EXPECT_EQ(received, "a,b\n1,2\n");
  EXPECT_TRUE(fs::is_symlink(dir + "/stdout"));
  EXPECT_TRUE(fs::is_fifo(dir + "/fifo"));
  write_file_atomic("/dev/null", "discarded");  // a character device that is a sink
  // A descriptor link (/dev/stdout redirected to a file) leads to a regular file: written
  // through (appended), the link left in place.
  write_text(dir + "/redirected.txt", "printed before\n");
  const int fd = ::open((dir + "/redirected.txt").c_str(), O_WRONLY | O_APPEND);
  ASSERT_GE(fd, 0);
  fs::create_symlink("/proc/self/fd/" + std::to_string(fd), dir + "/descriptor");
  write_file_atomic(dir + "/descriptor", "the table\n");
  ::close(fd);
  EXPECT_TRUE(fs::is_symlink(dir + "/descriptor"));
  EXPECT_EQ(slurp(dir + "/redirected.txt"), "printed before\nthe table\n");
  // A link to a folder (or a disk) is still refused, and nothing is left beside it.
  fs::create_directories(dir + "/folder");
  fs::create_symlink(dir + "/folder", dir + "/to-folder");
  EXPECT_TRUE(contains(error_of([&] { write_file_atomic(dir + "/to-folder", "x"); }), "a folder, not a regular file"));
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().rfind(kTempPrefix, 0), std::string::npos) << entry.path();
}

TEST(Hardening2, ResumeRemovesOnlyTemporariesBrdffitCreated) {
  const std::string dir = fresh_dir("hardening2-temp");
  write_model_csv(dir + "/a.csv", "lambert", {"albedo=0.5"}, 200);
  fs::create_directories(dir + "/out");
  const std::vector<std::string> ours = {kTempPrefix + "a.json.Ab3xYz", kTempPrefix + "x.png.Q1w2E3.png"};
  const std::vector<std::string> users = {"notes.json.tmp.Ab3xYz", "a.json.tmp.123456", "data.tmp.txt"};
  for (const std::string& name : ours) write_text(dir + "/out/" + name, "{");
  for (const std::string& name : users) write_text(dir + "/out/" + name, "mine");
  const CommandResult r = run_cli("batch " + dir + "/a.csv --models lambert --resume --out " + dir + "/out");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  for (const std::string& name : ours) EXPECT_FALSE(fs::exists(dir + "/out/" + name)) << name;
  for (const std::string& name : users) EXPECT_EQ(slurp(dir + "/out/" + name), "mine") << name;
  // The temporaries write_file_atomic makes carry the prefix.
  const std::string planted = dir + "/out/" + kTempPrefix + "b.json.Zz9Zz9";
  write_text(planted, "{");
  EXPECT_EQ(remove_stale_temp_files(dir + "/out"), 1);
}

TEST(Hardening2, CapturePatternsAreExpandedOnceForTheCheckAndTheReading) {
  const std::string dir = fresh_dir("hardening2-capture");
  for (const char* frame : {"/shot_01.png", "/shot_02.png"})
    write_image(dir + frame, cv::Mat(4, 4, CV_32FC3, cv::Scalar(0.5, 0.5, 0.5)), Encoding::Srgb8);
  const std::string before = slurp(dir + "/shot_01.png");
  // printf's %2d pads with a space: shot_ 1.png, which does not exist. Nothing is read, nothing
  // overwritten (OpenCV expanded it to shot_01.png before).
  EXPECT_TRUE(capture_input_files(dir + "/shot_%2d.png").empty());
  const CommandResult r = run_cli("capture '" + dir + "/shot_%2d.png' --out " + dir + "/shot_01.png");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(contains(r.output, "no frame of this image sequence exists")) << r.output;
  EXPECT_EQ(slurp(dir + "/shot_01.png"), before);
  // The zero-padded pattern lists both frames, and an output among them is refused.
  EXPECT_EQ(capture_input_files(dir + "/shot_%02d.png"),
            (std::vector<std::string>{dir + "/shot_01.png", dir + "/shot_02.png"}));
  const CommandResult same = run_cli("capture '" + dir + "/shot_%02d.png' --out " + dir + "/shot_02.png");
  EXPECT_NE(same.exit_code, 0);
  EXPECT_TRUE(contains(same.output, "the output is the input")) << same.output;
}

TEST(Hardening2, OneLockProtocolForWholeFolderAndShardRuns) {
  const std::string dir = fresh_dir("hardening2-lock"), out = dir + "/out";
  {
    const OutputFolderLock shard0(out, 0, 2);
    EXPECT_EQ(error_of([&] { OutputFolderLock shard1(out, 1, 2); }), "");  // shards of one batch run together
    EXPECT_TRUE(contains(error_of([&] { OutputFolderLock again(out, 0, 2); }), "another batch (shard 0/2)"));
    EXPECT_TRUE(contains(error_of([&] { OutputFolderLock other(out, 1, 3); }), "shards of another number than 3"));
    EXPECT_TRUE(contains(error_of([&] { OutputFolderLock whole(out); }), "another batch"));
    // Another process: a plain batch, a merge and a shard of another N are refused.
    const std::string in = write_shard_inputs(dir);
    const std::string batch = "batch " + in + " --models lambert --threads 1 --out " + out;
    for (const std::string& extra : {std::string(), std::string(" --merge"), std::string(" --shard 0/3")}) {
      const CommandResult r = run_cli(batch + extra);
      EXPECT_EQ(r.exit_code, 1) << extra << r.output;
      EXPECT_TRUE(contains(r.output, "is writing into this folder")) << r.output;
    }
    EXPECT_FALSE(fs::exists(out + "/summary.json"));
  }
  EXPECT_FALSE(fs::exists(out + "/" + std::string(OutputFolderLock::kLockName)));  // the last holder removed it
  {
    const OutputFolderLock whole(out);
    EXPECT_EQ(slurp(out + "/" + OutputFolderLock::kLockName), std::to_string(::getpid()) + "\n");
    EXPECT_TRUE(contains(error_of([&] { OutputFolderLock shard(out, 0, 2); }),
                         "another batch (pid " + std::to_string(::getpid()) + ")"));
  }
}

TEST(Hardening2, TwoSpellingsThroughLinkedFoldersAreOneOutput) {
  const std::string dir = fresh_dir("hardening2-linked");
  fs::create_directories(dir + "/real");
  fs::create_directory_symlink(dir + "/real", dir + "/l");
  fs::create_directory_symlink(dir + "/real", dir + "/r");
  EXPECT_TRUE(contains(error_of([&] {
                         check_outputs({}, {dir + "/l/x.json", dir + "/r/x.json"});
                       }),
                       "the same file is given as two outputs"));
  EXPECT_EQ(error_of([&] { check_outputs({}, {dir + "/l/x.json", dir + "/r/y.json"}); }), "");
}

// ---- Resources

TEST(Hardening2, CompressedTablesStopAtTheSizeTheirHeaderImplies) {
  const std::string dir = fresh_dir("hardening2-bomb");
  // A 90x90x180 header implies 12 + 3·90·90·180·8 bytes; this stream holds 2 MB more.
  const uint64_t implied = 12 + uint64_t{3} * 90 * 90 * 180 * 8;
  std::string bytes(implied + (2 << 20), '\0');
  const int32_t header[3] = {90, 90, 180};
  std::memcpy(bytes.data(), header, sizeof header);
  write_text(dir + "/big.binary", bytes);
  ASSERT_EQ(run_command("xz -0 -f " + dir + "/big.binary").exit_code, 0);
  EXPECT_TRUE(contains(error_of([&] { open_measured(dir + "/big.binary.xz"); }),
                       "decompresses to more than " + std::to_string(implied) + " bytes"));
  // A header of no table: refused on its first bytes, naming its dimensions, whatever follows.
  const int32_t empty[3] = {90, 90, 0};
  std::memcpy(bytes.data(), empty, sizeof empty);
  write_text(dir + "/zero.binary", bytes);
  ASSERT_EQ(run_command("gzip -f " + dir + "/zero.binary").exit_code, 0);
  size_t seen = 0;
  const std::string message = error_of([&] {
    decompress_file(dir + "/zero.binary.gz", Compression::Gzip, [&](const std::string& head) -> uint64_t {
      seen = head.size();
      return MerlTable::file_size(head, "zero");
    });
  });
  EXPECT_TRUE(contains(message, "dimensions 90x90x0")) << message;
  EXPECT_EQ(seen, kHeadBytes);  // decided on the first 16 bytes, not after 2 GB
}

TEST(Hardening2, MaterialFilesAreBoundedInSize) {
  const std::string dir = fresh_dir("hardening2-material-size");
  std::string xml = "<scene version=\"3.0.0\">\n";
  while (xml.size() <= kMaxMaterialFileBytes) xml += "<!-- padding padding padding padding padding padding -->\n";
  write_text(dir + "/big.xml", xml + "</scene>\n");
  std::vector<std::string> warnings;
  EXPECT_TRUE(
      contains(error_of([&] { read_materials(dir + "/big.xml", warnings); }), "more than the limit of 16777216"));
  // Many shaders with their inputs: each gets its own (children are indexed, not searched).
  std::string mtlx = "<?xml version=\"1.0\"?>\n<materialx version=\"1.39\">\n";
  for (int i = 0; i < 300; ++i)
    mtlx += fmt::format(
        "<open_pbr_surface name=\"s{0}\" type=\"surfaceshader\"><input name=\"base_color\" type=\"color3\" "
        "value=\"{1}, {1}, {1}\" /></open_pbr_surface>\n",
        i, 0.001 * (i + 1));
  write_text(dir + "/many.mtlx", mtlx + "</materialx>\n");
  const std::vector<Material> materials = read_materials(dir + "/many.mtlx", warnings);
  ASSERT_EQ(materials.size(), 300u);
  const Model& openpbr = *find_model("openpbr");
  EXPECT_DOUBLE_EQ(materials[299].values[openpbr.offset_of("base_color")], 0.3);
  EXPECT_DOUBLE_EQ(materials[0].values[openpbr.offset_of("base_color") + 2], 0.001);
}

TEST(Hardening2, ShardCountsAreBoundedAndSharesAllocatedByMembers) {
  EXPECT_TRUE(
      contains(error_of([] { parse_shard("0/300000000"); }), "300000000 shards, more than the limit of 100000"));
  EXPECT_EQ(parse_shard("99999/100000").count, 100000);
  // Three materials among 100000 shards: the largest in shard 0, the next in 1, the smallest in 2.
  const std::string dir = fresh_dir("hardening2-shards");
  std::vector<BatchMaterial> materials;
  for (const auto& [name, size] : {std::pair{"small", 10}, std::pair{"large", 300}, std::pair{"middle", 100}}) {
    write_text(dir + "/" + name + ".csv", std::string(size, 'x'));
    materials.push_back({name, dir + "/" + name + ".csv"});
  }
  const auto share = [&](int index) {
    const std::vector<BatchMaterial> mine = shard_materials(materials, {index, 100000});
    return mine.size() == 1 ? mine[0].name : std::to_string(mine.size());
  };
  EXPECT_EQ(share(0), "large");
  EXPECT_EQ(share(1), "middle");
  EXPECT_EQ(share(2), "small");
  EXPECT_EQ(share(3), "0");
  EXPECT_EQ(share(99999), "0");
}

// ---- Wrong answers without an error

TEST(Hardening2, PublishedParametersAreCheckedAgainstTheBounds) {
  const std::string dir = fresh_dir("hardening2-published");
  for (const std::string roughness : {"1e-310", "-0.2"}) {
    SCOPED_TRACE(roughness);
    write_text(dir + "/p.fit",
               "m1 = Aggregate(Lambertian(albedo = [0.1, 0.2, 0.3]), NganWard(albedo = [0.01, 0.02, 0.03], "
               "roughness = " +
                   roughness + "))\n");
    const std::string message = error_of([&] { find_published_fits(dir + "/p.fit", "m1"); });
    EXPECT_TRUE(
        contains(message, dir + "/p.fit: m1 (NganWard as ward): alpha must be at least 0.001, got " + roughness))
        << message;
  }
}

TEST(Hardening2, TablesBelowTheMagnitudeFloorAreRefused) {
  SampleSet tiny;
  tiny.source = "tiny-table";
  for (int i = 0; i < 50; ++i)
    tiny.samples.push_back(
        {dir(0.1 * (i % 5), 0.0, 1.0), dir(0.0, 0.1 * (i % 3), 1.0), Rgb<double>::Constant(5e-301), 1.0});
  const std::string message = error_of([&] { fit_model(*find_model("lambert"), tiny, FitOptions{}); });
  EXPECT_TRUE(contains(message, "tiny-table: the largest sample value is 5e-301, below the 1e-100")) << message;
  for (Sample& s : tiny.samples) s.value = Rgb<double>::Constant(0.3), s.weight = 1e-200;
  EXPECT_TRUE(contains(error_of([&] { check_sample_magnitudes(tiny); }), "the largest sample weight is 1e-200"));
  for (Sample& s : tiny.samples) s.weight = 1.0;
  tiny.samples[3].value = Rgb<double>::Constant(1e-200);  // one tiny value among ordinary ones is data
  EXPECT_EQ(error_of([&] { check_sample_magnitudes(tiny); }), "");
}

TEST(Hardening2, OptionalFieldsAreLookedUpSafelyAndTypedFieldsNamed) {
  const nlohmann::json document = {{"input", {{"path", "/x"}}}};
  EXPECT_EQ(json_field(document, {"input", "sha256"}), nullptr);
  EXPECT_EQ(json_field(document, {"input", "path", "deeper"}), nullptr);
  ASSERT_NE(json_field(document, {"input", "path"}), nullptr);
  EXPECT_EQ(*json_field(document, {"input", "path"}), "/x");

  const std::string dir = fresh_dir("hardening2-types");
  const std::string good = write_document(dir + "/good.json", dir + "/t.csv", {known_result("lambert", 0.01)});
  for (const auto& [field, value, message] :
       {std::tuple{"samples", nlohmann::json("x"), "samples: expected a whole number, found string"},
        std::tuple{"metric", nlohmann::json::array({1}), "metric: expected a string, found array"},
        std::tuple{"material", nlohmann::json(3), "material: expected a string, found number"}}) {
    nlohmann::json bad = nlohmann::json::parse(read_file(good));
    bad[field] = value;
    write_text(dir + "/bad.json", bad.dump());
    EXPECT_TRUE(contains(error_of([&] { read_fit_document(dir + "/bad.json"); }), dir + "/bad.json: " + message))
        << field;
    const CommandResult r = run_cli("compare " + dir + "/bad.json");
    EXPECT_EQ(r.exit_code, 1) << r.output;  // an error (1), not an internal error (70)
    EXPECT_TRUE(contains(r.output, message)) << r.output;
  }
  std::vector<std::string> warnings;
  write_text(dir + "/m.gltf", R"({"materials": [1]})");
  EXPECT_TRUE(contains(error_of([&] { read_materials(dir + "/m.gltf", warnings); }),
                       dir + "/m.gltf: materials[0]: expected an object, found number"));
  write_text(dir + "/m.gltf", R"({"materials": [{"name": "a", "pbrMetallicRoughness": {"metallicFactor": "x"}}]})");
  EXPECT_TRUE(contains(error_of([&] { read_materials(dir + "/m.gltf", warnings); }), "metallicFactor"));
  write_text(dir + "/m.gltf", R"({"materials": [{"name": 3}]})");
  EXPECT_TRUE(contains(error_of([&] { read_materials(dir + "/m.gltf", warnings); }), dir + "/m.gltf: materials[0]: "));
}

// ---- Output hygiene

TEST(Hardening2, PrintedTextEscapesControlsAndBytesThatAreNotUtf8) {
  EXPECT_EQ(printable("a\x1b[2Jb\r\x7f"), "a\\x1b[2Jb\\x0d\\x7f");
  EXPECT_EQ(printable("caf\xc3\xa9\n\tx"), "caf\xc3\xa9\n\tx");  // UTF-8, line breaks and tabs kept
  EXPECT_EQ(printable("\xc2\x9b"
                      "31m"),
            "\\xc2\\x9b31m");                                                          // C1 CSI
  EXPECT_EQ(printable("\xff\xc0\xaf\xed\xa0\x80"), "\\xff\\xc0\\xaf\\xed\\xa0\\x80");  // F5–FF, overlong, surrogate
  // A file named with an escape sequence: what fit prints carries no ESC byte.
  const std::string dir = fresh_dir("hardening2-terminal");
  const std::string name = dir + "/red\x1b[2J.csv";
  write_model_csv(name, "lambert", {"albedo=0.5"}, 100);
  const CommandResult r = run_cli("fit '" + name + "' --models lambert");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find('\x1b'), std::string::npos) << r.output;
  EXPECT_TRUE(contains(r.output, "red\\x1b[2J.csv")) << r.output;
}

TEST(Hardening2, XmlExportsCarryOnlyXmlCharacters) {
  EXPECT_TRUE(valid_utf8("caf\xc3\xa9 \xf0\x9f\x98\x80"));
  for (const char* bad : {"\xf5\x80\x80\x80", "\xc0\xaf", "\xed\xa0\x80", "\xf4\x90\x80\x80", "\x80", "\xe2\x82"})
    EXPECT_FALSE(valid_utf8(bad)) << bad;
  const std::string dir = fresh_dir("hardening2-xml");
  const std::string name = "odd \xef\xbf\xbe \xf5 \xc0\xaf \xed\xa0\x80 end";
  // The name reaches the XML comment through the input's path (stored losslessly, read back as bytes).
  nlohmann::json document = fit_document_json(dir + "/" + name + ".csv", SampleSet{}, FitOptions{},
                                              {known_result("principled", 0.01), known_result("openpbr", 0.01)});
  put_name(document, "material", name);
  write_text(dir + "/doc.json", json_text(document, 2));
  // The openpbr fit as MaterialX; Mitsuba's own model is mitsuba-principled, the principled fit is converted to it.
  for (const auto& [out, model] : {std::pair{"/m.mtlx", "openpbr"}, {"/m.xml", "principled"}}) {
    const CommandResult r = run_cli("export " + dir + "/doc.json --force --model " + model + " --out " + dir + out);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::string xml = slurp(dir + out);
    EXPECT_TRUE(valid_utf8(xml)) << xml;
    EXPECT_EQ(xml.find("\xef\xbf\xbe"), std::string::npos) << xml;
    if (run_command("command -v xmllint").exit_code == 0)
      EXPECT_EQ(run_command("xmllint --noout " + dir + out).exit_code, 0) << xml;
  }
}

}  // namespace
}  // namespace brdffit::test
