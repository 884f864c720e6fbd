// brdffit and brdffit-imaging: fit analytic reflectance models to measured reflectance. One main for
// both; each registers its own commands (add_commands, commands.h).
#include <fmt/format.h>

#include <cstdio>
#include <exception>

#include "brdffit/error.h"
#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{"brdffit " BRDFFIT_VERSION ": fit analytic reflectance models to measured BRDFs and photographs"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "brdffit " BRDFFIT_VERSION);
  app.option_defaults()->always_capture_default();  // every command's --help shows every default
  try {
    brdffit::cli::add_commands(app, argc, argv);  // brdffit or brdffit-imaging's (commands.h)
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);  // --help, --version
    fmt::print(stderr, "brdffit: error: {}\n(brdffit help COMMAND lists a command's options)\n",
               brdffit::printable(e.what()));
    return e.get_exit_code();
  } catch (const brdffit::Error& e) {
    fmt::print(stderr, "brdffit: error: {}\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "brdffit: internal error: {}\n", brdffit::printable(e.what()));
    return 2;
  }
  return 0;
}
