#pragma once
// The one "Gravity" entry of every scene with weight, declared and parsed in the current
// subsection: a magnitude along a direction the scene fixes, or a vector.

#include <string>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace nlmech
{
  struct GravityParameter
  {
    /// `components` = 1: a magnitude (default 9.81) along the direction `note` names; otherwise a
    /// vector (default 0, 0, -9.81) of that many components, 0 for one per space dimension.
    static void declare_parameters(dealii::ParameterHandler &prm, unsigned int components,
                                   const std::string &note = "");
    /// The value with exactly `components` entries (an error naming the entry otherwise).
    static std::vector<double> parse_parameters(const dealii::ParameterHandler &prm, unsigned int components);
  };
} // namespace nlmech
