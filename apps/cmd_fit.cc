// `brdffit fit`, `score`: the fitter (issue 4).
#include "commands.h"

namespace brdffit::cli {

void add_fit_commands(CLI::App& /*app*/) {}

}  // namespace brdffit::cli
