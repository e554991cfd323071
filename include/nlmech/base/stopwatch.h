#pragma once
// Wall-clock seconds for the timings solvers report (factorisation, series, continuation).

#include <chrono>

namespace nlmech
{
  /// Seconds of wall time since `start` (steady clock).
  inline double seconds_since(const std::chrono::steady_clock::time_point start)
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
} // namespace nlmech
