#include <nlmech/models/dynamics/spring_network.h>

#include <memory>

namespace nlmech
{
  Model make_duffing_model(const double mass, const double stiffness, const double cubic)
  {
    Model             model(2);
    SpringElements<1> springs;
    Spring<1>         s;
    s.a = 0, s.b = 1, s.stiffness = stiffness, s.cubic = cubic, s.axial = true, s.direction = {{1.0}};
    springs.springs.push_back(s);
    model.add_term(std::make_shared<SpringTerm<1>>("Duffing spring", springs));
    model.lumped_mass() = Eigen::VectorXd::Constant(2, mass);
    model.fix(0, 0.0);
    return model;
  }

  Model make_two_spring_mass_model(const double mass, const double stiffness, const double cubic,
                                   const double span, const double rest_length)
  {
    Model             model(6);
    SpringElements<2> springs;
    for (const unsigned int anchor : {0u, 2u})
      {
        Spring<2> s;
        s.a = anchor, s.b = 1, s.stiffness = stiffness, s.cubic = cubic, s.rest_length = rest_length;
        springs.springs.push_back(s);
      }
    model.add_term(std::make_shared<SpringTerm<2>>("springs", springs));
    model.lumped_mass() = Eigen::VectorXd::Constant(6, mass);
    model.fix(0, -span), model.fix(1, 0.0), model.fix(4, span), model.fix(5, 0.0);
    return model;
  }

  template class ElementEnergyTerm<SpringElements<1>>;
  template class ElementEnergyTerm<SpringElements<2>>;
} // namespace nlmech
