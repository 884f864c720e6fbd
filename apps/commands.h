// Each brdffit subcommand (or pair of close ones: fit and score, models and eval) lives in its own
// cmd_*.cc and registers itself on the app here.
// A command's callback throws brdffit::Error for bad input; main() prints it and exits 1.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <string>

namespace brdffit::cli {

class BatchRanks;  // batch_ranks.h
using BatchRanksFactory = std::function<std::unique_ptr<BatchRanks>()>;

// The commands of `brdffit` (brdffit_core):
void add_models_commands(CLI::App& app);  // cmd_models.cc: models, eval
void add_table_commands(CLI::App& app);   // cmd_tables.cc: info, lookup, bake
void add_fit_commands(CLI::App& app);     // cmd_fit.cc: fit, score
// batch (in this process when make_ranks is empty; brdffit-mpi passes its MPI ranks: batch_ranks.h)
void add_batch_command(CLI::App& app, BatchRanksFactory make_ranks = {});  // cmd_batch.cc
void add_compare_command(CLI::App& app);                                   // cmd_compare.cc
void add_export_command(CLI::App& app);                                    // cmd_export.cc
// The commands of `brdffit-imaging` (brdffit_imaging), which `brdffit` hands them over to:
void add_sphere_commands(CLI::App& app);  // cmd_sphere.cc: sphere, capture
void add_render_commands(CLI::App& app);  // cmd_render.cc: render, report

struct CommandSummary {
  const char* name;
  const char* summary;  // the one line of `brdffit --help`
};
// brdffit-imaging's commands, for `brdffit` to list and hand over.
inline constexpr CommandSummary kImagingCommands[] = {
    {"sphere", "Fit models to photographs of a sphere under known (or chrome-ball) lights"},
    {"capture", "Grab frames from a camera, video or image sequence; merge several exposures into an HDR image"},
    {"render", "Render a sphere of a measured table or of a fitted model"},
    {"report", "One self-contained HTML page comparing fits, with pictures"},
};
inline const char* imaging_summary(const std::string& name) {
  for (const CommandSummary& command : kImagingCommands)
    if (name == command.name) return command.summary;
  return "";
}

// Registers this executable's commands (commands_core.cc for brdffit, commands_imaging.cc for
// brdffit-imaging). brdffit's replaces the process with brdffit-imaging when argv names one of
// its commands, and throws Error when it cannot.
void add_commands(CLI::App& app, int argc, char** argv);

}  // namespace brdffit::cli
