#pragma once
// The BLAS underneath CHOLMOD's supernodal factorisation is Debian's single-threaded OpenBLAS,
// which is not safe to call from two threads at once: DIM samples solved on two task threads
// differed in their last digits (and in Newton iterations) from one run to the next, and were
// the same on every run with the factorisations and solves taken one at a time.

#include <mutex>

namespace nlmech
{
  /// Held while a CHOLMOD (BLAS-calling) factorisation or solve runs on a thread that may run
  /// beside others; uncontended (one thread, or MPI ranks alone) it costs a few nanoseconds.
  std::unique_lock<std::mutex> lock_serial_blas();
} // namespace nlmech
