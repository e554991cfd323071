#pragma once
// Thread policy: parallelism is MPI ranks plus deal.II's (TBB) task threads; libraries underneath
// stay serial.

namespace nlmech
{
  /// Makes OpenMP parallel regions run on one thread (max-active-levels 0) if an OpenMP runtime
  /// is loaded. CHOLMOD 3 (SuiteSparse 5) opens teams of a compiled-in 4 threads
  /// (CHOLMOD_OMP_NUM_THREADS) inside its supernodal factorisation, ignoring OMP_NUM_THREADS;
  /// on a 2-core machine, or beside TBB threads and other MPI ranks, their spinning made each
  /// factorisation of the strain-limiting normal matrix (60x60 sheet) 1.4x slower. Idempotent,
  /// cheap; called by the command line and by the solvers that factorise with CHOLMOD.
  void serialise_openmp();
} // namespace nlmech
