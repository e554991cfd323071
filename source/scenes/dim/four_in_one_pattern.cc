// Pattern "4-in-1" (subsection Material/4-in-1).

#include <nlmech/scenes/dim/pattern_plugin.h>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    class FourInOnePattern : public PatternPlugin
    {
    public:
      static void declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("4-in-1");
        prm.declare_entry("Ring radius", "3", Patterns::Double(0), "R, centreline radius [mm].");
        prm.declare_entry("Tube radius", "0.5", Patterns::Double(0), "r [mm].");
        prm.declare_entry("Tilt", "30", Patterns::Double(0, 80),
                          "Tilt of the rings about the column axis [deg].");
        prm.declare_entry("Column spacing", "2", Patterns::Double(0), "a [mm].");
        prm.declare_entry("Row spacing", "7.5", Patterns::Double(0), "b [mm].");
        prm.declare_entry("Segments", "64", Patterns::Integer(8), "Centreline segments per ring.");
        prm.leave_subsection();
      }

      explicit FourInOnePattern(ParameterHandler &prm)
      {
        prm.enter_subsection("4-in-1");
        d.R = prm.get_double("Ring radius"), d.r = prm.get_double("Tube radius");
        d.tilt = prm.get_double("Tilt") * dim_units::degree, d.a = prm.get_double("Column spacing");
        d.b = prm.get_double("Row spacing"), d.segments = prm.get_integer("Segments");
        prm.leave_subsection();
      }

      dim::Pattern pattern(const double density) const override
      {
        return dim::four_in_one_pattern(d, density);
      }

    private:
      dim::FourInOneDimensions d;
    };
  } // namespace

  NLMECH_REGISTER_PATTERN(four_in_one,
                          PatternInfo{"4-in-1",
                                      "four_in_one_pattern.cc0",
                                      {&FourInOnePattern::declare_parameters},
                                      [](ParameterHandler &prm) -> std::unique_ptr<PatternPlugin> {
                                        return std::make_unique<FourInOnePattern>(prm);
                                      }})
} // namespace nlmech
