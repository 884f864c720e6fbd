// The commands of brdffit-imaging: those that read or write images.
#include "commands.h"

namespace brdffit::cli {

void add_commands(CLI::App& app, int, char**) {
  add_sphere_commands(app);
  add_render_commands(app);
}

}  // namespace brdffit::cli
