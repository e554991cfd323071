#include <nlmech/models/triplet_assembly.h>

#include <algorithm>

namespace nlmech
{
  Eigen::SparseMatrix<double> TripletAssembly::assemble(const std::size_t n, const Triplets &triplets)
  {
    std::lock_guard<std::mutex> hold(assembly_guard);
    const std::size_t           m    = triplets.size();
    bool                        same = pattern.rows() == Eigen::Index(n) && rows.size() == m;
    for (std::size_t i = 0; same && i < m; ++i)
      same = triplets[i].row() == rows[i] && triplets[i].col() == cols[i];
    if (!same)
      {
        // New sequence: Eigen builds the matrix, and every triplet's slot in it is looked up.
        pattern.resize(n, n);
        pattern.setFromTriplets(triplets.begin(), triplets.end());
        pattern.makeCompressed();
        rows.resize(m), cols.resize(m), position.resize(m);
        for (std::size_t i = 0; i < m; ++i)
          {
            rows[i]          = triplets[i].row();
            cols[i]          = triplets[i].col();
            const int *begin = pattern.innerIndexPtr() + pattern.outerIndexPtr()[cols[i]];
            const int *end   = pattern.innerIndexPtr() + pattern.outerIndexPtr()[cols[i] + 1];
            position[i]      = int(std::lower_bound(begin, end, rows[i]) - pattern.innerIndexPtr());
          }
        return pattern;
      }
    double *values = pattern.valuePtr();
    std::fill(values, values + pattern.nonZeros(), 0.0);
    for (std::size_t i = 0; i < m; ++i)
      values[position[i]] += triplets[i].value();
    return pattern;
  }

  TripletAssemblyPool::Handle::Handle(TripletAssemblyPool &pool, const std::size_t slot)
      : pool(pool)
      , slot(slot)
      , assembly(pool.assemblies[slot].get())
  {
  }

  TripletAssemblyPool::Handle::~Handle()
  {
    std::lock_guard<std::mutex> hold(pool.guard);
    pool.held[slot] = false;
  }

  TripletAssemblyPool::Handle TripletAssemblyPool::acquire()
  {
    std::lock_guard<std::mutex> hold(guard);
    std::size_t                 slot = 0;
    while (slot < held.size() && held[slot])
      ++slot;
    if (slot == held.size())
      {
        assemblies.push_back(std::make_unique<TripletAssembly>());
        held.push_back(false);
      }
    held[slot] = true;
    return Handle(*this, slot);
  }
} // namespace nlmech
