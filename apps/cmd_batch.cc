// `brdffit batch`, `compare`, `render`, `report`, `export` (issue 6).
#include "commands.h"

namespace brdffit::cli {

void add_batch_commands(CLI::App& /*app*/) {}

}  // namespace brdffit::cli
