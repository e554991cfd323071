#include <deal.II/base/array_view.h>
#include <deal.II/base/mpi.h>

#include <nlmech/base/rank_sharing.h>

namespace nlmech
{
  namespace
  {
    // Set by the scopes on the main thread before any loop starts; only read inside loops.
    MPI_Comm     sharing_comm = MPI_COMM_SELF;
    unsigned int sharing_rank = 0, sharing_size = 1;
  } // namespace

  MPI_Comm element_sharing_communicator()
  {
    return sharing_comm;
  }

  unsigned int element_sharing_ranks()
  {
    return sharing_size;
  }

  ShareElementsOverRanks::ShareElementsOverRanks(MPI_Comm comm)
      : previous_comm(sharing_comm)
      , previous_rank(sharing_rank)
      , previous_size(sharing_size)
  {
    sharing_comm = comm;
    sharing_rank = dealii::Utilities::MPI::this_mpi_process(comm);
    sharing_size = dealii::Utilities::MPI::n_mpi_processes(comm);
  }

  ShareElementsOverRanks::~ShareElementsOverRanks()
  {
    sharing_comm = previous_comm;
    sharing_rank = previous_rank;
    sharing_size = previous_size;
  }

  std::pair<std::size_t, std::size_t> owned_elements(const std::size_t n)
  {
    const std::size_t base = n / sharing_size, extra = n % sharing_size, r = sharing_rank;
    const std::size_t begin = r * base + std::min<std::size_t>(r, extra);
    return {begin, begin + base + (r < extra ? 1 : 0)};
  }

  void sum_over_sharing_ranks(double *values, const std::size_t count)
  {
    if (sharing_size == 1 || count == 0)
      return;
    const dealii::ArrayView<double> view(values, count);
    dealii::Utilities::MPI::sum(dealii::ArrayView<const double>(values, count), sharing_comm, view);
  }

  double sum_over_sharing_ranks(const double value)
  {
    return sharing_size == 1 ? value : dealii::Utilities::MPI::sum(value, sharing_comm);
  }

  double min_over_sharing_ranks(const double value)
  {
    return sharing_size == 1 ? value : dealii::Utilities::MPI::min(value, sharing_comm);
  }
} // namespace nlmech
