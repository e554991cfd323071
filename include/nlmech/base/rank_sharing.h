#pragma once
// Ranks that share the element loops of one model. Inside a ShareElementsOverRanks scope every
// rank of its communicator evaluates only its own contiguous block of each element loop (values,
// gradients, Hessians, ANM series), and the model sums the partial results over the ranks (MPI
// all-reduce through deal.II); the solver on top runs on every rank with the same summed data,
// so each rank holds the same answer, equal to the serial one to round-off. Outside such a scope
// (the default, and for independent samples that go one per rank) every loop is whole.

#include <mpi.h>

#include <cstddef>
#include <utility>

namespace nlmech
{
  /// The ranks sharing element loops now (MPI_COMM_SELF outside any scope).
  MPI_Comm     element_sharing_communicator();
  unsigned int element_sharing_ranks();

  /// Makes `comm`'s ranks share element loops until destroyed (scopes nest; the inner one rules).
  class ShareElementsOverRanks
  {
  public:
    explicit ShareElementsOverRanks(MPI_Comm comm);
    ~ShareElementsOverRanks();
    ShareElementsOverRanks(const ShareElementsOverRanks &)            = delete;
    ShareElementsOverRanks &operator=(const ShareElementsOverRanks &) = delete;

  private:
    MPI_Comm     previous_comm;
    unsigned int previous_rank, previous_size;
  };

  /// This rank's block [begin, end) of a loop over n elements: n / ranks each, the first n % ranks
  /// ranks one more (the whole [0, n) without sharing).
  std::pair<std::size_t, std::size_t> owned_elements(std::size_t n);

  /// values[i] = sum over the sharing ranks of values[i], in place (nothing without sharing).
  void   sum_over_sharing_ranks(double *values, std::size_t count);
  double sum_over_sharing_ranks(double value);
  double min_over_sharing_ranks(double value);
} // namespace nlmech
