#pragma once
// What went wrong, in one line a user can read: for error messages of the command line and of the
// solvers that keep going after one sample or scheme failed.

#include <exception>
#include <string>

namespace nlmech
{
  /// The message of an exception in one paragraph, without deal.II's source-location banner.
  std::string message_of(const std::exception &e);

  /// Inside a catch block: one line saying what was thrown, whatever its type (deal.II and standard
  /// exceptions, the std::string that gmsh throws, anything else), and of which type it was.
  std::string describe_current_exception();
} // namespace nlmech
