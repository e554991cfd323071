#pragma once
// The interlocking patterns of the dim-characterization scene as registered plugins: each pattern
// (4-in-1, threefold, torus knot, scale mail, ring chain, mesh element) declares its own subsection
// of subsection Material and builds its Pattern. A new pattern is one new file with
// NLMECH_REGISTER_PATTERN.

#include <nlmech/base/plugin_registry.h>
#include <nlmech/dim/patterns.h>

namespace nlmech
{
  class PatternPlugin
  {
  public:
    virtual ~PatternPlugin() = default;
    /// The pattern of elements of this density [kg/mm^3], its dimensions checked.
    virtual dim::Pattern pattern(double density) const = 0;
  };

  using PatternRegistry     = PluginRegistry<PatternPlugin>;
  using PatternInfo         = PluginInfo<PatternPlugin>;
  using PatternRegistration = PluginRegistration<PatternPlugin>;

  namespace dim_units
  {
    constexpr double degree = 3.14159265358979323846 / 180;
  }
} // namespace nlmech

#define NLMECH_REGISTER_PATTERN(identifier, ...)                                      \
  namespace                                                                           \
  {                                                                                   \
    const nlmech::PatternRegistration identifier##_pattern_registration(__VA_ARGS__); \
  }
