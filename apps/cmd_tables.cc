// `brdffit info`, `lookup`, `bake`: measured tables (issue 3).
#include "commands.h"

namespace brdffit::cli {

void add_table_commands(CLI::App& /*app*/) {}

}  // namespace brdffit::cli
