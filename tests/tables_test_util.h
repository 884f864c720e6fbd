// Helpers for the measured-input tests (test_merl, test_rgl, test_csv, test_tables_cli):
// scratch files, the shared data, and checking error messages.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "brdffit/error.h"
#include "brdffit/math.h"
#include "test_util.h"

namespace brdffit::test {

namespace fs = std::filesystem;

inline const std::string kSharedDir = BRDFFIT_SHARED_DIR;

// tables-test-data/ beside the test binary, in the build tree: kept between runs (it caches
// the decompressed MERL proxies) and outside git.
inline std::string test_data_dir() {
  static const std::string dir = [] {
    const fs::path path = fs::read_symlink("/proc/self/exe").parent_path() / "tables-test-data";
    fs::create_directories(path);
    return path.string();
  }();
  return dir;
}

// A path for a scratch file of this test process, in its scratch folder (test_util.h).
inline std::string scratch_path(const std::string& name) {
  fs::create_directories(scratch_root());
  return (scratch_root() / name).string();
}

// The shared MERL-format proxy `name` (e.g. "gold-metallic-paint") decompressed into the test
// data directory, once: later tests and runs reuse it while it is newer than the .xz. Empty
// when the shared data is absent.
inline std::string merl_proxy(const std::string& name) {
  const fs::path packed = kSharedDir + "/data/merl-proxy/" + name + ".binary.xz";
  if (!fs::exists(packed)) return "";
  const fs::path path = fs::path(test_data_dir()) / (name + ".binary");
  const uintmax_t merl_size = 12 + 3 * 90 * 90 * 180 * sizeof(double);
  if (!fs::exists(path) || fs::file_size(path) != merl_size ||
      fs::last_write_time(path) < fs::last_write_time(packed)) {
    // Decompress beside it and rename, so a concurrent test process never sees half a file.
    const std::string part = path.string() + ".part" + std::to_string(::getpid());
    const CommandResult r =
        run_command("xz -dkc '" + packed.string() + "' > '" + part + "' && mv '" + part + "' '" + path.string() + "'");
    EXPECT_EQ(r.exit_code, 0) << "decompressing " << packed << ": " << r.output;
  }
  return path.string();
}

// All RGL files of the shared data, sorted.
inline std::vector<std::string> shared_rgl_files() {
  std::vector<std::string> files;
  const fs::path dir = kSharedDir + "/data/rgl";
  if (fs::exists(dir))
    for (const auto& entry : fs::directory_iterator(dir))
      if (entry.path().extension() == ".bsdf") files.push_back(entry.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

// The stored double of channel c at (iθh, iθd, iφd) of a 90x90x180 file, read from its bytes
// with the layout written out here rather than the reader's index code.
inline double raw_bin(const std::string& bytes, int channel, int i_theta_h, int i_theta_d, int i_phi_d) {
  const size_t bin = (size_t(i_theta_h) * 90 + i_theta_d) * 180 + i_phi_d, kBins = 90 * 90 * 180;
  double value;
  std::memcpy(&value, bytes.data() + 12 + (channel * kBins + bin) * 8, 8);
  return value;
}

inline Rgb<double> raw_f(const std::string& bytes, int i_theta_h, int i_theta_d, int i_phi_d) {
  return {raw_bin(bytes, 0, i_theta_h, i_theta_d, i_phi_d) / 1500,
          raw_bin(bytes, 1, i_theta_h, i_theta_d, i_phi_d) * 1.15 / 1500,
          raw_bin(bytes, 2, i_theta_h, i_theta_d, i_phi_d) * 1.66 / 1500};
}

// The light/view pair with half/difference angles (degrees) θh, θd, φd and φh, built from the
// half-vector frame t = ∂h/∂θh, b = ẑ × h / sinθh, h (independent of rusinkiewicz.h):
// l = sinθd cosφd t + sinθd sinφd b + cosθd h, and v the mirror of l about h.
inline std::pair<Vec3, Vec3> pair_from_angles(double theta_h, double theta_d, double phi_d, double phi_h) {
  const double th = theta_h * kPi / 180, td = theta_d * kPi / 180, pd = phi_d * kPi / 180, ph = phi_h * kPi / 180;
  const Vec3 h(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
  const Vec3 t(std::cos(th) * std::cos(ph), std::cos(th) * std::sin(ph), -std::sin(th));
  const Vec3 b(-std::sin(ph), std::cos(ph), 0);
  const Vec3 l = std::sin(td) * std::cos(pd) * t + std::sin(td) * std::sin(pd) * b + std::cos(td) * h;
  return {l, 2 * l.dot(h) * h - l};
}

inline void write_bytes(const std::string& path, const std::string& bytes) {
  FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr) << path;
  ASSERT_EQ(std::fwrite(bytes.data(), 1, bytes.size(), f), bytes.size());
  std::fclose(f);
}

}  // namespace brdffit::test
