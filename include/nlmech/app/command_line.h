#pragma once
// The nlmech command line:
//   nlmech FILE.prm [--output-directory DIR]   run the scene the file names
//   nlmech --validate FILE.prm                 parse and check only
//   nlmech --print-parameters SCENE            print a scene's documented defaults
//   nlmech --list-scenes                       list the registered scenes
// and anywhere on the line `--threads N`: at most N threads per MPI rank. By default every rank
// takes its share of the node's cores (deal.II's MPI_InitFinalize); DEAL_II_NUM_THREADS limits
// further.
// User mistakes end in one clear message on stderr and a non-zero exit status.

#include <nlmech/base/exceptions.h>

#include <mpi.h>

#include <exception>
#include <string>

namespace nlmech
{
  int run_command_line(int argc, char **argv, MPI_Comm comm);

  /// Removes `--threads N` from the arguments (before MPI starts) and returns N, or
  /// numbers::invalid_unsigned_int (every core) when it is absent. Throws on a value that is not
  /// a positive integer.
  unsigned int take_thread_option(int &argc, char **argv);

  /// The value of the top-level `set Scene type = NAME` entry of a parameter file, or "" if absent.
  std::string read_scene_type(const std::string &parameter_file);
} // namespace nlmech
