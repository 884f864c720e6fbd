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
  try {
    brdffit::cli::add_commands(app, argc, argv);  // brdffit or brdffit-imaging's (commands.h)
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const brdffit::Error& e) {
    fmt::print(stderr, "brdffit: error: {}\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "brdffit: internal error: {}\n", e.what());
    return 2;
  }
  return 0;
}
