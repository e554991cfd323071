// Pattern "ring chain" (subsection Material/Ring chain): the validation material, rows of linked
// rings with a closed-form stretch limit 2 (R - r) / spacing - 1.

#include <nlmech/scenes/dim/pattern_plugin.h>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    class RingChainPattern : public PatternPlugin
    {
    public:
      static void declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Ring chain");
        prm.declare_entry("Ring radius", "4", Patterns::Double(0), "R [mm].");
        prm.declare_entry("Tube radius", "1", Patterns::Double(0), "r [mm].");
        prm.declare_entry("Spacing", "5.5", Patterns::Double(0), "Distance of linked rings at rest [mm].");
        prm.declare_entry("Row spacing", "12", Patterns::Double(0), "Distance of the (unlinked) rows [mm].");
        prm.declare_entry("Segments", "64", Patterns::Integer(8), "Centreline segments per ring.");
        prm.leave_subsection();
      }

      explicit RingChainPattern(ParameterHandler &prm)
      {
        prm.enter_subsection("Ring chain");
        R = prm.get_double("Ring radius"), r = prm.get_double("Tube radius");
        spacing = prm.get_double("Spacing"), row_spacing = prm.get_double("Row spacing");
        segments = unsigned(prm.get_integer("Segments"));
        prm.leave_subsection();
      }

      dim::Pattern pattern(const double density) const override
      {
        return dim::ring_chain_pattern(R, r, spacing, segments, row_spacing, density);
      }

    private:
      double       R = 4, r = 1, spacing = 5.5, row_spacing = 12;
      unsigned int segments = 64;
    };
  } // namespace

  NLMECH_REGISTER_PATTERN(ring_chain,
                          PatternInfo{"ring chain",
                                      "the validation material: rows of linked rings with a closed-form "
                                      "stretch limit",
                                      {&RingChainPattern::declare_parameters},
                                      [](ParameterHandler &prm) -> std::unique_ptr<PatternPlugin> {
                                        return std::make_unique<RingChainPattern>(prm);
                                      }})
} // namespace nlmech
