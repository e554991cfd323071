#pragma once
// Sparse matrices from triplets, with the pattern kept between calls: a Hessian whose triplets
// come in the same (row, column) sequence as last time is assembled by adding each value into
// its known position, instead of Eigen's sort-and-merge setFromTriplets (the serial part of a
// tangent: 7 million triplets on a 10k-vertex tetrahedral mesh). The sums are taken in triplet
// order, as setFromTriplets takes them.

#include <nlmech/models/energy_term.h>

#include <Eigen/Sparse>

#include <memory>
#include <mutex>
#include <vector>

namespace nlmech
{
  class TripletAssembly
  {
  public:
    /// The n x n matrix of the triplets (duplicates summed). Thread-safe (one call at a time).
    Eigen::SparseMatrix<double> assemble(std::size_t n, const Triplets &triplets);

    /// A buffer to collect triplets in, kept between calls (no re-allocation of millions of
    /// entries per tangent); for one user at a time (TripletAssemblyPool hands them out).
    Triplets &buffer() { return scratch; }

  private:
    std::mutex                  assembly_guard;
    Triplets                    scratch;
    std::vector<int>            rows, cols, position; // the last sequence and each one's slot
    Eigen::SparseMatrix<double> pattern;
  };

  /// Assemblies for tangents evaluated at the same time on several threads (harmonic balance
  /// evaluates one per time sample): each concurrent caller gets an assembly of its own, with the
  /// pattern that assembly kept from its last use. A flag per assembly, not a lock, marks it held,
  /// so a task that re-enters on a thread already holding one simply gets another.
  class TripletAssemblyPool
  {
  public:
    /// An assembly nobody else holds, until the handle dies; a new one when all are held.
    class Handle
    {
    public:
      Handle(TripletAssemblyPool &pool, std::size_t slot);
      ~Handle();
      Handle(const Handle &)                     = delete;
      Handle          &operator=(const Handle &) = delete;
      TripletAssembly *operator->() const { return assembly; }

    private:
      TripletAssemblyPool &pool;
      std::size_t          slot;
      TripletAssembly     *assembly;
    };

    Handle acquire();

  private:
    std::mutex                                    guard;
    std::vector<std::unique_ptr<TripletAssembly>> assemblies;
    std::vector<bool>                             held;
  };
} // namespace nlmech
