#pragma once
// Progress with an estimate of the time left, printed by rank 0 only.

#include <mpi.h>

#include <chrono>
#include <iosfwd>
#include <string>

namespace nlmech
{
  class ProgressReporter
  {
  public:
    /// total_work is in any unit the caller can estimate up front (steps, expected DOFs, ...);
    /// the time left is extrapolated from the work done so far.
    ProgressReporter(const std::string &task, double total_work, MPI_Comm comm, std::ostream &out);

    /// Reports that `work_done` of the total is finished, with a short label of what was done.
    void report(double work_done, const std::string &label = "");

    double elapsed_seconds() const;
    /// Estimated seconds left; negative when nothing is done yet.
    double estimated_seconds_left(double work_done) const;

  private:
    std::string                                        task;
    double                                             total_work;
    bool                                               is_root;
    std::ostream                                      &out;
    std::chrono::time_point<std::chrono::steady_clock> start;
  };
} // namespace nlmech
