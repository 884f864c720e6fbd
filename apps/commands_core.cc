// The commands of brdffit, and the hand-over of the image commands to brdffit-imaging: brdffit
// itself links no image library, so that `brdffit models` or `brdffit fit` start in a few
// milliseconds and a few megabytes (docs/architecture.md, "Two executables").
#include <unistd.h>

#include <fmt/format.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "brdffit/error.h"
#include "cli_common.h"
#include "commands.h"

namespace brdffit::cli {

namespace {

constexpr const char* kImagingExecutable = "brdffit-imaging";
constexpr const char* kMpiExecutable = "brdffit-mpi";

// Replaces this process with `executable` running the same command line: the one beside this
// executable (a build folder, an installed bin/), else the first on PATH. Returns only to throw.
[[noreturn]] void hand_over(const char* executable, int argc, char** argv) {
  std::vector<char*> args(argv, argv + argc);  // argv[0] kept: usage lines keep saying brdffit
  args.push_back(nullptr);
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  const std::string beside = error ? std::string() : (self.parent_path() / executable).string();
  if (!beside.empty()) ::execv(beside.c_str(), args.data());
  ::execvp(executable, args.data());
  fail("{}: needs {}, which is neither beside this brdffit ({}) nor on PATH: {}", argv[1], executable,
       beside.empty() ? "unknown" : beside, std::strerror(errno));
}
[[noreturn]] void hand_over_to_imaging(int argc, char** argv) { hand_over(kImagingExecutable, argc, argv); }

// `brdffit help [COMMAND]`: the command's --help (brdffit-imaging's for its commands).
void add_help_command(CLI::App& app, char* program) {
  auto topic = std::make_shared<std::string>();
  CLI::App* help = app.add_subcommand("help", "Show the options of a command: brdffit help COMMAND");
  help->add_option("command", *topic, "The command");
  help->callback([&app, topic, program] {
    if (topic->empty()) return fmt::print("{}", app.help());
    for (const CommandSummary& command : kImagingCommands)
      if (*topic == command.name) {
        char help_flag[] = "--help";
        char* args[] = {program, const_cast<char*>(command.name), help_flag};
        hand_over_to_imaging(3, args);
      }
    for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; }))
      if (command->get_name() == *topic) return fmt::print("{}", command->help("brdffit"));
    fail_unknown_command(app, *topic);
  });
}

// Whether mpirun started this process as one of several ranks (its environment says so; brdffit
// itself links no MPI library).
bool started_by_mpirun() {
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"})
    if (const char* size = std::getenv(variable)) return std::atoi(size) > 1;
  return false;
}

}  // namespace

void add_commands(CLI::App& app, int argc, char** argv) {
  for (const CommandSummary& command : kImagingCommands)
    if (argc > 1 && std::strcmp(argv[1], command.name) == 0) hand_over_to_imaging(argc, argv);
  // `mpirun -n N brdffit batch ...`: the ranks share the batch in brdffit-mpi (batch_mpi.h).
  if (argc > 1 && std::strcmp(argv[1], "batch") == 0 && started_by_mpirun()) hand_over(kMpiExecutable, argc, argv);
  add_models_commands(app);
  add_table_commands(app);
  add_fit_commands(app);
  add_batch_command(app);
  add_compare_command(app);
  add_export_command(app);
  add_help_command(app, argv[0]);
  // Listed in --help; never run here (argv[1] names them, handed over above).
  for (const CommandSummary& command : kImagingCommands) {
    CLI::App* listed = app.add_subcommand(command.name, command.summary);
    listed->prefix_command();
    listed->allow_extras();
    listed->callback([argc, argv] { hand_over_to_imaging(argc, argv); });
  }
}

}  // namespace brdffit::cli
