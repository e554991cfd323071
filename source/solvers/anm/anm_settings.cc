#include <deal.II/base/exceptions.h>

#include <nlmech/solvers/anm/anm_solver.h>

namespace nlmech
{
  using namespace dealii;

  void AnmSettings::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("ANM order", "20", Patterns::Integer(2, 31), "Truncation order n of the series [-].");
    prm.declare_entry("Series tolerance", "1e-6", Patterns::Double(0),
                      "r of the step-length rule a_r = (r |x_1| / |x_n|)^(1/(n-1)) (paper eqs. 19-20) [-].");
    prm.declare_entry(
        "Residual tolerance", "1e-9", Patterns::Double(0),
        "Final equilibrium: |residual| <= tol |load| on the free unknowns, for every method [-].");
    prm.declare_entry("Path tolerance", "1e-6", Patterns::Double(0),
                      "ANM corrections between steps only above this relative residual [-].");
    prm.declare_entry(
        "Pade approximants", "false", Patterns::Bool(),
        "Follow the branch with Pade approximants (common denominator) where they reach further "
        "than the series; anm_steps.csv gives both radii per step.");
  }

  void AnmSettings::parse_parameters(ParameterHandler &prm)
  {
    order              = unsigned(prm.get_integer("ANM order"));
    series_tolerance   = prm.get_double("Series tolerance");
    residual_tolerance = prm.get_double("Residual tolerance");
    path_tolerance     = prm.get_double("Path tolerance");
    pade               = prm.get_bool("Pade approximants");
    AssertThrow(residual_tolerance > 0 && series_tolerance > 0 && series_tolerance < 1,
                ExcMessage("The ANM tolerances must be positive (and the series tolerance below 1)."));
  }
} // namespace nlmech
