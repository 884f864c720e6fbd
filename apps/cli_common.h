// What every command spells and shows the same way: how models are named (-m/--models), old
// spellings that still work, durations, and the progress line of fit and sphere.
#pragma once

#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "brdffit/error.h"
#include "brdffit/fit.h"

namespace brdffit::cli {

// Everything the commands print goes through say(): the text, whatever built it, escaped by
// printable() (error.h), so that control characters in a file's contents or name (import
// warnings, the compare table, progress, echoed names) never reach the terminal as such.
template <class... Args>
void say(std::FILE* out, fmt::format_string<Args...> format, Args&&... args) {
  fmt::print(out, "{}", printable(fmt::format(format, std::forward<Args>(args)...)));
}
template <class... Args>
void say(fmt::format_string<Args...> format, Args&&... args) {
  say(stdout, format, std::forward<Args>(args)...);
}

// The terminal control that starts a progress line over the last one: the only text printed
// without say().
inline void rewind_line() { std::fputs("\r\033[K", stderr); }

// An old spelling still works, with this note on stderr.
inline void deprecated(const std::string& old_spelling, const std::string& new_spelling) {
  say(stderr, "brdffit: note: {} is deprecated; use {}\n", old_spelling, new_spelling);
}

// -m/--models NAME[,NAME...]: the one way every command names models; a command that takes one
// model takes one name. `--model` (score, render and export before) still works, with a note.
inline CLI::Option* add_models_option(CLI::App* command, std::string& models, const std::string& description) {
  CLI::Option* option = command->add_option("-m,--models", models, description);
  command->add_option("--model", models)->group("")->each([](const std::string&) {
    deprecated("--model", "-m/--models");
  });
  return option;
}

// The model as a positional argument (`brdffit eval ggx`, before -m): still works, with a note.
inline void add_positional_model(CLI::App* command, std::string& model) {
  command->add_option("model", model)->group("")->each([name = command->get_name()](const std::string& m) {
    deprecated(fmt::format("'brdffit {} {}'", name, m), fmt::format("'brdffit {} -m {}'", name, m));
  });
}

// The one model a command works on: given, and only one.
inline const std::string& one_model(const std::string& models, const std::string& command) {
  if (models.empty()) fail("{}: name the model with -m MODEL", command);
  if (models.find(',') != std::string::npos) fail("{}: -m takes one model here, not '{}'", command, models);
  return models;
}

inline std::string duration_text(double seconds) {
  const long s = std::lround(seconds);
  return s >= 3600 ? fmt::format("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
                   : fmt::format("{}:{:02}", s / 60, s % 60);
}

// fit's and sphere's progress on a terminal: "[k/n] fitting MODEL  elapsed, ETA" on stderr,
// redrawn as each model starts and cleared at the end. Nothing when stderr is not a terminal
// (a log or a pipe gets the results only).
class ModelProgress {
 public:
  ModelProgress() : terminal_(::isatty(STDERR_FILENO) == 1), start_(Clock::now()) {}
  ModelProgress(const ModelProgress&) = delete;
  ModelProgress& operator=(const ModelProgress&) = delete;
  ~ModelProgress() { clear(); }

  // Reports to this progress while `options` fit (the options must not outlive it).
  void attach(FitOptions& options) {
    if (terminal_)
      options.on_model_start = [this](size_t index, size_t count, const std::string& model) {
        draw(index, count, model);
      };
  }

  void clear() {
    if (drawn_) rewind_line();
    drawn_ = false;
  }

 private:
  using Clock = std::chrono::steady_clock;

  void draw(size_t index, size_t count, const std::string& model) {
    const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    // Models differ in cost by a factor of a hundred: the ETA is the rate so far, no more.
    const std::string eta = index > 0 ? ", ETA " + duration_text(elapsed / index * (count - index)) : "";
    rewind_line();
    say(stderr, "[{}/{}] fitting {}  {}{}", index + 1, count, model, duration_text(elapsed), eta);
    std::fflush(stderr);
    drawn_ = true;
  }

  const bool terminal_;
  const Clock::time_point start_;
  bool drawn_ = false;
};

}  // namespace brdffit::cli
