// A batch over the ranks of an MPI job (batch_mpi.h).
#include "brdffit/batch_mpi.h"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numeric>
#include <string>
#include <thread>

#include "brdffit/error.h"
#include "brdffit/parallel.h"
#include "brdffit/result_json.h"

namespace brdffit {

namespace {

namespace fs = std::filesystem;

constexpr int kTag = 17;
constexpr int kNoMoreWork = -1;

// A worker's report of one material (JSON text), and its request for the next: the first
// request carries no report.
std::string report_of(int index, const MaterialOutcome& o) {
  nlohmann::json report = {{"index", index},
                           {"status", material_status_name(o.status)},
                           {"resumed", o.resumed},
                           {"error", o.error},
                           {"seconds", o.seconds}};
  put_name(report, "result_path", o.result_path);  // read back by rank 0: byte for byte
  return json_text(report);
}

// The outcome rank 0 keeps for a report: the models' results read back from the document the
// worker wrote (the progress line and the summary need them).
MaterialOutcome outcome_of(const nlohmann::json& report, const BatchMaterial& material, const BatchOptions& options) {
  MaterialOutcome o;
  o.material = material;
  const std::string status = report.at("status").get<std::string>();
  o.status = status == "ok"        ? MaterialStatus::Ok
             : status == "partial" ? MaterialStatus::Partial
                                   : MaterialStatus::Failed;
  o.resumed = report.at("resumed").get<bool>();
  o.error = report.at("error").get<std::string>();
  o.result_path = get_name(report, "result_path", "MPI report").value_or("");
  o.seconds = report.at("seconds").get<double>();
  if (o.status == MaterialStatus::Failed) return o;
  try {
    const FitDocument document = read_fit_document(o.result_path);
    for (const Model* model : options.models)
      if (const FitResult* fit = find_result(document.results, model->name())) o.fits.push_back(*fit);
  } catch (const Error& e) {
    o.status = MaterialStatus::Failed;
    o.error = e.what();
  }
  return o;
}

// Materials in the order they are handed out: largest input first, so that the long ones do not
// start last and leave the other ranks idle at the end.
std::vector<int> largest_first(const std::vector<BatchMaterial>& materials) {
  std::vector<uintmax_t> size(materials.size(), 0);
  for (size_t i = 0; i < materials.size(); ++i) {
    std::error_code error;
    const uintmax_t bytes = fs::file_size(materials[i].path, error);
    size[i] = error ? 0 : bytes;
  }
  std::vector<int> order(materials.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return size[a] > size[b]; });
  return order;
}

void check(int mpi_result, const char* what) {
  if (mpi_result != MPI_SUCCESS) fail("MPI: {} failed (error {})", what, mpi_result);
}

}  // namespace

MpiBatch::MpiBatch() {
  int provided = 0;
  check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  // Errors come back as codes (and become Error here) instead of aborting inside MPI.
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiBatch::~MpiBatch() { MPI_Finalize(); }

std::vector<MaterialOutcome> MpiBatch::run(const std::vector<BatchMaterial>& materials, const BatchOptions& options,
                                           const BatchEvents& events) {
  if (size_ < 2) return run_batch(materials, options, events);
  if (rank_ == 0) {
    // Before anything is written: what a killed run left behind (run_batch does this itself
    // when it runs in one process).
    if (options.resume) {
      BatchOptions clean = options;
      run_batch({}, clean);
    }
    std::vector<MaterialOutcome> outcomes(materials.size());
    const std::vector<int> order = largest_first(materials);
    size_t next = 0;
    for (int working = size_ - 1; working > 0;) {
      // Polled rather than a blocking receive: OpenMPI's blocking receive spins a core, and
      // this rank only waits.
      MPI_Status status;
      for (int arrived = 0; !arrived;) {
        check(MPI_Iprobe(MPI_ANY_SOURCE, kTag, MPI_COMM_WORLD, &arrived, &status), "MPI_Iprobe");
        if (!arrived) std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
      int length = 0;
      MPI_Get_count(&status, MPI_CHAR, &length);
      std::string message(static_cast<size_t>(length), '\0');
      check(MPI_Recv(message.data(), length, MPI_CHAR, status.MPI_SOURCE, kTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
            "MPI_Recv");
      if (!message.empty()) {
        const nlohmann::json report = nlohmann::json::parse(message);
        const int index = report.at("index").get<int>();
        outcomes[index] = outcome_of(report, materials[index], options);
        if (events.finished) events.finished(outcomes[index]);
      }
      const int assigned = next < order.size() ? order[next++] : kNoMoreWork;
      if (assigned == kNoMoreWork)
        --working;
      else if (events.started)
        events.started(materials[assigned]);
      check(MPI_Send(&assigned, 1, MPI_INT, status.MPI_SOURCE, kTag, MPI_COMM_WORLD), "MPI_Send");
    }
    return outcomes;
  }

  BatchOptions one = options;
  one.jobs = 1;
  one.shared_folder = true;  // rank 0 holds the lock and cleans up; the ranks write side by side
  if (one.fit.threads <= 0) {
    // The node's cores among the ranks that fit on it (rank 0 only waits: counted out, as if
    // it shared the node; OMPI_COMM_WORLD_LOCAL_SIZE counts the ranks on this node).
    const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
    const int ranks_here = std::max(1, (local ? std::atoi(local) : size_) - 1);
    // A rank bound to fewer cores (mpirun binds to a core by default up to two ranks) has only those.
    one.fit.threads =
        std::min(available_cores(), std::max(1, static_cast<int>(std::thread::hardware_concurrency()) / ranks_here));
  }
  std::string report;
  for (;;) {
    check(MPI_Send(report.data(), static_cast<int>(report.size()), MPI_CHAR, 0, kTag, MPI_COMM_WORLD), "MPI_Send");
    int index = kNoMoreWork;
    check(MPI_Recv(&index, 1, MPI_INT, 0, kTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "MPI_Recv");
    if (index == kNoMoreWork) return {};
    const MaterialOutcome outcome = run_batch({materials.at(static_cast<size_t>(index))}, one).at(0);
    report = report_of(index, outcome);
  }
}

}  // namespace brdffit
