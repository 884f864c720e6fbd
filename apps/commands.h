// Each brdffit subcommand lives in its own cmd_*.cc and registers itself on the app here.
// A command's callback throws brdffit::Error for bad input; main() prints it and exits 1.
#pragma once

#include <CLI/CLI.hpp>

namespace brdffit::cli {

void add_models_commands(CLI::App& app);  // cmd_models.cc: models, eval
void add_table_commands(CLI::App& app);   // cmd_tables.cc: info, lookup, bake
void add_fit_commands(CLI::App& app);     // cmd_fit.cc: fit, score
void add_sphere_commands(CLI::App& app);  // cmd_sphere.cc: sphere, capture
void add_batch_commands(CLI::App& app);   // cmd_batch.cc: batch, compare, export
void add_render_commands(CLI::App& app);  // cmd_render.cc: render, report

}  // namespace brdffit::cli
