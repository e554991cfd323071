// Structures "duffing" (m x'' + c x' + k x + k3 x^3 = F cos(w t)) and "two-spring-mass" (a mass
// between two anchors joined by geometric springs, forced across the span): the lumped
// oscillators, with their parameters in subsection Oscillator.

#include <deal.II/base/exceptions.h>

#include <nlmech/models/dynamics/spring_network.h>
#include <nlmech/scenes/hbm/structure.h>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    /// subsection Oscillator, the lumped oscillators' entries.
    struct OscillatorSettings
    {
      double mass = 1, stiffness = 1, cubic_stiffness = 1, force = 0.5;

      static void declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Oscillator");
        prm.declare_entry("Mass", "1", Patterns::Double(0), "m [kg].");
        prm.declare_entry("Stiffness", "1", Patterns::Double(0), "k, per spring [N/m].");
        prm.declare_entry("Cubic stiffness", "1", Patterns::Double(), "k3, per spring [N/m^3].");
        prm.declare_entry("Force amplitude", "0.5", Patterns::Double(0), "F [N].");
        prm.leave_subsection();
      }

      void parse_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Oscillator");
        mass = prm.get_double("Mass"), stiffness = prm.get_double("Stiffness");
        cubic_stiffness = prm.get_double("Cubic stiffness"), force = prm.get_double("Force amplitude");
        prm.leave_subsection();
        AssertThrow(mass > 0, ExcMessage("Mass must be positive."));
      }
    };

    /// subsection Oscillator, the two-spring mass's geometry.
    struct SpanSettings
    {
      double span = 1, rest_length = 0.8;

      static void declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Oscillator");
        prm.declare_entry("Span", "1", Patterns::Double(0), "two-spring-mass: half the anchor distance [m].");
        prm.declare_entry("Rest length", "0.8", Patterns::Double(0), "two-spring-mass: L0 [m].");
        prm.leave_subsection();
      }

      void parse_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Oscillator");
        span = prm.get_double("Span"), rest_length = prm.get_double("Rest length");
        prm.leave_subsection();
      }
    };

    /// The force on the tracked unknown, the state at rest, the Newmark check from rest.
    PeriodicStructure oscillator(Model model, const std::size_t tracked, const double force)
    {
      PeriodicStructure s;
      s.model             = std::move(model);
      s.tracked           = tracked;
      s.forces            = {{tracked, force, 0.0}};
      s.tracked_dofs      = {tracked};
      s.newmark_from_rest = true;
      s.point_dofs        = [tracked](const Point<3> &) { return std::vector<std::size_t>{tracked}; };
      s.point_distance    = [](const Point<3> &) { return 0.0; }; // one mass: every point selects it
      s.rest              = Eigen::VectorXd::Zero(s.model.n_unknowns());
      for (const auto &f : s.model.fixed())
        s.rest[f.first] = f.second;
      return s;
    }

    class DuffingStructure : public StructurePlugin
    {
    public:
      explicit DuffingStructure(ParameterHandler &prm) { oscillator_settings.parse_parameters(prm); }

      PeriodicStructure build(RunContext &, const HarmonicBalanceSettings &,
                              const ExcitationSettings &) override
      {
        const auto &o = oscillator_settings;
        return oscillator(make_duffing_model(o.mass, o.stiffness, o.cubic_stiffness), 1, o.force);
      }

    private:
      OscillatorSettings oscillator_settings;
    };

    class TwoSpringMassStructure : public StructurePlugin
    {
    public:
      explicit TwoSpringMassStructure(ParameterHandler &prm)
      {
        oscillator_settings.parse_parameters(prm);
        span_settings.parse_parameters(prm);
      }

      PeriodicStructure build(RunContext &, const HarmonicBalanceSettings &,
                              const ExcitationSettings &) override
      {
        const auto &o = oscillator_settings;
        return oscillator(make_two_spring_mass_model(o.mass, o.stiffness, o.cubic_stiffness,
                                                     span_settings.span, span_settings.rest_length),
                          3, o.force);
      }

    private:
      OscillatorSettings oscillator_settings;
      SpanSettings       span_settings;
    };
  } // namespace

  NLMECH_REGISTER_STRUCTURE(duffing,
                            StructureInfo{"duffing",
                                          "m x'' + c x' + k x + k3 x^3 = F cos(w t) (subsection Oscillator)",
                                          {&OscillatorSettings::declare_parameters},
                                          [](ParameterHandler &prm) -> std::unique_ptr<StructurePlugin> {
                                            return std::make_unique<DuffingStructure>(prm);
                                          }})
  NLMECH_REGISTER_STRUCTURE(
      two_spring_mass,
      StructureInfo{
          "two-spring-mass",
          "a mass at the middle between two anchors at distance 2 Span, joined by geometric springs "
          "of rest length L0, forced across the span (a geometric nonlinearity)",
          {&OscillatorSettings::declare_parameters, &SpanSettings::declare_parameters},
          [](ParameterHandler &prm) -> std::unique_ptr<StructurePlugin> {
            return std::make_unique<TwoSpringMassStructure>(prm);
          }})
} // namespace nlmech
