// brdffit and brdffit-imaging: fit analytic reflectance models to measured reflectance. One main for
// both; each registers its own commands (add_commands, commands.h). The exit status tells a script
// what went wrong (kExitCodes, shown under every --help): 1 for the files or the fits, 2 for the
// command line itself.
#include <fmt/format.h>

#include <cstdio>
#include <exception>

#include "brdffit/error.h"
#include "cli_common.h"
#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{"brdffit " BRDFFIT_VERSION ": fit analytic reflectance models to measured BRDFs and photographs"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "brdffit " BRDFFIT_VERSION);
  app.option_defaults()->always_capture_default();  // every command's --help shows every default
  using brdffit::cli::Exit;
  try {
    brdffit::cli::add_commands(app, argc, argv);  // brdffit or brdffit-imaging's (commands.h)
    brdffit::cli::add_common_options(app);        // -q, -v and the exit statuses, on every command
    brdffit::cli::check_command_name(app, argc, argv);
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);  // --help, --version
    const std::string suggestion =
        dynamic_cast<const CLI::ExtrasError*>(&e) ? brdffit::cli::option_suggestion(app) : std::string();
    fmt::print(stderr, "brdffit: error: {}{}\n(brdffit help COMMAND lists a command's options)\n",
               brdffit::printable(e.what()), brdffit::printable(suggestion));
    return Exit::kUsage;
  } catch (const brdffit::UsageError& e) {
    fmt::print(stderr, "brdffit: error: {}\n", e.what());
    return Exit::kUsage;
  } catch (const brdffit::Error& e) {
    fmt::print(stderr, "brdffit: error: {}\n", e.what());
    return Exit::kFailed;
  } catch (const std::exception& e) {
    fmt::print(stderr, "brdffit: internal error: {}\n", brdffit::printable(e.what()));
    return Exit::kInternal;
  }
  return Exit::kOk;
}
