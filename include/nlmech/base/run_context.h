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

    bool is_root() const;
  };

  /// A path from a parameter file: absolute, or relative to the folder of the parameter file.
  std::string resolve_input_path(const std::string &path, const std::string &parameter_file_directory);

  /// The folder holding the parameter file being read (set by the command line before parsing).
  const std::string &current_parameter_directory();
  void               set_current_parameter_directory(const std::string &directory);
} // namespace nlmech
