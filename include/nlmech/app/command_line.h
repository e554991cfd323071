#pragma once
// The nlmech command line:
//   nlmech FILE.prm [--output-directory DIR]   run the scene the file names
//   nlmech --validate FILE.prm                 parse and check only
//   nlmech --print-parameters SCENE            print a scene's documented defaults
//   nlmech --list-scenes                       list the registered scenes
// User mistakes end in one clear message on stderr and a non-zero exit status.

#include <mpi.h>

#include <exception>
#include <string>

namespace nlmech
{
  int run_command_line(int argc, char **argv, MPI_Comm comm);

  /// The message of an exception in one paragraph, without deal.II's source-location banner.
  std::string message_of(const std::exception &e);

  /// Inside a catch block: one line saying what was thrown, whatever its type (deal.II and standard
  /// exceptions, the std::string that gmsh throws, anything else), and of which type it was.
  std::string describe_current_exception();

  /// The value of the top-level `set Scene type = NAME` entry of a parameter file, or "" if absent.
  std::string read_scene_type(const std::string &parameter_file);
} // namespace nlmech
