#pragma once
// Results are written under a temporary name and renamed into place, so an interrupted run never
// leaves a file (or a results folder) that looks complete.

#include <mpi.h>

#include <fstream>
#include <string>

namespace nlmech
{
  /// One file written atomically: stream into it, then commit() renames it into place.
  /// Destroying an uncommitted AtomicFile removes the temporary.
  class AtomicFile
  {
  public:
    explicit AtomicFile(const std::string &path);
    ~AtomicFile();
    AtomicFile(const AtomicFile &)            = delete;
    AtomicFile &operator=(const AtomicFile &) = delete;

    std::ostream &stream() { return out; }
    void          commit();

  private:
    std::string   final_path;
    std::string   temporary_path;
    std::ofstream out;
    bool          committed = false;
  };

  /// Writes a whole string to a file atomically.
  void write_file_atomically(const std::string &path, const std::string &content);

  /// A results folder that is filled under "<path>.incomplete" and renamed to "<path>" only when
  /// the run finishes. Collective over the communicator; rank 0 touches the file system.
  class OutputDirectory
  {
  public:
    OutputDirectory(const std::string &final_path, MPI_Comm comm);

    /// Creates the staging folder (removing a stale one). Collective.
    void create();
    bool is_created() const { return created; }
    /// Path of a result file inside the staging folder.
    std::string file(const std::string &name) const;
    /// Replaces the final folder by the staging folder. Collective.
    void commit();
    /// Removes the staging folder after a failure; never throws.
    void abandon() noexcept;

    const std::string &final_path() const { return final_directory; }

  private:
    std::string final_directory;
    std::string staging_directory;
    MPI_Comm    comm;
    bool        created = false;
  };
} // namespace nlmech
