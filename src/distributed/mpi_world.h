// The world of this process (core/world.h) when it runs under mpirun: MPI's ranks. The one
// place that includes MPI (tests/test_layering.cpp checks it); built with MPI when CMake's
// MANYLIGHT_MPI is on, and without it these functions answer as one process.
#pragma once

#include "core/world.h"

namespace ml {

// True when this build has MPI (CMake's MANYLIGHT_MPI found OpenMPI).
bool mpi_built();

// The number of processes an MPI launcher (mpirun) started this one among, from its
// environment (OMPI_COMM_WORLD_SIZE, PMI_SIZE); 1 when none did.
int launched_ranks();

// The world of this process. Under mpirun (launched_ranks() > 1) in an MPI build: MPI's,
// initialised on the first call (MPI_Init) and finalised when the program exits. Otherwise
// local_world(): without mpirun no MPI is initialised, and the program runs as it always did.
// Throws UsageError when mpirun started several processes of a build without MPI: each would
// render the whole image and write the same files.
World& process_world(int* argc, char*** argv);

}  // namespace ml
