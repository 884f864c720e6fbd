// What every command spells and shows the same way: exit statuses, -q/-v, how models are named
// (-m/--models), old spellings that still work, durations, and the progress line of fit and sphere.
#pragma once

#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <vector>

#include "brdffit/error.h"
#include "brdffit/fit.h"
#include "brdffit/measured.h"
#include "brdffit/names.h"
#include "brdffit/registry.h"

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

// The exit status of every command, and its explanation under every --help.
struct Exit {
  static constexpr int kOk = 0;
  static constexpr int kFailed = 1;     // an Error: a file could not be read or written, or a fit failed
  static constexpr int kUsage = 2;      // a UsageError or CLI11's parse error: the command line is wrong
  static constexpr int kInternal = 70;  // anything else: a bug (EX_SOFTWARE of sysexits.h)
};
inline constexpr const char* kExitCodes =
    "Exit status: 0 done; 1 an input or output file could not be used, or the fitting failed; 2 the command "
    "line is wrong (an unknown command, option, model or metric name, a bad value, an input of the wrong kind); "
    "70 an internal error (a bug: please report it).";

// How much a command prints: -q (errors and the results only), -v (every stage as it starts).
enum class Verbosity { Quiet, Normal, Verbose };
inline Verbosity& verbosity() {
  static Verbosity level = Verbosity::Normal;
  return level;
}

// What a command prints besides its results (what it read, what it is about to do): not with -q.
template <class... Args>
void inform(std::FILE* out, fmt::format_string<Args...> format, Args&&... args) {
  if (verbosity() != Verbosity::Quiet) say(out, format, std::forward<Args>(args)...);
}

// A stage starting, on stderr with -v only: "brdffit: reading t.csv".
template <class... Args>
void stage(fmt::format_string<Args...> format, Args&&... args) {
  if (verbosity() == Verbosity::Verbose) say(stderr, "brdffit: {}\n", fmt::format(format, std::forward<Args>(args)...));
}

// Under every command: -q/--quiet, -v/--verbose and the exit statuses at the end of its --help.
inline void add_common_options(CLI::App& app) {
  app.footer(kExitCodes);
  for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; })) {
    command->footer(kExitCodes);
    if (command->get_name() == "help") continue;
    CLI::Option* quiet = command->add_flag_callback(
        "-q,--quiet", [] { verbosity() = Verbosity::Quiet; }, "Print only errors, warnings and the results");
    command
        ->add_flag_callback(
            "-v,--verbose", [] { verbosity() = Verbosity::Verbose; }, "Print each stage as it starts")
        ->excludes(quiet);
  }
}

// The usage error for a command `app` does not have, with the nearest one it has.
[[noreturn]] inline void fail_unknown_command(const CLI::App& app, const std::string& name) {
  std::vector<std::string> commands;
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; }))
    commands.push_back(command->get_name());
  fail_usage("no command '{}'{} (brdffit --help lists them)", name, did_you_mean(name, commands));
}

// "; did you mean '--max-samples'?" for the first option CLI11 did not expect (`--max-sample`,
// `--Max_Samples=5`) among the options of the command it parsed, or "".
inline std::string option_suggestion(const CLI::App& app) {
  for (const CLI::App* command : app.get_subcommands())
    for (const std::string& extra : command->remaining()) {
      if (extra.size() < 2 || extra[0] != '-') continue;
      std::vector<std::string> names;
      for (const CLI::Option* option : command->get_options()) {
        for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
        for (const std::string& name : option->get_snames()) names.push_back("-" + name);
      }
      return did_you_mean(extra.substr(0, extra.find('=')), names);
    }
  return "";
}

// `brdffit hlep`: refused with the nearest command before CLI11 takes the word for an argument.
inline void check_command_name(const CLI::App& app, int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return;
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; }))
    if (command->get_name() == argv[1]) return;
  fail_unknown_command(app, argv[1]);
}

// An Error from turning an option's value into the library's terms (parameter_values,
// parse_vec3, parse_shard, material_format) is a usage error: the value on the command line is wrong.
template <class F>
auto option_value(F&& parse) {
  try {
    return parse();
  } catch (const UsageError&) {
    throw;
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
}

// The input of fit, score, info and lookup is one measured table: a folder, a photograph or a
// result document is a usage error naming the command that takes it, before anything is read.
inline void check_table_argument(const std::string& path, const std::string& command) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::is_directory(path, error))
    fail_usage("{}: a folder; {} takes one measured table (`brdffit batch {}` fits every table in a folder)", path,
               command, path);
  std::string extension = fs::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const char* image : {".png", ".jpg", ".jpeg", ".exr", ".hdr", ".tif", ".tiff"})
    if (extension == image)
      fail_usage(
          "{}: a photograph; {} takes a measured table (MERL, RGL, CSV); `brdffit sphere {} --lights FILE` "
          "fits photographs of a sphere",
          path, command, path);
  if (extension == ".json")
    fail_usage(
        "{}: a result document, not a measured table ({} takes the table it was fitted to; render, report, "
        "export and compare read result documents)",
        path, command);
}

// The inputs of compare, report and export are result documents (or folders of them): a measured
// table is a usage error saying how to make one, not a JSON parser's message.
inline void check_document_arguments(const std::vector<std::string>& paths) {
  std::error_code error;
  for (const std::string& path : paths)
    if (!std::filesystem::is_directory(path, error) && has_table_extension(path))
      fail_usage("{}: a measured table, not a result document; `brdffit fit {} -o RESULT.json` makes one", path, path);
}

// The models of `names` this build has, comma separated: a command's default -m.
inline std::string model_list(std::initializer_list<const char*> names) {
  std::string list;
  for (const char* name : names)
    if (find_model(name)) list += (list.empty() ? "" : ",") + std::string(name);
  return list;
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
  if (models.empty()) fail_usage("{}: name the model with -m MODEL", command);
  if (models.find(',') != std::string::npos) fail_usage("{}: -m takes one model here, not '{}'", command, models);
  return models;
}

// The one model a command works on, by its name (a usage error with the nearest name when unknown).
inline const Model& named_model(const std::string& models, const std::string& command) {
  const std::string& name = one_model(models, command);
  if (name == "all") fail_usage("{}: -m takes one model here, not 'all'", command);
  return *parse_model_list(name).front();
}

inline std::string duration_text(double seconds) {
  const long s = std::lround(seconds);
  return s >= 3600 ? fmt::format("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
                   : fmt::format("{}:{:02}", s / 60, s % 60);
}

// fit's and sphere's progress: on a terminal "[k/n] fitting MODEL  elapsed, ETA" on stderr,
// redrawn as each model starts and cleared at the end; nothing when stderr is not a terminal (a
// log or a pipe gets the results only) or with -q. With -v, one such line per model, kept.
class ModelProgress {
 public:
  ModelProgress()
      : terminal_(::isatty(STDERR_FILENO) == 1 && verbosity() == Verbosity::Normal),
        lines_(verbosity() == Verbosity::Verbose),
        start_(Clock::now()) {}
  ModelProgress(const ModelProgress&) = delete;
  ModelProgress& operator=(const ModelProgress&) = delete;
  ~ModelProgress() { clear(); }

  // Reports to this progress while `options` fit (the options must not outlive it).
  void attach(FitOptions& options) {
    if (terminal_ || lines_)
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
    const std::string line =
        fmt::format("[{}/{}] fitting {}  {}{}", index + 1, count, model, duration_text(elapsed), eta);
    if (lines_) return stage("{}", line);
    rewind_line();
    say(stderr, "{}", line);
    std::fflush(stderr);
    drawn_ = true;
  }

  const bool terminal_, lines_;
  const Clock::time_point start_;
  bool drawn_ = false;
};

}  // namespace brdffit::cli
