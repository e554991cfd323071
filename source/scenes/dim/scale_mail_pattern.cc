// Pattern "scale mail" (subsection Material/Scale mail).

#include <nlmech/scenes/dim/pattern_plugin.h>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    class ScaleMailPattern : public PatternPlugin
    {
    public:
      static void declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Scale mail");
        prm.declare_entry("Ring radius", "4", Patterns::Double(0), "R of the base ring [mm].");
        prm.declare_entry("Tube radius", "0.5", Patterns::Double(0), "r [mm].");
        prm.declare_entry("Wave height", "0.8", Patterns::Double(0), "h of the base ring [mm].");
        prm.declare_entry("Spacing", "5.657", Patterns::Double(0), "D [mm].");
        prm.declare_entry("Plate radius", "2.45", Patterns::Double(0), "Hexagon circumradius [mm].");
        prm.declare_entry("Plate thickness", "0.8", Patterns::Double(0), "[mm].");
        prm.declare_entry("Plate height", "2.3", Patterns::Double(0),
                          "Plate mid-plane above the ring plane [mm].");
        prm.declare_entry("Segments", "96", Patterns::Integer(48), "Centreline segments per ring.");
        prm.leave_subsection();
      }

      explicit ScaleMailPattern(ParameterHandler &prm)
      {
        prm.enter_subsection("Scale mail");
        d.R = prm.get_double("Ring radius"), d.r = prm.get_double("Tube radius");
        d.h = prm.get_double("Wave height"), d.D = prm.get_double("Spacing");
        d.plate_radius    = prm.get_double("Plate radius"),
        d.plate_thickness = prm.get_double("Plate thickness");
        d.plate_height = prm.get_double("Plate height"), d.segments = prm.get_integer("Segments");
        prm.leave_subsection();
      }

      dim::Pattern pattern(const double density) const override
      {
        return dim::scale_mail_pattern(d, density);
      }

    private:
      dim::ScaleMailDimensions d;
    };
  } // namespace

  NLMECH_REGISTER_PATTERN(scale_mail,
                          PatternInfo{"scale mail",
                                      "scale_mail_pattern.cc0",
                                      {&ScaleMailPattern::declare_parameters},
                                      [](ParameterHandler &prm) -> std::unique_ptr<PatternPlugin> {
                                        return std::make_unique<ScaleMailPattern>(prm);
                                      }})
} // namespace nlmech
