#include <deal.II/base/exceptions.h>

#include <nlmech/dim/characterization.h>
#include <nlmech/solvers/newton/newton_solver.h>

#include <Eigen/Dense>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace nlmech::dim
{
  namespace
  {
    std::pair<Eigen::Vector2d, Eigen::Vector2d> principal_frame(const double theta)
    {
      return {Eigen::Vector2d(std::cos(theta), std::sin(theta)), Eigen::Vector2d(-std::sin(theta), std::cos(theta))};
    }

    TestOutcome minimise(const Model &model, const RigidAssembly &assembly, Eigen::VectorXd &q,
                         const NativeSolveSettings &settings, const std::string &what)
    {
      const auto     start = std::chrono::steady_clock::now();
      NewtonSettings newton;
      newton.max_iterations = settings.max_iterations;
      newton.step_tolerance = settings.step_tolerance;
      newton.grow_shift_on_short_steps = std::getenv("NLMECH_DIM_GROW") != nullptr;
      newton.shift_metric              = assembly.motion_metric(q);
      TestOutcome outcome;
      try
        {
          const auto result  = minimize_with_newton(model, q, newton);
          outcome.iterations = result.iterations;
        }
      catch (const std::exception &e)
        {
          AssertThrow(false, dealii::ExcMessage(what + ": the native-scale solve failed: " + e.what()));
        }
      outcome.seconds      = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      outcome.smallest_gap = assembly.smallest_gap(q, settings.contact.separation + settings.contact.dhat).gap;
      outcome.principal    = q[assembly.parameter_index(0)];
      outcome.orthogonal   = q[assembly.parameter_index(1)];
      return outcome;
    }
  } // namespace

  Eigen::Vector3d green_strain(const Eigen::Matrix2d &F)
  {
    const Eigen::Matrix2d E = 0.5 * (F.transpose() * F - Eigen::Matrix2d::Identity());
    return {E(0, 0), E(1, 1), E(0, 1)};
  }

  Eigen::Vector3d green_strain(const double theta, const double eps_p, const double eps_o)
  {
    const auto [dp, d_o] = principal_frame(theta);
    const Eigen::Matrix2d U = Eigen::Matrix2d::Identity() + eps_p * dp * dp.transpose() + eps_o * d_o * d_o.transpose();
    return green_strain(U);
  }

  Eigen::Vector3d curvature_tensor(const double theta, const double kappa_p, const double kappa_o)
  {
    const auto [dp, d_o] = principal_frame(theta);
    const Eigen::Matrix2d K = kappa_p * dp * dp.transpose() + kappa_o * d_o * d_o.transpose();
    return {K(0, 0), K(1, 1), K(0, 1)};
  }

  Eigen::Matrix2d cell_deformation_gradient(const Eigen::Vector2d &t1, const Eigen::Vector2d &t2,
                                            const Eigen::Vector2d &tbar1, const Eigen::Vector2d &tbar2)
  {
    Eigen::Matrix2d T, Tbar;
    T << t1, t2;
    Tbar << tbar1, tbar2;
    return T * Tbar.inverse();
  }

  double travel_metric(const double eps_stretch, const double eps_compress)
  {
    return (eps_stretch - eps_compress) / (1 + eps_compress);
  }

  InPlaneTest::InPlaneTest(const Pattern &pattern, const double theta, NativeSolveSettings s)
      : angle(theta)
      , settings(s)
  {
    const auto [dp, d_o] = principal_frame(theta);
    cell                 = periodic_cell(pattern, {dp * dp.transpose(), d_o * d_o.transpose()});
    check_initial_state(*cell.assembly, cell.q, settings.contact.separation);
    q = cell.q;
  }

  TestOutcome InPlaneTest::solve(const double target_p, const double weight_p, const double target_o,
                                 const double weight_o, const bool continue_from_last)
  {
    if (!continue_from_last)
      q = cell.q;
    const auto &assembly = *cell.assembly;
    Model       model(assembly.n_unknowns());
    model.add_term(std::make_shared<ContactBarrier>(cell.assembly, settings.contact));
    model.add_term(std::make_shared<ParameterTarget>(assembly.parameter_index(0), std::vector<double>{target_p, target_o},
                                                     std::vector<double>{weight_p, weight_o}));
    // A translation of the whole cell is a null mode: hold the first element's centre.
    for (unsigned k = 0; k < 3; ++k)
      model.fix(k, q[k]);
    std::ostringstream what;
    what << "In-plane test (theta = " << angle * 180 / M_PI << " deg, targets " << target_p << ", " << target_o << ")";
    return minimise(model, assembly, q, settings, what.str());
  }

  BendingTest::BendingTest(const Pattern &pattern, const unsigned int n_elements, const double theta,
                           NativeSolveSettings s)
      : angle(theta)
      , settings(s)
  {
    patch               = finite_patch(pattern, n_elements, PatchShape::disk, Placement::paraboloid);
    const double c      = std::cos(theta), sn = std::sin(theta);
    // (A, B, C) = A' (c^2, s^2, 2 c s) + B' (s^2, c^2, -2 c s): z = A' x'^2 + B' y'^2 in the rotated frame.
    patch.assembly->set_curvature_basis({Eigen::Vector3d(c * c, sn * sn, 2 * c * sn), Eigen::Vector3d(sn * sn, c * c, -2 * c * sn)});
    patch.q.conservativeResize(patch.assembly->n_unknowns());
    patch.q.tail(patch.assembly->n_parameters()).setZero();
    check_initial_state(*patch.assembly, patch.q, settings.contact.separation);
    q = patch.q;
    for (unsigned b = 0; b < patch.assembly->n_bodies(); ++b)
      gravity_forces.emplace_back(0, 0, -patch.assembly->shape(b).mass * settings.gravity);
  }

  TestOutcome BendingTest::solve(const double target_p, const double weight_p, const double target_o,
                                 const double weight_o, const bool continue_from_last)
  {
    if (!continue_from_last)
      q = patch.q;
    const auto &assembly = *patch.assembly;
    Model       model(assembly.n_unknowns());
    model.add_term(std::make_shared<ContactBarrier>(patch.assembly, settings.contact));
    model.add_term(std::make_shared<CentreForces>(patch.assembly, gravity_forces));
    // Parameters are A', B' = kappa / 2.
    model.add_term(std::make_shared<ParameterTarget>(assembly.parameter_index(0),
                                                     std::vector<double>{0.5 * target_p, 0.5 * target_o},
                                                     std::vector<double>{weight_p, weight_o}));
    // Centres stay on the paraboloid; the central element holds the patch in place.
    for (unsigned b = 0; b < assembly.n_bodies(); ++b)
      model.fix(6 * b + 2, 0.0);
    model.fix(0, q[0]), model.fix(1, q[1]), model.fix(5, q[5]);
    std::ostringstream what;
    what << "Bending test (theta = " << angle * 180 / M_PI << " deg, targets " << target_p << ", " << target_o << ")";
    TestOutcome outcome = minimise(model, assembly, q, settings, what.str());
    outcome.principal *= 2, outcome.orthogonal *= 2;
    return outcome;
  }
} // namespace nlmech::dim
