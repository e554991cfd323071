#include <nlmech/base/plot.h>

#include <cstdlib>
#include <iostream>

namespace nlmech
{
  namespace
  {
    /// Single quotes for the shell, with embedded ones closed, escaped and reopened.
    std::string quoted(const std::string &text)
    {
      std::string out = "'";
      for (const char c : text)
        out += c == '\'' ? std::string("'\\''") : std::string(1, c);
      return out + "'";
    }
  } // namespace

  bool run_plot(const std::string &script, const std::vector<std::string> &arguments)
  {
    std::string command =
        quoted(NLMECH_PYTHON) + " " + quoted(std::string(NLMECH_SOURCE_DIR) + "/contrib/plot/" + script);
    for (const auto &a : arguments)
      command += " " + quoted(a);
    if (std::system(command.c_str()) == 0)
      return true;
    std::cerr << "nlmech: warning: the plot " << script << " could not be drawn (python3/matplotlib)."
              << std::endl;
    return false;
  }
} // namespace nlmech
