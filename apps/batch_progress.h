// The progress of `brdffit batch` on stderr (BatchProgress, with the models' warnings once per
// kind: RepeatedWarnings) and the Ticker that redraws it every second.
#pragma once

#include <fmt/format.h>

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <functional>
#include <map>
#include <mutex>
#include <regex>
#include <set>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "brdffit/batch.h"
#include "brdffit/metric.h"
#include "brdffit/result_json.h"
#include "cli_common.h"

namespace brdffit::cli {

// The models' warnings of a batch: the first of each kind, and how many more like it. Two
// warnings are alike when they differ only in their numbers (the material's values): a batch of
// 300 materials where roughness sits at its bound prints that once, "(and 299 more like it)".
class RepeatedWarnings {
 public:
  void add(const std::string& material, const std::string& model, const std::string& warning) {
    static const std::regex number(R"([-+]?[0-9]*\.?[0-9]+([eE][-+]?[0-9]+)?)");
    const std::string kind = model + ": " + std::regex_replace(warning, number, "#");
    const auto [seen, first] = repeats_.try_emplace(kind, 0);
    if (first)
      order_.push_back({kind, fmt::format("    {} {}: warning: {}", material, model, warning)});
    else
      ++seen->second;
  }
  // Each kind once, with its count; then forgets them.
  void print() {
    for (const auto& [kind, line] : order_)
      say(stderr, "{}{}\n", line, repeats_[kind] > 0 ? fmt::format(" (and {} more like it)", repeats_[kind]) : "");
    order_.clear();
    repeats_.clear();
  }

 private:
  std::vector<std::pair<std::string, std::string>> order_;  // kind, its first line
  std::map<std::string, size_t> repeats_;                   // kind, how many more
};

// Progress of a batch on stderr: a line per finished material, and on a terminal a bar below
// them with counts, elapsed time and ETA, redrawn every second; the models' warnings once per
// kind at the end (RepeatedWarnings). With -q only the failures and the warnings; with -v
// every warning where it arises.
class BatchProgress {
 public:
  using Clock = std::chrono::steady_clock;

  BatchProgress(size_t total, Metric metric, bool terminal)
      : total_(total), metric_(metric), terminal_(terminal && verbosity() != Verbosity::Quiet), start_(Clock::now()) {}

  void started(const BatchMaterial& material) {
    const std::lock_guard<std::mutex> lock(mutex_);
    running_.insert(material.name);
    draw_bar();
  }

  void finished(const MaterialOutcome& o) {
    const std::lock_guard<std::mutex> lock(mutex_);
    running_.erase(o.material.name);
    ++done_;
    if (o.resumed) ++resumed_;
    if (o.status != MaterialStatus::Ok) ++failed_;
    if (!o.resumed) fitting_seconds_ = elapsed();
    std::string line = fmt::format("[{}/{}] {}: ", done_, total_, o.material.name);
    if (o.status == MaterialStatus::Failed) {
      line += "FAILED: " + o.error;
    } else {
      line += o.resumed ? "already done" : fmt::format("{} in {:.1f} s", material_status_name(o.status), o.seconds);
      const int poor = count_poor(o.fits);
      if (const FitResult* best = best_result(o.fits, metric_))
        line += fmt::format(", best {} ({} {:.4g})", best->model, metric_name(metric_), best->metrics.get(metric_));
      else if (!o.fits.empty())
        line += ", no usable fit";
      if (poor > 0) line += fmt::format(" ({} poor)", poor);
      if (o.status == MaterialStatus::Partial) line += "; failed: " + o.error;
    }
    if (!terminal_ && fitted() > 0 && done_ < total_) line += ", ETA " + duration_text(eta());
    // A poor fit and a parameter on a bound or not identifiable: a warning line each, with -v
    // here, else once per kind at the end.
    for (const FitResult& fit : o.fits)
      for (const std::string& warning : fit.warnings)
        if (verbosity() == Verbosity::Verbose)
          line += fmt::format("\n    {} {}: warning: {}", o.material.name, fit.model, warning);
        else
          warnings_.add(o.material.name, fit.model, warning);
    clear_bar();
    if (verbosity() != Verbosity::Quiet || o.status != MaterialStatus::Ok) say(stderr, "{}\n", line);
    draw_bar();
  }

  void redraw() {
    const std::lock_guard<std::mutex> lock(mutex_);
    draw_bar();
  }

  void close() {
    const std::lock_guard<std::mutex> lock(mutex_);
    clear_bar();
    warnings_.print();
  }

 private:
  double elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  size_t fitted() const { return done_ - resumed_; }
  // Materials still to do at the rate fitted ones went so far (resumed ones take no time).
  double eta() const { return fitting_seconds_ / fitted() * (total_ - done_); }

  void clear_bar() {
    if (terminal_) rewind_line();
  }

  void draw_bar() {
    if (!terminal_) return;
    constexpr int kWidth = 30;
    const int filled = total_ ? static_cast<int>(kWidth * done_ / total_) : kWidth;
    std::string running;
    for (const std::string& name : running_) running += (running.empty() ? "" : ", ") + name;
    if (running.size() > 40) running = running.substr(0, 37) + "...";
    rewind_line();
    say(stderr, "[{}{}] {}/{}  failed {}  {}{}  {}", std::string(filled, '#'), std::string(kWidth - filled, '-'), done_,
        total_, failed_, duration_text(elapsed()),
        fitted() > 0 && done_ < total_ ? ", ETA " + duration_text(eta()) : std::string(), running);
    std::fflush(stderr);
  }

  std::mutex mutex_;
  const size_t total_;
  const Metric metric_;
  const bool terminal_;
  const Clock::time_point start_;
  size_t done_ = 0, resumed_ = 0, failed_ = 0;
  double fitting_seconds_ = 0.0;  // elapsed when the last fitted (not resumed) material finished
  std::set<std::string> running_;
  RepeatedWarnings warnings_;
};

// Calls tick() every second on its own thread until destroyed.
class Ticker {
 public:
  explicit Ticker(std::function<void()> tick)
      : thread_([this, tick] {
          std::unique_lock<std::mutex> lock(mutex_);
          while (!stop_.wait_for(lock, std::chrono::seconds(1), [this] { return stopping_; })) tick();
        }) {}
  ~Ticker() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    stop_.notify_one();
    thread_.join();
  }

 private:
  std::mutex mutex_;
  std::condition_variable stop_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace brdffit::cli
