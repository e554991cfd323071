// Pattern "threefold" (subsection Material/Threefold).

#include <nlmech/scenes/dim/pattern_plugin.h>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    class ThreefoldPattern : public PatternPlugin
    {
    public:
      static void declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Threefold");
        prm.declare_entry("Ring radius", "4", Patterns::Double(0), "R [mm].");
        prm.declare_entry("Tube radius", "0.5", Patterns::Double(0), "r [mm].");
        prm.declare_entry("Wave height", "0.8", Patterns::Double(0), "h of z = h cos 6 (t - 15 deg) [mm].");
        prm.declare_entry("Spacing", "5.657", Patterns::Double(0), "D, triangular lattice spacing [mm].");
        prm.declare_entry("Segments", "96", Patterns::Integer(48), "Centreline segments per ring.");
        prm.leave_subsection();
      }

      explicit ThreefoldPattern(ParameterHandler &prm)
      {
        prm.enter_subsection("Threefold");
        d.R = prm.get_double("Ring radius"), d.r = prm.get_double("Tube radius");
        d.h = prm.get_double("Wave height"), d.D = prm.get_double("Spacing");
        d.segments = prm.get_integer("Segments");
        prm.leave_subsection();
      }

      dim::Pattern pattern(const double density) const override { return dim::threefold_pattern(d, density); }

    private:
      dim::ThreefoldDimensions d;
    };
  } // namespace

  NLMECH_REGISTER_PATTERN(threefold, PatternInfo{"threefold",
                                                 "threefold_pattern.cc0",
                                                 {&ThreefoldPattern::declare_parameters},
                                                 [](ParameterHandler &prm) -> std::unique_ptr<PatternPlugin> {
                                                   return std::make_unique<ThreefoldPattern>(prm);
                                                 }})
} // namespace nlmech
