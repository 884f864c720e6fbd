// Each brdffit subcommand lives in its own cmd_*.cc and registers itself on the app here.
// A command's callback throws brdffit::Error for bad input; main() prints it and exits 1.
#pragma once

#include <CLI/CLI.hpp>

namespace brdffit::cli {

void add_models_commands(CLI::App& app);  // models, eval

}  // namespace brdffit::cli
