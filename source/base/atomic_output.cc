#include <nlmech/base/atomic_output.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <unistd.h>

#include <filesystem>

namespace nlmech
{
  namespace fs = std::filesystem;

  AtomicFile::AtomicFile(const std::string &path)
      : final_path(path)
      , temporary_path(path + ".tmp." + std::to_string(::getpid()))
      , out(temporary_path)
  {
    AssertThrow(out.good(), dealii::ExcMessage("Cannot open <" + temporary_path + "> for writing."));
    out.precision(16);
  }

  AtomicFile::~AtomicFile()
  {
    if (!committed)
      {
        out.close();
        std::error_code ec;
        fs::remove(temporary_path, ec);
      }
  }

  void AtomicFile::commit()
  {
    out.flush();
    AssertThrow(out.good(), dealii::ExcMessage("Writing <" + temporary_path + "> failed."));
    out.close();
    fs::rename(temporary_path, final_path);
    committed = true;
  }

  void write_file_atomically(const std::string &path, const std::string &content)
  {
    AtomicFile file(path);
    file.stream() << content;
    file.commit();
  }

  OutputDirectory::OutputDirectory(const std::string &final_path, MPI_Comm comm)
      : final_directory(fs::path(final_path).lexically_normal().string())
      , comm(comm)
  {
    while (final_directory.size() > 1 && final_directory.back() == '/')
      final_directory.pop_back();
    staging_directory = final_directory + ".incomplete";
  }

  void OutputDirectory::create()
  {
    std::string error;
    if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      {
        std::error_code ec;
        fs::remove_all(staging_directory, ec);
        fs::create_directories(staging_directory, ec);
        if (ec)
          error = "Cannot create the output folder <" + staging_directory + ">: " + ec.message();
      }
    error = dealii::Utilities::MPI::broadcast(comm, error, 0);
    AssertThrow(error.empty(), dealii::ExcMessage(error));
    created = true;
  }

  std::string OutputDirectory::file(const std::string &name) const
  {
    return (fs::path(staging_directory) / name).string();
  }

  void OutputDirectory::commit()
  {
    MPI_Barrier(comm);
    std::string error;
    if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      {
        std::error_code ec;
        fs::remove_all(final_directory, ec);
        fs::rename(staging_directory, final_directory, ec);
        if (ec)
          error = "Cannot move results into <" + final_directory + ">: " + ec.message();
      }
    error = dealii::Utilities::MPI::broadcast(comm, error, 0);
    AssertThrow(error.empty(), dealii::ExcMessage(error));
    created = false;
  }

  void OutputDirectory::abandon() noexcept
  {
    if (!created)
      return;
    if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      {
        std::error_code ec;
        fs::remove_all(staging_directory, ec);
      }
    created = false;
  }
} // namespace nlmech
