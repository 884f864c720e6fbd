#include "brdffit/batch_shard.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <numeric>

#include "brdffit/error.h"

namespace brdffit {

namespace {

// A whole non-negative number, or nullopt.
std::optional<long> whole_number(const std::string& text) {
  if (text.empty() || text.size() > 9 ||
      !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return std::nullopt;
  return std::stol(text);
}

long required_number(const EnvironmentLookup& environment, const std::string& name, long fallback, bool required) {
  const std::optional<std::string> value = environment(name);
  if (!value) {
    if (required)
      fail(
          "--shard auto: {} is not set (not a Slurm job array task; in a Kubernetes Indexed Job give auto/N, "
          "elsewhere K/N)",
          name);
    return fallback;
  }
  const std::optional<long> number = whole_number(*value);
  if (!number) fail("--shard auto: {}='{}' is not a whole number", name, *value);
  return *number;
}

// This task's index in a Slurm job array (arrays may start anywhere and step).
long slurm_index(const EnvironmentLookup& environment) {
  const long id = required_number(environment, "SLURM_ARRAY_TASK_ID", 0, true);
  const long min = required_number(environment, "SLURM_ARRAY_TASK_MIN", 0, false);
  const long step = std::max(1L, required_number(environment, "SLURM_ARRAY_TASK_STEP", 1, false));
  return (id - min) / step;
}

}  // namespace

std::optional<std::string> process_environment(const std::string& name) {
  const char* value = std::getenv(name.c_str());
  return value ? std::optional<std::string>(value) : std::nullopt;
}

Shard parse_shard(const std::string& text, const EnvironmentLookup& environment) {
  const size_t slash = text.find('/');
  const std::string first = text.substr(0, slash), second = slash == std::string::npos ? "" : text.substr(slash + 1);
  long index = 0, count = 0;
  if (first == "auto" && slash == std::string::npos) {
    index = slurm_index(environment);
    count = required_number(environment, "SLURM_ARRAY_TASK_COUNT", 0, true);
  } else {
    const std::optional<long> n = whole_number(second);
    if (slash == std::string::npos || !n || *n < 1)
      fail("--shard '{}': expected K/N (0 <= K < N), auto (Slurm job array) or auto/N (Kubernetes Indexed Job)", text);
    count = *n;
    if (first == "auto") {
      const std::optional<std::string> k8s = environment("JOB_COMPLETION_INDEX");
      index = k8s ? required_number(environment, "JOB_COMPLETION_INDEX", 0, true) : slurm_index(environment);
    } else {
      const std::optional<long> k = whole_number(first);
      if (!k) fail("--shard '{}': K must be a whole number (0 <= K < N)", text);
      index = *k;
    }
  }
  if (count > OutputFolderLock::kMaxShards)
    fail("--shard '{}': {} shards, more than the limit of {}", text, count, OutputFolderLock::kMaxShards);
  if (index < 0 || index >= count)
    fail("--shard '{}': shard {} does not exist among {} (0 <= K < N)", text, index, count);
  return {static_cast<int>(index), static_cast<int>(count)};
}

std::vector<BatchMaterial> shard_materials(const std::vector<BatchMaterial>& materials, const Shard& shard) {
  std::vector<uintmax_t> sizes(materials.size());
  for (size_t i = 0; i < materials.size(); ++i) {
    std::error_code error;  // a missing table weighs nothing; it fails when its shard reaches it
    const uintmax_t size = std::filesystem::file_size(materials[i].path, error);
    sizes[i] = error ? 0 : size;
  }
  std::vector<size_t> order(materials.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return sizes[a] > sizes[b]; });
  // Greedy to the least loaded, first of equals: with N shards for M < N materials, material k
  // (largest first) goes to shard k, and shards M and above stay empty; only min(N, M) are kept.
  std::vector<uintmax_t> load(std::min<size_t>(static_cast<size_t>(shard.count), materials.size()), 0);
  std::vector<bool> mine(materials.size(), false);
  for (size_t i : order) {
    const size_t lightest = std::min_element(load.begin(), load.end()) - load.begin();  // first of equals
    load[lightest] += sizes[i] + 1;  // +1: empty or missing files still count as a material
    mine[i] = static_cast<int>(lightest) == shard.index;
  }
  std::vector<BatchMaterial> share;
  for (size_t i = 0; i < materials.size(); ++i)
    if (mine[i]) share.push_back(materials[i]);
  return share;
}

}  // namespace brdffit
