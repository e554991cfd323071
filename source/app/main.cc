// nlmech: computational modeling and design of nonlinear mechanical systems (deal.II/Trilinos).
#include <deal.II/base/mpi.h>

#include <nlmech/app/command_line.h>
#include <nlmech/base/threads.h>

int main(int argc, char **argv)
{
  // One thread per MPI rank by default; the parallelism is MPI.
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  nlmech::serialise_openmp();
  return nlmech::run_command_line(argc, argv, MPI_COMM_WORLD);
}
