#include <deal.II/base/exceptions.h>

#include <nlmech/models/dynamics/mechanism.h>
#include <nlmech/models/dynamics/spring_network.h>

#include <algorithm>

namespace nlmech
{
  namespace
  {
    double distance(const std::array<double, 2> &a, const std::array<double, 2> &b)
    {
      return std::hypot(b[0] - a[0], b[1] - a[1]);
    }
  } // namespace

  MechanismModel make_mechanism_model(const MechanismDescription &d)
  {
    const std::size_t n = d.joints.size();
    AssertThrow(n >= 2 && d.masses.size() == n,
                dealii::ExcMessage("A mechanism needs at least two joints and one mass per joint."));
    for (const double m : d.masses)
      AssertThrow(m > 0, dealii::ExcMessage("Every joint mass must be positive."));
    AssertThrow(d.link_stiffness > 0 && d.angle_stiffness >= 0,
                dealii::ExcMessage("The link penalty must be positive and the angle penalty not negative."));
    MechanismModel mech;
    mech.model = Model(2 * n);
    mech.rest_positions.resize(2 * n);
    Eigen::VectorXd gravity = Eigen::VectorXd::Zero(2 * n);
    for (std::size_t j = 0; j < n; ++j)
      {
        mech.rest_positions[2 * j] = d.joints[j][0], mech.rest_positions[2 * j + 1] = d.joints[j][1];
        mech.model.lumped_mass()[2 * j] = mech.model.lumped_mass()[2 * j + 1] = d.masses[j];
        gravity[2 * j + 1]                                                    = -d.masses[j] * d.gravity;
      }
    SpringElements<2> links;
    for (const auto &l : d.links)
      {
        AssertThrow(l[0] < n && l[1] < n && l[0] != l[1],
                    dealii::ExcMessage("A link joins a missing joint or a joint to itself."));
        const double length = distance(d.joints[l[0]], d.joints[l[1]]);
        AssertThrow(length > 0, dealii::ExcMessage("A link has zero length."));
        Spring<2> s;
        s.a = l[0], s.b = l[1], s.rest_length = length, s.stiffness = d.link_stiffness;
        links.springs.push_back(s);
      }
    JointAngleElements angles;
    angles.stiffness = d.angle_stiffness;
    for (const auto &a : d.rigid_angles)
      {
        AssertThrow(a[0] < n && a[1] < n && a[2] < n,
                    dealii::ExcMessage("A rigid joint refers to a missing joint."));
        std::array<double, 6> X;
        for (int v = 0; v < 3; ++v)
          X[2 * v] = d.joints[a[v]][0], X[2 * v + 1] = d.joints[a[v]][1];
        angles.joints.push_back(a);
        angles.rest_angle.push_back(JointAngleElements::angle(X));
      }
    AttachedSpringElements springs;
    for (const auto &s : d.springs)
      {
        AssertThrow(s.link_a < d.links.size() && s.link_b < d.links.size(),
                    dealii::ExcMessage("A spring is attached to a missing link."));
        AssertThrow(s.stiffness >= 0, dealii::ExcMessage("A spring stiffness is negative."));
        const auto &la = d.links[s.link_a], &lb = d.links[s.link_b];
        springs.ends.push_back({{la[0], la[1], lb[0], lb[1]}});
        springs.local.push_back({{s.u_a, s.w_a, s.u_b, s.w_b}});
        springs.stiffness.push_back(s.stiffness);
        std::array<double, 8> X;
        for (int v = 0; v < 4; ++v)
          X[2 * v] = d.joints[springs.ends.back()[v]][0], X[2 * v + 1] = d.joints[springs.ends.back()[v]][1];
        double p[2], q[2];
        AttachedSpringElements::attachment(X, 0, s.u_a, s.w_a, p);
        AttachedSpringElements::attachment(X, 1, s.u_b, s.w_b, q);
        springs.rest_length.push_back(s.rest_length >= 0 ? s.rest_length
                                                         : std::hypot(q[0] - p[0], q[1] - p[1]));
      }
    mech.model.add_term(std::make_shared<SpringTerm<2>>("rigid links (penalty)", links));
    if (!angles.joints.empty())
      mech.model.add_term(
          std::make_shared<ElementEnergyTerm<JointAngleElements>>("rigid joints (penalty)", angles));
    if (!springs.ends.empty())
      mech.model.add_term(
          std::make_shared<ElementEnergyTerm<AttachedSpringElements>>("link springs", springs));
    if (d.gravity != 0)
      mech.model.add_term(std::make_shared<ConstantForceTerm>("gravity", gravity));
    return mech;
  }

  std::array<double, 2> mechanism_constraint_violation(const MechanismDescription &d,
                                                       const Eigen::VectorXd      &x)
  {
    std::array<double, 2> worst = {{0, 0}};
    auto at = [&](unsigned int j) { return std::array<double, 2>{{x[2 * j], x[2 * j + 1]}}; };
    for (const auto &l : d.links)
      worst[0] = std::max(
          worst[0], std::abs(distance(at(l[0]), at(l[1])) / distance(d.joints[l[0]], d.joints[l[1]]) - 1));
    for (const auto &a : d.rigid_angles)
      {
        std::array<double, 6> X, X0;
        for (int v = 0; v < 3; ++v)
          X[2 * v] = x[2 * a[v]], X[2 * v + 1] = x[2 * a[v] + 1], X0[2 * v] = d.joints[a[v]][0],
                X0[2 * v + 1] = d.joints[a[v]][1];
        worst[1] = std::max(worst[1], std::abs(JointAngleElements::angle(X) - JointAngleElements::angle(X0)));
      }
    return worst;
  }

  template class ElementEnergyTerm<JointAngleElements>;
  template class ElementEnergyTerm<AttachedSpringElements>;
} // namespace nlmech
