// Helpers shared by the tests: random directions and parameters, running the CLI.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "brdffit/error.h"
#include "brdffit/model.h"
#include "brdffit/registry.h"
#include "brdffit/samples.h"

namespace brdffit::test {

// A file's bytes whole ("" when it cannot be read).
inline std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// The message of the Error `f` throws, or "" when it throws none.
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// Expects `action` to throw brdffit::Error (nothing else) whose message contains every
// fragment; returns the message.
template <class Action>
std::string expect_error(Action&& action, const std::vector<std::string>& fragments) {
  try {
    action();
  } catch (const Error& e) {
    const std::string message = e.what();
    for (const std::string& f : fragments)
      EXPECT_NE(message.find(f), std::string::npos) << "'" << f << "' not in: " << message;
    return message;
  }
  ADD_FAILURE() << "expected an error mentioning '" << fragments.front() << "'";
  return "";
}

// This test program's scratch folder, removed when the program ends.
inline std::filesystem::path scratch_root() {
  return std::filesystem::temp_directory_path() / ("brdffit-tests-" + std::to_string(::getpid()));
}

class ScratchCleanup : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ignored;
    std::filesystem::remove_all(scratch_root(), ignored);
  }
};
inline ::testing::Environment* const kScratchCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

// An empty folder for one test, inside the scratch folder.
inline std::string fresh_dir(const std::string& name) {
  const std::filesystem::path dir = scratch_root() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

// A uniformly random direction in the upper hemisphere, kept away from grazing (z >= min_z).
inline Vec3 random_upper_direction(std::mt19937_64& rng, double min_z = 0.05) {
  std::normal_distribution<double> normal;
  for (;;) {
    Vec3 d(normal(rng), normal(rng), std::abs(normal(rng)));
    const double len = d.norm();
    if (len < 1e-9) continue;
    d /= len;
    if (d.z() >= min_z) return d;
  }
}

// Random values strictly inside every parameter's bounds (integers: a random integer).
inline std::vector<double> random_values(const Model& model, std::mt19937_64& rng, double margin = 0.05) {
  std::vector<double> values;
  std::uniform_real_distribution<double> unit(margin, 1.0 - margin);
  for (const ParamSpec& p : model.parameters())
    for (int c = 0; c < p.channels; ++c) {
      double x = p.lower + unit(rng) * (p.upper - p.lower);
      if (p.integer) x = std::round(x);
      values.push_back(x);
    }
  return values;
}

// Random values over every parameter's whole range, bounds included: each value is its lower or
// upper bound one time in eight each, else uniform (log-uniform for Spacing::Log, so that the
// narrow lobes near a width's lower bound are drawn as often as the wide ones).
inline std::vector<double> random_values_with_bounds(const Model& model, std::mt19937_64& rng) {
  std::vector<double> values;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const ParamSpec& p : model.parameters())
    for (int c = 0; c < p.channels; ++c) {
      const double u = unit(rng), w = unit(rng);
      double x =
          p.spacing == Spacing::Log ? p.lower * std::pow(p.upper / p.lower, w) : p.lower + w * (p.upper - p.lower);
      if (u < 0.125) x = p.lower;
      if (u > 0.875) x = p.upper;
      if (p.integer) x = std::round(x);
      values.push_back(x);
    }
  return values;
}

// A random direction above the surface at most max_theta_degrees from the normal (89.9: grazing).
inline Vec3 random_direction_up_to(std::mt19937_64& rng, double max_theta_degrees) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double cos_max = std::cos(max_theta_degrees * kPi / 180);
  const double z = cos_max + (1.0 - cos_max) * unit(rng), phi = 2 * kPi * unit(rng);
  const double s = std::sqrt(1.0 - z * z);
  return Vec3(s * std::cos(phi), s * std::sin(phi), z);
}

// A model or material name as a GoogleTest parameter name (letters, digits and '_' only).
inline std::string gtest_name(std::string name) {
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

// Whether this is a CI run (CI set to anything but empty, as CI services set it: true, 1, yes):
// there ../shared and every tool scripts/install-deps.sh installs are present, so a test that
// needs them fails instead of skipping (a missing mount must not pass as green).
inline bool running_in_ci() {
  const char* ci = std::getenv("CI");
  return ci && *ci;
}

// Skips the test when data beside the project (../shared) is absent, saying what is missing;
// fails under CI. `what` may be a stream expression: "the MERL proxies (" << dir << ")".
#define SKIP_UNLESS_SHARED(present, what)                                                        \
  do {                                                                                           \
    if (!(present)) {                                                                            \
      if (::brdffit::test::running_in_ci()) FAIL() << what << " absent, and CI needs ../shared"; \
      GTEST_SKIP() << what << " absent (the shared data beside the project is not mounted)";     \
    }                                                                                            \
  } while (0)

// Samples of `model` at `values` over random direction pairs with both z >= min_z, each value
// with multiplicative Gaussian noise of relative size `noise`; uniform weights.
inline SampleSet model_table(const Model& model, const std::vector<double>& values, size_t count, double noise,
                             uint64_t seed, double min_z) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss;
  SampleSet set;
  set.source = "synthetic " + model.name();
  set.weighting = "uniform";
  while (set.samples.size() < count) {
    Sample s;
    s.l = random_upper_direction(rng, min_z);
    s.v = random_upper_direction(rng, min_z);
    s.value = model.shade(values.data(), s.l, s.v);
    for (int c = 0; c < 3; ++c) s.value[c] *= 1.0 + noise * gauss(rng);
    set.samples.push_back(s);
  }
  return set;
}

// Whether any of `lines` (a fit's warnings, a command's output) contains `text`.
inline bool mentions(const std::vector<std::string>& lines, const std::string& text) {
  return std::any_of(lines.begin(), lines.end(),
                     [&](const std::string& l) { return l.find(text) != std::string::npos; });
}

// The fitter tests' tables: random direction pairs down to z = 0.02.
inline SampleSet synthetic(const Model& model, const std::vector<double>& values, size_t count, double noise,
                           uint64_t seed) {
  return model_table(model, values, count, noise, seed, 0.02);
}

inline Vec3 dir(double x, double y, double z) { return Vec3(x, y, z).normalized(); }

// The published fits bundled in data/ (BBM's .fit files).
inline const std::string kPublishedFits = std::string(BRDFFIT_SOURCE_DIR) + "/data/published-fits";

inline const Vec3 kNormal(0, 0, 1);
inline const double kCos30 = std::sqrt(3.0) / 2;

// A registered model's shaded value for the "NAME=VALUE" assignments (parameter_values).
inline Rgb<double> shade(const std::string& model_name, const std::vector<std::string>& assignments, const Vec3& l,
                         const Vec3& v) {
  const Model* model = find_model(model_name);
  EXPECT_NE(model, nullptr) << model_name;
  if (!model) return Rgb<double>::Zero();
  const std::vector<double> values = parameter_values(*model, assignments);
  return model->shade(values.data(), l, v);
}

// The same for one channel, when the assignments make all channels equal (checked).
inline double shade1(const std::string& model_name, const std::vector<std::string>& assignments, const Vec3& l,
                     const Vec3& v) {
  const Rgb<double> s = shade(model_name, assignments, l, v);
  EXPECT_NEAR(s[0], s[1], 1e-15);
  EXPECT_NEAR(s[1], s[2], 1e-15);
  return s[0];
}

// Each channel within `relative` of the expected value's magnitude.
inline void expect_rgb_near(const Rgb<double>& actual, const Rgb<double>& expected, double relative = 1e-12) {
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(actual[c], expected[c], relative * std::max(1e-300, std::abs(expected[c]))) << "channel " << c;
}

struct CommandResult {
  int exit_code;
  std::string output;  // stdout and stderr together
};

// The rows of a CSV text without quoted fields, each split at its commas.
inline std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  size_t start = 0;
  while (start < text.size()) {
    const size_t end = std::min(text.find('\n', start), text.size());
    std::vector<std::string> row;
    for (size_t field = start;;) {
      const size_t comma = text.find(',', field);
      if (comma == std::string::npos || comma > end) {
        row.push_back(text.substr(field, end - field));
        break;
      }
      row.push_back(text.substr(field, comma - field));
      field = comma + 1;
    }
    rows.push_back(std::move(row));
    start = end + 1;
  }
  return rows;
}

// Runs a shell command and captures what it prints.
inline CommandResult run_command(const std::string& command) {
  CommandResult result{-1, ""};
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

inline CommandResult run_cli(const std::string& arguments) {
  return run_command(std::string(BRDFFIT_CLI) + " " + arguments);
}

// Whether a command is on the PATH.
inline bool have_tool(const std::string& name) { return run_command("command -v " + name).exit_code == 0; }

// Debian's Chromium (scripts/install-deps.sh with BRDFFIT_WITH_CHROMIUM=1), "" when absent.
inline std::string find_chromium() {
  for (const char* name : {"chromium", "chromium-browser"}) {
    const CommandResult r = run_command(std::string("command -v ") + name);
    if (r.exit_code == 0 && !r.output.empty()) return r.output.substr(0, r.output.find('\n'));
  }
  return "";
}

// The npm packages scripts/install-deps.sh installs (NODE_PATH for node).
inline std::string npm_modules() { return std::string(BRDFFIT_SOURCE_DIR) + "/.deps/npm/node_modules"; }

// Skips (outside CI) or fails (CI) when an ecosystem's checking tool is missing.
#define REQUIRE_TOOL(available, what)                                                                              \
  do {                                                                                                             \
    if (!(available)) {                                                                                            \
      if (::brdffit::test::running_in_ci()) FAIL() << what << " is missing (scripts/install-deps.sh installs it)"; \
      GTEST_SKIP() << what << " is not installed (scripts/install-deps.sh installs it)";                           \
    }                                                                                                              \
  } while (0)

// A command line and a part of the error message it must print.
struct CliErrorCase {
  std::string args, message;
  int exit_code = 0;  // the documented code (1: a file or the fit, 2: the command line); 0: either
};

// Runs each command line, expecting a documented error exit (1 or 2, or the case's own: never a
// signal such as an abort after the message, never 70, an internal error), the message in what
// it printed, and no file at `must_not_exist` (an output that must not be written, even in part).
inline void expect_cli_errors(const std::vector<CliErrorCase>& cases, const std::string& must_not_exist) {
  for (const CliErrorCase& c : cases) {
    SCOPED_TRACE(c.args);
    const CommandResult r = run_cli(c.args);
    if (c.exit_code != 0)
      EXPECT_EQ(r.exit_code, c.exit_code) << r.output;
    else
      EXPECT_TRUE(r.exit_code == 1 || r.exit_code == 2) << "exit code " << r.exit_code << "\n" << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(must_not_exist));
  }
}

}  // namespace brdffit::test
