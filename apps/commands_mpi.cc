// The command of brdffit-mpi: `batch`, whose materials the ranks of an MPI job share
// (batch_mpi.h). `brdffit batch` started by mpirun hands itself over to it.
#include "commands.h"

namespace brdffit::cli {

void add_commands(CLI::App& app, int, char**) { add_batch_commands(app); }

}  // namespace brdffit::cli
