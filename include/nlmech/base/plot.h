#pragma once
// PNG plots by the matplotlib scripts in contrib/plot: one launcher for every scene.

#include <string>
#include <vector>

namespace nlmech
{
  /// Runs contrib/plot/`script` with Debian's python3 on `arguments`; returns false (after a
  /// warning on stderr naming the plot) when it could not be drawn. A missing plot never fails a run.
  bool run_plot(const std::string &script, const std::vector<std::string> &arguments);
} // namespace nlmech
