#pragma once
// What a scene gets to run: the communicator, the staged output folder, a timer, the summary
// figures, and path resolution relative to the parameter file.

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/base/json.h>

#include <mpi.h>

#include <sstream>
#include <string>
#include <vector>

namespace nlmech
{
  class RunContext
  {
  public:
    RunContext(MPI_Comm comm, OutputDirectory &output);

    MPI_Comm                   comm;
    OutputDirectory           &output;
    dealii::ConditionalOStream pcout;
    std::ostringstream         timing_text;
    dealii::TimerOutput        timer;
    JsonObject                 summary;
    /// Set by a scene whose solve stopped early but left consistent partial results: the results are
    /// kept (marked "status": "partial" in summary.json) and the run still exits with an error.
    std::string partial_reason;
    /// The run's own verifications that failed (a forward round trip above its tolerance, a Newmark
    /// check that disagrees with the periodic state, an unstable designed equilibrium): the results
    /// are kept, summary.json says "status": "check_failed" and lists them, and the run exits with 1.
    std::vector<std::string> failed_checks;

    /// Records a failed verification (see failed_checks) and says so on stderr (rank 0).
    void fail_check(const std::string &what);

    bool is_root() const;
  };

  /// A path from a parameter file: absolute, or relative to the folder of the parameter file.
  std::string resolve_input_path(const std::string &path, const std::string &parameter_file_directory);

  /// The folder holding the parameter file being read (set by the command line before parsing).
  const std::string &current_parameter_directory();
  void               set_current_parameter_directory(const std::string &directory);
} // namespace nlmech
