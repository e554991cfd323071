#pragma once
// The nlmech command line:
//   nlmech FILE.prm [--output-directory DIR]   run the scene the file names
//   nlmech --validate FILE.prm                 parse and check only
//   nlmech --print-parameters SCENE            print a scene's documented defaults
//   nlmech --list-scenes                       list the registered scenes
// User mistakes end in one clear message on stderr and a non-zero exit status.

#include <nlmech/base/exceptions.h>

#include <mpi.h>

#include <exception>
#include <string>

namespace nlmech
{
  int run_command_line(int argc, char **argv, MPI_Comm comm);

  /// The value of the top-level `set Scene type = NAME` entry of a parameter file, or "" if absent.
  std::string read_scene_type(const std::string &parameter_file);
} // namespace nlmech
