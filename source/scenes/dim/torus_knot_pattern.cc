// Pattern "torus knot" (subsection Material/Torus knot).

#include <nlmech/scenes/dim/pattern_plugin.h>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    class TorusKnotPattern : public PatternPlugin
    {
    public:
      static void declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Torus knot");
        prm.declare_entry("p", "3", Patterns::Integer(1), "Turns around the symmetry axis.");
        prm.declare_entry("q", "4", Patterns::Integer(1), "Turns around the tube (q-fold symmetry).");
        prm.declare_entry("Ring radius", "4", Patterns::Double(0), "R [mm].");
        prm.declare_entry("Knot offset", "1.5", Patterns::Double(0),
                          "a, radius of the winding about the core [mm].");
        prm.declare_entry("Tube radius", "0.5", Patterns::Double(0), "r [mm].");
        prm.declare_entry("Spacing", "9.5", Patterns::Double(0), "D, square lattice spacing [mm].");
        prm.declare_entry("Phase", "0", Patterns::Double(), "Rotation of every element about z [deg].");
        prm.declare_entry("Segments", "192", Patterns::Integer(8), "Centreline segments per element.");
        prm.leave_subsection();
      }

      explicit TorusKnotPattern(ParameterHandler &prm)
      {
        prm.enter_subsection("Torus knot");
        d.p = prm.get_integer("p"), d.q = prm.get_integer("q"), d.R = prm.get_double("Ring radius");
        d.a = prm.get_double("Knot offset"), d.r = prm.get_double("Tube radius");
        d.D = prm.get_double("Spacing"), d.phase = prm.get_double("Phase") * dim_units::degree;
        d.segments = prm.get_integer("Segments");
        prm.leave_subsection();
      }

      dim::Pattern pattern(const double density) const override
      {
        return dim::torus_knot_pattern(d, density);
      }

    private:
      dim::TorusKnotDimensions d;
    };
  } // namespace

  NLMECH_REGISTER_PATTERN(torus_knot,
                          PatternInfo{"torus knot",
                                      "torus_knot_pattern.cc0",
                                      {&TorusKnotPattern::declare_parameters},
                                      [](ParameterHandler &prm) -> std::unique_ptr<PatternPlugin> {
                                        return std::make_unique<TorusKnotPattern>(prm);
                                      }})
} // namespace nlmech
