#include <nlmech/base/progress.h>

#include <deal.II/base/mpi.h>

#include <cstdio>
#include <ostream>

namespace nlmech
{
  ProgressReporter::ProgressReporter(const std::string &task, double total_work, MPI_Comm comm,
                                     std::ostream &out)
      : task(task)
      , total_work(total_work)
      , is_root(dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      , out(out)
      , start(std::chrono::steady_clock::now())
  {
  }

  double ProgressReporter::elapsed_seconds() const
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  double ProgressReporter::estimated_seconds_left(double work_done) const
  {
    if (work_done <= 0)
      return -1;
    return elapsed_seconds() * (total_work - work_done) / work_done;
  }

  void ProgressReporter::report(double work_done, const std::string &label)
  {
    if (!is_root)
      return;
    const double left = estimated_seconds_left(work_done);
    char         line[256];
    std::snprintf(line, sizeof(line), "[%s] %5.1f%% done, %.1f s elapsed, about %.1f s left", task.c_str(),
                  100.0 * work_done / total_work, elapsed_seconds(), left < 0 ? 0.0 : left);
    out << line << (label.empty() ? "" : " (" + label + ")") << std::endl;
  }
} // namespace nlmech
