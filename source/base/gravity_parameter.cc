#include <deal.II/base/parameter_handler.h>

#include <nlmech/base/gravity_parameter.h>
#include <nlmech/base/parse.h>

namespace nlmech
{
  void GravityParameter::declare_parameters(dealii::ParameterHandler &prm, const unsigned int components,
                                            const std::string &note)
  {
    const std::string tail = note.empty() ? "" : "; " + note;
    if (components == 1)
      prm.declare_entry("Gravity", "9.81", dealii::Patterns::Double(),
                        "Gravitational acceleration" + tail + " [m/s^2].");
    else
      prm.declare_entry("Gravity", "0, 0, -9.81", dealii::Patterns::Anything(),
                        "Gravitational acceleration vector, " +
                            (components == 0 ? std::string("one component per space dimension")
                                             : std::to_string(components) + " components") +
                            tail + " [m/s^2].");
  }

  std::vector<double> GravityParameter::parse_parameters(const dealii::ParameterHandler &prm,
                                                         const unsigned int              components)
  {
    const std::vector<double> g = parse_number_list(prm.get("Gravity"), "Gravity");
    AssertThrow(g.size() == components,
                dealii::ExcMessage("The entry <Gravity> needs " + std::to_string(components) + " component" +
                                   (components == 1 ? "" : "s") + "; it has " + std::to_string(g.size()) +
                                   "."));
    return g;
  }
} // namespace nlmech
