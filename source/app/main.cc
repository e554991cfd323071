// nlmech: computational modeling and design of nonlinear mechanical systems (deal.II/Trilinos).
#include <deal.II/base/mpi.h>

#include <nlmech/app/command_line.h>
#include <nlmech/base/threads.h>

#include <iostream>

int main(int argc, char **argv)
{
  unsigned int threads = 0;
  try
    {
      threads = nlmech::take_thread_option(argc, argv);
    }
  catch (...)
    {
      std::cerr << "nlmech: error: " << nlmech::describe_current_exception() << std::endl;
      return 1;
    }
  // Every rank takes its share of the node's cores unless --threads or DEAL_II_NUM_THREADS says
  // fewer; element loops run on deal.II's task threads, CHOLMOD's OpenMP stays serial.
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, threads);
  nlmech::serialise_openmp();
  return nlmech::run_command_line(argc, argv, MPI_COMM_WORLD);
}
