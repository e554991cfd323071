#pragma once
// Thread policy: parallelism is MPI ranks plus deal.II's (TBB) task threads; libraries underneath
// stay serial. Loops over elements run in fixed blocks, so that what they compute, and the order
// in which it is summed, does not depend on the number of threads.

#include <deal.II/base/multithread_info.h>
#include <deal.II/base/parallel.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

namespace nlmech
{
  /// Makes OpenMP parallel regions run on one thread (max-active-levels 0) if an OpenMP runtime
  /// is loaded. CHOLMOD 3 (SuiteSparse 5) opens teams of a compiled-in 4 threads
  /// (CHOLMOD_OMP_NUM_THREADS) inside its supernodal factorisation, ignoring OMP_NUM_THREADS;
  /// on a 2-core machine, or beside TBB threads and other MPI ranks, their spinning made each
  /// factorisation of the strain-limiting normal matrix (60x60 sheet) 1.4x slower. Idempotent,
  /// cheap; called by the command line and by the solvers that factorise with CHOLMOD.
  void serialise_openmp();

  /// Calls work(begin, end) for the blocks [0, b), [b, 2b), ... of [0, n), on deal.II's task
  /// threads when there is more than one block and more than one thread. The blocks are the same
  /// for every thread count; work must only write what belongs to its own block.
  template <typename Work>
  void for_each_block(const std::size_t n, const std::size_t block_size, const Work &work)
  {
    const std::size_t n_blocks = (n + block_size - 1) / block_size;
    auto              blocks   = [&](const std::size_t first, const std::size_t last) {
      for (std::size_t b = first; b < last; ++b)
        work(b * block_size, std::min(n, (b + 1) * block_size));
    };
    if (n_blocks <= 1 || dealii::MultithreadInfo::n_threads() == 1)
      blocks(0, n_blocks);
    else
      dealii::parallel::apply_to_subranges(std::size_t(0), n_blocks, blocks, 1);
  }

  /// out[dofs(e)[i]] += v_e[i] for the element vectors local(e, v_e) of the elements
  /// [begin, end) (v_e zeroed before, N entries in the element's numbering), computed in blocks on
  /// deal.II's threads into a buffer and added in element order: bit for bit what one thread
  /// computes.
  template <std::size_t N, typename Vector, typename Dofs, typename Local>
  void add_element_vectors(const std::size_t begin, const std::size_t end, const std::size_t block_size,
                           const Dofs &dofs, const Local &local, Vector &out)
  {
    auto add = [&](const std::size_t e, const std::array<double, N> &v) {
      const auto d = dofs(e);
      for (std::size_t i = 0; i < N; ++i)
        out[d[i]] += v[i];
    };
    const std::size_t n = end - begin;
    if (n <= block_size || dealii::MultithreadInfo::n_threads() == 1)
      {
        for (std::size_t e = begin; e < end; ++e)
          {
            std::array<double, N> v{};
            local(e, v);
            add(e, v);
          }
        return;
      }
    std::vector<std::array<double, N>> buffer(n); // value-initialised: zeros
    for_each_block(n, block_size, [&](const std::size_t first, const std::size_t last) {
      for (std::size_t i = first; i < last; ++i)
        local(begin + i, buffer[i]);
    });
    for (std::size_t i = 0; i < n; ++i)
      add(begin + i, buffer[i]);
  }

  /// The same over all n elements.
  template <std::size_t N, typename Vector, typename Dofs, typename Local>
  void add_element_vectors(const std::size_t n, const std::size_t block_size, const Dofs &dofs,
                           const Local &local, Vector &out)
  {
    add_element_vectors<N>(0, n, block_size, dofs, local, out);
  }
} // namespace nlmech
