// `brdffit sphere`, `capture`: photographed spheres (issue 5).
#include "commands.h"

namespace brdffit::cli {

void add_sphere_commands(CLI::App& /*app*/) {}

}  // namespace brdffit::cli
