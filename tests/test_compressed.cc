// Compressed inputs (.xz, .gz): read as the uncompressed file would be, recognised by content,
// and a damaged or oversized one refused with a message naming it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "brdffit/compressed.h"
#include "brdffit/csv_samples.h"
#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/measured.h"
#include "brdffit/merl.h"
#include "test_util.h"

namespace brdffit {
namespace {

namespace fs = std::filesystem;

class Compressed : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::fresh_dir("compressed");
    table_ = dir_ + "/paint.binary";
    // A Lambert table of albedo (0.5, 0.25, 0.125): f = albedo/π.
    write_merl(table_, [](const Vec3&, const Vec3&) -> Rgb<double> { return Rgb<double>(0.5, 0.25, 0.125) / kPi; });
    ASSERT_EQ(test::run_command("xz -k -c " + table_ + " > " + table_ + ".xz").exit_code, 0);
    ASSERT_EQ(test::run_command("gzip -c " + table_ + " > " + table_ + ".gz").exit_code, 0);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string dir_, table_;
};

void expect_same_samples(const SampleSet& a, const SampleSet& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.samples[i].value, b.samples[i].value) << i;
    EXPECT_EQ(a.samples[i].l, b.samples[i].l) << i;
  }
}

TEST_F(Compressed, XzAndGzipTablesReadAsTheTableItself) {
  const SamplingOptions options{90.0, 5000, 3, false};
  const SampleSet plain = load_samples(table_, options);
  expect_same_samples(load_samples(table_ + ".xz", options), plain);
  expect_same_samples(load_samples(table_ + ".gz", options), plain);
  // By content, not by name: a compressed table under any name opens.
  fs::copy_file(table_ + ".xz", dir_ + "/renamed.data");
  expect_same_samples(load_samples(dir_ + "/renamed.data", options), plain);
  EXPECT_NEAR(describe_measured(table_ + ".gz").albedo[0], 0.5, 1e-3);
  // Through the command line: the same fit as the uncompressed table.
  const auto fit = test::run_cli("fit " + table_ + ".xz -m lambert --threads 1");
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  EXPECT_NE(fit.output.find("albedo=[0.5,0.25,0.125]"), std::string::npos) << fit.output;
}

TEST_F(Compressed, CompressedCsvSamplesRead) {
  const std::string csv = dir_ + "/s.csv";
  write_file_atomic(csv, "lx,ly,lz,vx,vy,vz,r,g,b\n0,0,1,0,0,1,0.1,0.2,0.3\n0.6,0,0.8,0,0,1,0.1,0.2,0.3\n");
  ASSERT_EQ(test::run_command("gzip -k " + csv).exit_code, 0);
  expect_same_samples(load_samples(csv + ".gz", SamplingOptions{}), load_samples(csv, SamplingOptions{}));
}

TEST_F(Compressed, NamesAndMaterialNamesLookThroughTheSuffix) {
  EXPECT_TRUE(has_table_extension("a/gold.binary.xz"));
  EXPECT_TRUE(has_table_extension("a/gold.BSDF.gz"));
  EXPECT_FALSE(has_table_extension("a/notes.txt.gz"));
  EXPECT_EQ(table_material_name("a/gold-metallic-paint.binary.xz"), "gold-metallic-paint");
  EXPECT_EQ(without_compression_suffix("x.csv.gz"), "x.csv");
  EXPECT_EQ(table_material_name("a/GOLD.BINARY.XZ"), "GOLD");
  EXPECT_EQ(without_compression_suffix("x.csv"), "x.csv");
}

TEST_F(Compressed, DamagedOrOversizedFilesAreRefusedByName) {
  const std::string bytes = read_file(table_ + ".xz");
  const std::string truncated = dir_ + "/truncated.binary.xz";
  write_file_atomic(truncated, bytes.substr(0, bytes.size() / 2));
  std::string corrupt_gz = read_file(table_ + ".gz");
  corrupt_gz[corrupt_gz.size() / 2] ^= 0x55;
  const std::string corrupt = dir_ + "/corrupt.binary.gz";
  write_file_atomic(corrupt, corrupt_gz);
  const std::string cut_gz = dir_ + "/cut.binary.gz";
  write_file_atomic(cut_gz, read_file(table_ + ".gz").substr(0, 100));
  const std::vector<std::pair<std::string, std::string>> cases = {
      {truncated, ": xz: truncated"}, {corrupt, ": gzip: corrupt data"}, {cut_gz, ": gzip: truncated"}};
  for (const auto& [path, problem] : cases) {
    try {
      load_samples(path, SamplingOptions{});
      ADD_FAILURE() << path << " was read";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()), path + problem) << e.what();
    }
  }
  // A decompression bomb (or a file that is no table): refused at the limit, not read to the end.
  // Under the sanitizers this also shows that the decoder's state is freed when the limit throws.
  for (const auto& [suffix, compression] : {std::pair{".xz", Compression::Xz}, std::pair{".gz", Compression::Gzip}}) {
    try {
      decompress_file(table_ + suffix, compression, 1000);
      ADD_FAILURE() << "decompressed past the limit";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()),
                table_ + suffix + ": decompresses to more than 1000 bytes: not a measured table");
    }
  }
}

}  // namespace
}  // namespace brdffit
