#include <nlmech/base/run_context.h>

#include <deal.II/base/mpi.h>

#include <filesystem>
#include <iostream>

namespace nlmech
{
  RunContext::RunContext(MPI_Comm comm, OutputDirectory &output)
      : comm(comm)
      , output(output)
      , pcout(std::cout, dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      // Per-rank wall times: a communicator-based TimerOutput would synchronise in its destructor,
      // which it refuses (noisily) while an error unwinds the stack.
      , timer(timing_text, dealii::TimerOutput::never, dealii::TimerOutput::wall_times)
  {
  }

  bool RunContext::is_root() const
  {
    return dealii::Utilities::MPI::this_mpi_process(comm) == 0;
  }

  void RunContext::fail_check(const std::string &what)
  {
    failed_checks.push_back(what);
    if (is_root())
      std::cerr << "nlmech: check failed: " << what << std::endl;
  }

  namespace
  {
    std::string &parameter_directory()
    {
      static std::string directory = ".";
      return directory;
    }
  } // namespace

  const std::string &current_parameter_directory()
  {
    return parameter_directory();
  }

  void set_current_parameter_directory(const std::string &directory)
  {
    parameter_directory() = directory.empty() ? "." : directory;
  }

  std::string resolve_input_path(const std::string &path, const std::string &parameter_file_directory)
  {
    namespace fs = std::filesystem;
    if (path.empty() || fs::path(path).is_absolute())
      return path;
    return (fs::path(parameter_file_directory) / path).lexically_normal().string();
  }
} // namespace nlmech
