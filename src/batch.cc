// Batch fitting (see batch.h).
#include "brdffit/batch.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/measured.h"
#include "brdffit/parallel.h"
#include "brdffit/result_json.h"

namespace brdffit {

namespace {

namespace fs = std::filesystem;

// A manifest is text; every table format but CSV (recognised by its extension) is binary, and a
// binary file has a NUL byte early on (MERL's first int32 is 90).
bool looks_like_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  char head[4096];
  in.read(head, sizeof head);
  return std::find(head, head + in.gcount(), '\0') == head + in.gcount();
}

fs::path absolute_normal(const fs::path& path) { return fs::weakly_canonical(fs::absolute(path)); }

bool is_inside(const fs::path& path, const fs::path& folder) {
  if (folder.empty()) return false;
  const auto [folder_end, path_end] = std::mismatch(folder.begin(), folder.end(), path.begin(), path.end());
  return folder_end == folder.end();
}

// Collects table paths in input order, each once.
class TableList {
 public:
  explicit TableList(const std::string& skip_dir) : skip_(skip_dir.empty() ? fs::path() : absolute_normal(skip_dir)) {}

  void add_input(const std::string& input) {
    std::error_code error;
    if (fs::is_directory(input, error)) return add_folder(input);
    if (!fs::exists(input, error)) fail("{}: no such file or folder", input);
    if (!has_table_extension(input) && looks_like_text(input)) return add_manifest(input);
    add_table(input);
  }

  std::vector<fs::path> take() { return std::move(tables_); }

 private:
  void add_table(const fs::path& path) {
    const fs::path absolute = absolute_normal(path);
    if (seen_.insert(absolute).second) tables_.push_back(absolute);
  }

  void add_folder(const fs::path& folder) {
    std::vector<fs::path> found;
    std::error_code error;
    for (auto it = fs::recursive_directory_iterator(folder, fs::directory_options::skip_permission_denied, error);
         !error && it != fs::recursive_directory_iterator(); it.increment(error)) {
      if (is_inside(absolute_normal(it->path()), skip_)) {
        if (it->is_directory()) it.disable_recursion_pending();
        continue;
      }
      if (it->is_regular_file() && has_table_extension(it->path())) found.push_back(it->path());
    }
    if (error) fail("{}: cannot list the folder: {}", folder.string(), error.message());
    if (found.empty() && is_inside(absolute_normal(folder), skip_))
      fail(
          "{}: this folder is inside the output folder {} (--out), whose files are the batch's own: put the "
          "results elsewhere with --out, or the tables in another folder",
          folder.string(), skip_.string());
    if (found.empty()) fail("{}: no tables (.binary, .bsdf, .csv) in this folder", folder.string());
    std::sort(found.begin(), found.end());
    for (const fs::path& table : found) add_table(table);
  }

  void add_manifest(const fs::path& manifest) {
    std::istringstream lines(read_file(manifest.string()));
    std::string line;
    size_t entries = 0;
    while (std::getline(lines, line)) {
      const size_t begin = line.find_first_not_of(" \t\r"), end = line.find_last_not_of(" \t\r");
      if (begin == std::string::npos || line[begin] == '#') continue;
      const fs::path entry = manifest.parent_path() / line.substr(begin, end - begin + 1);
      std::error_code error;
      if (fs::is_directory(entry, error))
        add_folder(entry);
      else
        add_table(entry);  // missing or unreadable: that material fails when its turn comes
      ++entries;
    }
    if (entries == 0) fail("{}: the manifest lists no tables", manifest.string());
  }

  fs::path skip_;
  std::set<fs::path> seen_;
  std::vector<fs::path> tables_;
};

// A file name safe on every system: letters, digits, '.', '-' and '_'.
std::string file_name_safe(const std::string& name) {
  std::string safe = name;
  for (char& c : safe)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
  return safe.empty() ? "material" : safe;
}

// The models that failed and why, "model: reason; ...".
std::string failed_models(const std::vector<FitResult>& fits) {
  std::string text;
  for (const FitResult& fit : fits)
    if (!fit.ok) text += (text.empty() ? "" : "; ") + fit.model + ": " + fit.error;
  return text;
}

// The existing result document of a material when it is complete and current: the same input
// bytes, the same fitting settings, and every requested model fitted ok.
std::optional<FitDocument> completed_document(const std::string& result_path, const BatchMaterial& material,
                                              const BatchOptions& options) {
  std::error_code error;
  if (!fs::exists(result_path, error)) return std::nullopt;
  FitDocument document;
  try {
    document = read_fit_document(result_path);
  } catch (const Error&) {
    return std::nullopt;  // unreadable (e.g. from an older version): fitted again and replaced
  }
  // The header a new fit would write, for the same input file and options.
  const nlohmann::json current = fit_document_json(material.path, SampleSet{}, options.fit, {});
  for (const char* key : {"input", "metric", "per_channel", "loss", "fixed"})
    if (document.json.value(key, nlohmann::json()) != current.value(key, nlohmann::json())) return std::nullopt;
  for (const Model* model : options.models) {
    const FitResult* fit = find_result(document.results, model->name());
    if (!fit || !fit->ok) return std::nullopt;
  }
  return document;
}

// Only the requested models, in the requested order (a resumed document may hold more).
std::vector<FitResult> requested_fits(const std::vector<FitResult>& fits, const std::vector<const Model*>& models) {
  std::vector<FitResult> selected;
  for (const Model* model : models)
    for (const FitResult& fit : fits)
      if (fit.model == model->name()) selected.push_back(fit);
  return selected;
}

MaterialOutcome process_material(const BatchMaterial& material, const BatchOptions& options, const FitOptions& fit) {
  const auto started = std::chrono::steady_clock::now();
  MaterialOutcome outcome;
  outcome.material = material;
  // Absolute, as the summary lists it: compare and report may run from another folder.
  const std::string result_path = absolute_path((fs::path(options.out_dir) / (material.name + ".json")).string());
  try {
    std::optional<FitDocument> done;
    if (options.resume || options.merge_only) done = completed_document(result_path, material, options);
    if (!done && options.merge_only)
      fail(
          "{}: no complete result document for these options (its shard did not finish it: run that shard, or the "
          "batch, again with --resume)",
          result_path);
    if (done) {
      outcome.status = MaterialStatus::Ok;
      outcome.resumed = true;
      outcome.fits = requested_fits(done->results, options.models);
      outcome.result_path = result_path;
    } else {
      // Read only now, and released when this material is done: memory holds `jobs` tables at most.
      const SampleSet data = load_samples(material.path, options.sampling);
      if (data.empty()) fail("{}: no samples left to fit (check --max-angle)", material.path);
      outcome.fits = fit_models(options.models, data, fit);
      nlohmann::json document = fit_document_json(material.path, data, fit, outcome.fits);
      put_name(document, "material", material.name);
      write_file_atomic(result_path, json_text(document, 2) + "\n");
      outcome.result_path = result_path;
      outcome.error = failed_models(outcome.fits);
      outcome.status = outcome.error.empty() ? MaterialStatus::Ok : MaterialStatus::Partial;
    }
  } catch (const std::exception& e) {  // Error, and e.g. bad_alloc: the batch goes on
    outcome.status = MaterialStatus::Failed;
    outcome.error = e.what();
    outcome.fits.clear();
    outcome.result_path.clear();
    // A document from an earlier run would read as this run's result (compare takes every *.json).
    std::error_code ignored;
    fs::remove(result_path, ignored);
  }
  outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return outcome;
}

// A model's error on a material under the metric; NaN when it did not fit.
double fitted_error(const MaterialOutcome& outcome, const std::string& model, Metric metric) {
  const FitResult* fit = find_result(outcome.fits, model);
  return fit && fit->ok ? fit->metrics.get(metric) : NAN;
}

}  // namespace

const char* material_status_name(MaterialStatus status) {
  switch (status) {
    case MaterialStatus::Ok: return "ok";
    case MaterialStatus::Partial: return "partial";
    case MaterialStatus::Failed: break;
  }
  return "failed";
}

std::vector<BatchMaterial> batch_materials(const std::vector<std::string>& inputs, const std::string& skip_dir) {
  TableList list(skip_dir);
  for (const std::string& input : inputs) list.add_input(input);
  std::vector<BatchMaterial> materials;
  std::set<std::string> taken = {"summary"};  // summary.json is the batch's own
  for (const fs::path& table : list.take()) {
    const std::string base = file_name_safe(table_material_name(table.string()));
    std::string name = base;
    for (int n = 2; taken.count(name); ++n) name = base + "-" + std::to_string(n);
    taken.insert(name);
    materials.push_back({name, table.string()});
  }
  return materials;
}

namespace {

// The pid a lock file names, or 0 when it names none.
long lock_owner(const std::string& path) {
  try {
    return std::stol(read_file(path, 64));
  } catch (const std::exception&) {
    return 0;
  }
}

bool process_alive(long pid) { return pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM); }

// The lock file's bytes, each a lock of its own (open-file-description locks: released when the
// process ends, however it ends, so a killed batch leaves nothing to clean up):
//   byte 0              the folder: a whole-folder run locks it for writing, every shard for reading;
//   byte 1 + N          shards of N lock it for reading; a shard refuses to start while any other
//                       of these bytes is locked (shards of another N are running);
//   byte 2 + kMax + K   shard K locks it for writing: the same shard never runs twice at once.
constexpr off_t kFolderByte = 0;
off_t shard_count_byte(int count) { return 1 + count; }
off_t shard_byte(int index) { return 2 + OutputFolderLock::kMaxShards + index; }

// Takes (without waiting) a read or write lock on `length` bytes from `start`; false when
// another holder's lock is in the way.
bool lock_bytes(int fd, short type, off_t start, off_t length) {
  struct flock lock {};
  lock.l_type = type;
  lock.l_whence = SEEK_SET;
  lock.l_start = start;
  lock.l_len = length;
  if (::fcntl(fd, F_OFD_SETLK, &lock) == 0) return true;
  if (errno == EAGAIN || errno == EACCES) return false;
  fail("cannot lock the batch's lock file: {}", std::strerror(errno));
}

// Whether another holder has any lock on `length` bytes from `start`.
bool bytes_locked(int fd, off_t start, off_t length) {
  if (length <= 0) return false;
  struct flock lock {};
  lock.l_type = F_WRLCK;
  lock.l_whence = SEEK_SET;
  lock.l_start = start;
  lock.l_len = length;
  if (::fcntl(fd, F_OFD_GETLK, &lock) != 0) fail("cannot test the batch's lock file: {}", std::strerror(errno));
  return lock.l_type != F_UNLCK;
}

}  // namespace

OutputFolderLock::OutputFolderLock(const std::string& folder) : OutputFolderLock(folder, -1, 0) {}

OutputFolderLock::OutputFolderLock(const std::string& folder, int shard_index, int shard_count) {
  const bool shard = shard_count > 0;
  if (shard && (shard_count > kMaxShards || shard_index < 0 || shard_index >= shard_count))
    fail("shard {}/{}: not a shard of at most {} (0 <= K < N)", shard_index, shard_count, kMaxShards);
  std::error_code error;
  fs::create_directories(folder, error);
  if (error || !fs::is_directory(folder))
    fail("{}: cannot create the output folder{}", folder, error ? ": " + error.message() : "");
  path_ = (fs::path(folder) / kLockName).string();
  const auto refuse = [&](const std::string& who) {
    fail("{}: {} is writing into this folder; wait for it to finish, or choose another --out", folder, who);
  };
  // A holder that is releasing may unlink the file between our open and our lock: the lock is
  // only ours when the name still leads to the file we locked.
  for (int attempt = 0; attempt < 8; ++attempt) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd_ < 0) fail("{}: cannot create the lock file: {}", path_, std::strerror(errno));
    std::string busy;
    if (!shard) {
      if (!lock_bytes(fd_, F_WRLCK, kFolderByte, 1)) {
        const long owner = lock_owner(path_);
        busy = process_alive(owner) ? fmt::format("another batch (pid {})", owner) : "another batch (shards)";
      }
    } else if (!lock_bytes(fd_, F_RDLCK, kFolderByte, 1)) {
      busy = fmt::format("another batch (pid {})", lock_owner(path_));
    } else if (!lock_bytes(fd_, F_RDLCK, shard_count_byte(shard_count), 1) ||
               bytes_locked(fd_, shard_count_byte(1), shard_count - 1) ||
               bytes_locked(fd_, shard_count_byte(shard_count + 1), kMaxShards - shard_count)) {
      busy = fmt::format("a batch in shards of another number than {}", shard_count);
    } else if (!lock_bytes(fd_, F_WRLCK, shard_byte(shard_index), 1)) {
      busy = fmt::format("another batch (shard {}/{})", shard_index, shard_count);
    }
    if (!busy.empty()) {
      ::close(fd_);
      fd_ = -1;
      refuse(busy);
    }
    struct stat held, named;
    if (::fstat(fd_, &held) == 0 && ::lstat(path_.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
        held.st_ino == named.st_ino) {
      if (!shard) {  // who holds the folder, for the message another batch gets
        const std::string pid = std::to_string(::getpid()) + "\n";
        if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size()))
          fail("{}: cannot write the lock file: {}", path_, std::strerror(errno));
      }
      return;
    }
    ::close(fd_);
    fd_ = -1;
  }
  fail("{}: cannot take the lock file {}", folder, path_);
}

OutputFolderLock::~OutputFolderLock() {
  // The last holder removes the file: when no other process holds any of its bytes.
  if (fd_ < 0) return;
  if (lock_bytes(fd_, F_WRLCK, 0, 0)) {
    struct stat held, named;
    if (::fstat(fd_, &held) == 0 && ::lstat(path_.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
        held.st_ino == named.st_ino)
      ::unlink(path_.c_str());
  }
  ::close(fd_);
}

void check_batch_keeps_models(const std::vector<BatchMaterial>& materials, const BatchOptions& options) {
  if (options.merge_only) return;  // writes no result document
  std::vector<std::string> fitted;
  for (const Model* model : options.models) fitted.push_back(model->name());
  std::vector<std::string> wanted = fitted;  // these and every model the documents hold, in order
  std::vector<std::string> losing;           // "red.json (ward, lambert)"
  for (const BatchMaterial& material : materials) {
    const std::string path = (fs::path(options.out_dir) / (material.name + ".json")).string();
    std::error_code error;
    if (!fs::exists(path, error)) continue;
    if (options.resume && completed_document(path, material, options)) continue;  // kept as it is
    FitDocument document;
    try {
      document = read_fit_document(path);
    } catch (const Error&) {
      continue;  // unreadable (e.g. from an older version): replaced, as documented
    }
    std::string dropped;
    for (const FitResult& fit : document.results) {
      if (std::find(fitted.begin(), fitted.end(), fit.model) != fitted.end()) continue;
      dropped += (dropped.empty() ? "" : ", ") + fit.model;
      if (std::find(wanted.begin(), wanted.end(), fit.model) == wanted.end()) wanted.push_back(fit.model);
    }
    if (!dropped.empty()) losing.push_back(fs::path(path).filename().string() + " (" + dropped + ")");
  }
  if (losing.empty()) return;
  std::string listed, all;
  for (size_t i = 0; i < std::min<size_t>(losing.size(), 3); ++i) listed += (i ? ", " : "") + losing[i];
  if (losing.size() > 3) listed += fmt::format(" and {} more", losing.size() - 3);
  for (const std::string& name : wanted) all += (all.empty() ? "" : ",") + name;
  fail_usage(
      "{}: {} hold fits of models this batch does not fit, and refitting would replace them with fewer: {}. "
      "Fit those models too (-m {}), or write into another folder (--out)",
      options.out_dir, count_of(losing.size(), "result document"), listed, all);
}

std::vector<MaterialOutcome> run_batch(const std::vector<BatchMaterial>& materials, const BatchOptions& options,
                                       const BatchEvents& events) {
  std::error_code error;
  fs::create_directories(options.out_dir, error);
  if (error || !fs::is_directory(options.out_dir))
    fail("{}: cannot create the output folder{}", options.out_dir, error ? ": " + error.message() : "");

  if ((options.resume || options.merge_only) && !options.shared_folder) remove_stale_temp_files(options.out_dir);

  const BatchPlan plan = plan_batch(options, materials.size());
  const int jobs = plan.jobs;
  FitOptions fit = options.fit;
  fit.threads = plan.threads;

  std::vector<MaterialOutcome> outcomes(materials.size());
  std::atomic<size_t> next{0};
  std::mutex events_mutex;
  // Materials are taken in order as workers free up: tables differ in size, so a fixed split
  // would leave workers idle.
  const auto worker = [&] {
    for (size_t i = next++; i < materials.size(); i = next++) {
      if (events.started) {
        const std::lock_guard<std::mutex> lock(events_mutex);
        events.started(materials[i]);
      }
      outcomes[i] = process_material(materials[i], options, fit);
      if (events.finished) {
        const std::lock_guard<std::mutex> lock(events_mutex);
        events.finished(outcomes[i]);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int j = 1; j < jobs; ++j) pool.emplace_back(worker);
  worker();
  for (std::thread& thread : pool) thread.join();
  return outcomes;
}

BatchPlan plan_batch(const BatchOptions& options, size_t materials) {
  BatchPlan plan;
  plan.jobs = static_cast<int>(
      std::clamp<size_t>(static_cast<size_t>(std::max(1, options.jobs)), 1, std::max<size_t>(materials, 1)));
  // The fitter is parallel itself: the cores are shared among the materials fitted at once.
  plan.threads = options.fit.threads > 0 ? options.fit.threads : std::max(1, thread_count(0) / plan.jobs);
  return plan;
}

OutcomeCounts count_outcomes(const std::vector<MaterialOutcome>& outcomes) {
  OutcomeCounts counts;
  for (const MaterialOutcome& o : outcomes) {
    counts.ok += o.status == MaterialStatus::Ok;
    counts.partial += o.status == MaterialStatus::Partial;
    counts.failed += o.status == MaterialStatus::Failed;
    counts.resumed += o.resumed;
  }
  return counts;
}

nlohmann::json batch_summary_json(const std::vector<MaterialOutcome>& outcomes, const BatchOptions& options,
                                  double seconds) {
  const Metric metric = options.fit.metric;
  nlohmann::json models = nlohmann::json::array();
  for (const Model* model : options.models) models.push_back(model->name());
  nlohmann::json materials = nlohmann::json::array();
  for (const MaterialOutcome& o : outcomes) {
    nlohmann::json errors = nlohmann::json::object();
    for (const Model* model : options.models)
      errors[model->name()] = number_or_null(fitted_error(o, model->name(), metric));
    const FitResult* best = best_result(o.fits, metric);
    nlohmann::json material = {{"status", material_status_name(o.status)},
                               {"resumed", o.resumed},
                               {"error", o.error.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.error)},
                               {"seconds", o.seconds},
                               {"best_model", best ? nlohmann::json(best->model) : nlohmann::json(nullptr)},
                               {"errors", errors}};
    put_name(material, "material", o.material.name);
    put_name(material, "input", o.material.path);
    if (o.result_path.empty())
      material["result"] = nullptr;
    else
      put_name(material, "result", o.result_path);
    materials.push_back(std::move(material));
  }
  const OutcomeCounts counts = count_outcomes(outcomes);
  return {{"schema", 1},
          {"tool", "brdffit " BRDFFIT_VERSION},
          {"metric", metric_name(metric)},
          {"models", models},
          {"materials", materials},
          {"counts",
           {{"ok", counts.ok}, {"partial", counts.partial}, {"failed", counts.failed}, {"resumed", counts.resumed}}},
          {"seconds", seconds}};
}

std::string batch_summary_csv(const std::vector<MaterialOutcome>& outcomes, const BatchOptions& options) {
  const Metric metric = options.fit.metric;
  std::string csv = "material,input,status,resumed,error,best_model,best_error,seconds";
  for (const Model* model : options.models) csv += "," + csv_field(model->name());
  csv += "\n";
  for (const MaterialOutcome& o : outcomes) {
    const FitResult* best = best_result(o.fits, metric);
    csv += fmt::format("{},{},{},{},{},{},{},{:.3f}", csv_field(o.material.name), csv_field(o.material.path),
                       material_status_name(o.status), o.resumed ? "yes" : "no", csv_field(o.error),
                       best ? csv_field(best->model) : "", best ? fmt::format("{:.9g}", best->metrics.get(metric)) : "",
                       o.seconds);
    for (const Model* model : options.models) {
      const double e = fitted_error(o, model->name(), metric);
      csv += std::isfinite(e) ? fmt::format(",{:.9g}", e) : ",";
    }
    csv += "\n";
  }
  return csv;
}

}  // namespace brdffit
