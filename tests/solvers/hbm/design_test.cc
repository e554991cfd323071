// Harmonic-balance design against independent references: the adjoint gradient (2.4.5) against
// central differences of the objective with the state re-solved, for every parameter kind and both
// objectives; the sensitivity S (2.4.3) against re-solved states; first-order predictions whose
// error falls like |dp|^2; a mass tuned to resonance whose optimum is known in closed form.
#include <nlmech/base/nearest_point.h>
#include <nlmech/models/dynamics/mechanism.h>
#include <nlmech/models/dynamics/spring_network.h>
#include <nlmech/solvers/hbm/design.h>
#include <nlmech/solvers/hbm/design_parameters.h>
#include <nlmech/solvers/newton/newton_solver.h>

#include "hbm_test_helpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

using namespace nlmech;

namespace
{
  constexpr double pi = 3.14159265358979323846;

  /// A structure's parts the parameters change, and its harmonic balance settings.
  struct Setup
  {
    Model                      model{0};
    std::vector<HarmonicForce> forces;
    std::vector<HarmonicDrive> drives;
    HarmonicBalanceSettings    settings;
    Eigen::VectorXd            rest;

    HarmonicDesign::Rebuild rebuild()
    {
      return [this]() { return std::make_unique<HarmonicBalance>(model, settings, forces, drives); };
    }
    Eigen::VectorXd solved(double omega)
    {
      const HarmonicBalance hb(model, settings, forces, drives);
      Eigen::VectorXd       z = hb.static_coefficients(rest);
      EXPECT_TRUE(solve_with_excitation_ramp(hb, z, omega).converged);
      return z;
    }
  };

  /// The forced Duffing oscillator m x'' + 0.1 m x' + k x + k3 x^3 = F cos(w t + phi).
  std::unique_ptr<Setup> duffing(double k3)
  {
    auto s                    = std::make_unique<Setup>();
    s->model                  = make_duffing_model(1.0, 1.0, k3);
    s->forces                 = {{1, 0.3, 0.2}};
    s->settings.n_harmonics   = 5;
    s->settings.rayleigh_mass = 0.1;
    s->rest                   = Eigen::VectorXd::Zero(2);
    return s;
  }

  /// The soft plane square of hbm_test_helpers shaken at its base, with mass and stiffness damping.
  std::unique_ptr<Setup> strip(nlmech::testing::ShakenStrip &shaken)
  {
    auto s                         = std::make_unique<Setup>();
    s->model                       = shaken.solid.model;
    s->drives                      = shaken.drives;
    s->settings.n_harmonics        = 3;
    s->settings.rayleigh_mass      = 0.5;
    s->settings.rayleigh_stiffness = 2e-3;
    s->rest                        = shaken.solid.rest_positions;
    return s;
  }

  /// The shaken strip with a point mass at its top and the drive amplitude as parameters, the top's
  /// amplitude as objective at 2.5 rad/s, states solved tightly.
  struct TopMassAndDrive
  {
    nlmech::testing::ShakenStrip                  shaken = nlmech::testing::shaken_strip(0.01, 0.0);
    std::unique_ptr<Setup>                        s      = strip(shaken);
    std::vector<std::shared_ptr<DesignParameter>> parameters;
    std::unique_ptr<HarmonicDesign>               design;

    TopMassAndDrive()
    {
      const std::size_t top = nearest_point(shaken.m.vertices, dealii::Point<3>(0.5, 1.0, 0.0));
      parameters.push_back(
          make_point_mass_parameter("mass", s->model, {2 * top, 2 * top + 1}, 2e-3, 0.0, 0.1));
      parameters.push_back(make_drive_amplitude_parameter("drive", s->drives, 0.1, 3.0));
      DesignCase c;
      c.omega = 2.5;
      c.objectives.push_back(std::make_shared<AmplitudeObjective>(std::vector<std::size_t>{2 * top}, 1.0));
      DesignSettings ds;
      ds.solve.relative_tolerance = 1e-13;
      design = std::make_unique<HarmonicDesign>(s->rebuild(), parameters, std::vector<DesignCase>{c},
                                                std::vector<Eigen::VectorXd>{s->solved(c.omega)}, ds);
    }
  };

  /// Largest difference between the adjoint gradient and central differences of the objective
  /// (states re-solved at p +- h e_k, h relative to the bounds), relative to the largest gradient entry.
  double gradient_error(HarmonicDesign &design, double relative_step = 1e-5)
  {
    const Eigen::VectorXd p = design.values();
    Eigen::VectorXd       g;
    design.objective(&g);
    double worst = 0;
    for (Eigen::Index k = 0; k < p.size(); ++k)
      {
        const auto     &param = *design.design_parameters()[std::size_t(k)];
        const double    h     = relative_step * std::max(std::abs(p[k]), 1e-2 * (param.upper - param.lower));
        Eigen::VectorXd q     = p;
        q[k]                  = p[k] + h;
        EXPECT_TRUE(design.update(q));
        const double fp = design.objective();
        q[k]            = p[k] - h;
        EXPECT_TRUE(design.update(q));
        const double fm = design.objective();
        const double fd = (fp - fm) / (2 * h);
        std::printf("  %-18s adjoint % .10e  central % .10e\n", param.name().c_str(), g[k], fd);
        worst = std::max(worst, std::abs(fd - g[k]));
      }
    EXPECT_TRUE(design.update(p));
    return worst / std::max(g.lpNorm<Eigen::Infinity>(), 1e-300);
  }

  Eigen::MatrixXd ellipse(double a, double b, unsigned int samples, unsigned int rows)
  {
    Eigen::MatrixXd x(rows, samples);
    for (unsigned int i = 0; i < samples; ++i)
      {
        const double t = 2 * pi * i / samples;
        x(0, i)        = a * std::cos(t) + 0.1 * a * std::sin(3 * t);
        if (rows > 1)
          x(1, i) = b * std::sin(t);
      }
    return x;
  }
} // namespace

TEST(HarmonicDesign, DuffingAdjointGradientsMatchCentralDifferences)
{
  // Point mass (with its weight under gravity: the weight shifts the cubic spring's mean
  // stretch, so the motion depends on it), force amplitude factor, force phase and the spring's
  // stiffness (the term's modulus), on the amplitude and on the trajectory objective, with a
  // change penalty.
  for (const bool trajectory : {false, true})
    {
      auto s = duffing(0.5);
      // A static preload makes the state asymmetric: at zero mean load the amplitude would be even
      // in the weight and its derivative zero, and a weight missing from the model would go unseen.
      s->model.add_term(std::make_shared<ConstantForceTerm>("preload", Eigen::Vector2d(0.0, -0.5)));
      std::vector<std::shared_ptr<DesignParameter>> p;
      p.push_back(
          make_point_mass_parameter("mass", s->model, {1}, 0.2, 0.0, 2.0, Eigen::Vector2d(0.0, -2.0)));
      p.push_back(make_force_amplitude_parameter("force", s->forces, {0}, 0.1, 3.0));
      p.push_back(make_force_phase_parameter("phase", s->forces, {0}, -pi, pi));
      p.push_back(make_term_modulus_parameter("stiffness", s->model, 0, 1.0, 0.1, 10.0));
      p[1]->set(1.2), p[2]->set(0.3), p[3]->set(1.5);
      const double omega = 1.1;
      DesignCase   c;
      c.omega = omega;
      if (trajectory)
        c.objectives.push_back(
            std::make_shared<TrajectoryObjective>(std::vector<std::size_t>{1}, ellipse(0.8, 0, 64, 1), 5));
      else
        c.objectives.push_back(std::make_shared<AmplitudeObjective>(std::vector<std::size_t>{1}, 10.0));
      DesignSettings ds;
      ds.change_penalty           = 0.01;
      ds.solve.relative_tolerance = 1e-13; // the differences need states far below their step
      HarmonicDesign design(s->rebuild(), p, {c}, {s->solved(omega)}, ds);
      std::printf("Duffing, %s objective:\n", trajectory ? "trajectory" : "amplitude");
      const double error = gradient_error(design);
      std::printf("  largest relative difference %.2e\n", error);
      EXPECT_LT(error, 1e-6);
    }
}

TEST(HarmonicDesign, StripAdjointGradientsMatchCentralDifferences)
{
  // A plane solid with a prescribed base motion and stiffness damping: a point mass at the top,
  // the drive's amplitude factor, and Young's moduli of the lower and upper half of the elements;
  // two driving frequencies at once for the trajectory objective.
  for (const bool trajectory : {false, true})
    {
      auto                     shaken = nlmech::testing::shaken_strip(0.01, 0.0);
      auto                     s      = strip(shaken);
      const std::size_t        top    = nearest_point(shaken.m.vertices, dealii::Point<3>(0.5, 1.0, 0.0));
      std::vector<std::size_t> lower, upper;
      for (std::size_t e = 0; e < shaken.m.cells.size(); ++e)
        {
          double y = 0;
          for (const unsigned int v : shaken.m.cells[e])
            y += shaken.m.vertices[v][1] / 3;
          (y < 0.5 ? lower : upper).push_back(e);
        }
      std::vector<std::shared_ptr<DesignParameter>> p;
      p.push_back(make_point_mass_parameter("mass", s->model, {2 * top, 2 * top + 1}, 1e-3, 0.0, 0.1));
      p.push_back(make_drive_amplitude_parameter("drive", s->drives, 0.1, 3.0));
      for (auto &m : make_element_modulus_parameters("E", s->model, {lower, upper}, {1e4, 1e4}, 0.1, 10.0))
        p.push_back(m);
      p[3]->set(1.3e4);
      const std::vector<std::size_t> tracked = {2 * top, 2 * top + 1};
      std::vector<DesignCase>        cases;
      std::vector<Eigen::VectorXd>   states;
      for (const double omega : trajectory ? std::vector<double>{2.0, 3.0} : std::vector<double>{2.5})
        {
          DesignCase c;
          c.omega = omega;
          if (trajectory)
            c.objectives.push_back(
                std::make_shared<TrajectoryObjective>(tracked, ellipse(0.03, 0.005, 48, 2), 3));
          else
            c.objectives.push_back(std::make_shared<AmplitudeObjective>(tracked, 1.0));
          cases.push_back(c);
          states.push_back(s->solved(omega));
        }
      DesignSettings ds;
      ds.solve.relative_tolerance = 1e-13;
      HarmonicDesign design(s->rebuild(), p, cases, states, ds);
      std::printf("plane strip, %s objective:\n", trajectory ? "trajectory (2 frequencies)" : "amplitude");
      const double error = gradient_error(design);
      std::printf("  largest relative difference %.2e\n", error);
      EXPECT_LT(error, 1e-6);
    }
}

TEST(HarmonicDesign, SensitivityMatchesResolvedStatesAndPredictionErrorIsQuadratic)
{
  TopMassAndDrive       strip_design;
  HarmonicDesign       &design = *strip_design.design;
  const auto           &p      = strip_design.parameters;
  const Eigen::VectorXd p0 = design.values(), z0 = design.state(0);
  const Eigen::MatrixXd S = design.sensitivity(0);
  // Columns against central differences of re-solved states.
  for (Eigen::Index k = 0; k < p0.size(); ++k)
    {
      const double    h = 1e-4 * std::max(std::abs(p0[k]), 1e-2);
      Eigen::VectorXd q = p0;
      q[k] += h;
      ASSERT_TRUE(design.update(q));
      const Eigen::VectorXd zp = design.state(0);
      q[k] -= 2 * h;
      ASSERT_TRUE(design.update(q));
      const Eigen::VectorXd fd    = (zp - design.state(0)) / (2 * h);
      const double          error = (fd - S.col(k)).norm() / S.col(k).norm();
      std::printf("S column %s: relative difference %.2e\n", p[std::size_t(k)]->name().c_str(), error);
      EXPECT_LT(error, 1e-6);
    }
  // The first-order prediction z + S dp (2.4.4) along a compound direction: its error against the
  // re-solved state falls like |dp|^2 and is below 1 % of the motion at small steps.
  const Eigen::VectorXd direction = Eigen::Vector2d(5e-3, 0.2);
  const double          size      = z0.tail(z0.size() - Eigen::Index(design.balance().n_free())).norm();
  std::vector<double>   errors;
  for (const double t : {0.4, 0.2, 0.1, 0.05})
    {
      ASSERT_TRUE(design.update(p0 + t * direction));
      const double error = (design.state(0) - z0 - S * (t * direction)).norm() / size;
      errors.push_back(error);
      std::printf("prediction at step %.3f: error %.3e of the motion\n", t, error);
    }
  for (std::size_t i = 1; i < errors.size(); ++i)
    EXPECT_NEAR(std::log2(errors[i - 1] / errors[i]), 2.0, 0.25);
  EXPECT_LT(errors.back(), 1e-2);
}

TEST(HarmonicDesign, RepeatedSolvesStartFromTheFirstOrderPrediction)
{
  // After a gradient, the factorisation at the state predicts the next design's state as
  // z - (dh/dz)^-1 dh/dp dp, i.e. z + S dp with S from sensitivity() (a second route: one solve per
  // parameter column); the update then starts there, lands on the state a re-solve from the last
  // state finds, and the prediction is off by O(|dp|^2) only. A prediction needs the
  // factorisation at the current state: after the update (new state) there is none.
  TopMassAndDrive       strip_design;
  HarmonicDesign       &design = *strip_design.design;
  const Eigen::VectorXd p0 = design.values(), z0 = design.state(0);
  const Eigen::MatrixXd S = design.sensitivity(0);
  Eigen::VectorXd       g;
  design.objective(&g);
  const Eigen::VectorXd dp        = Eigen::Vector2d(1e-3, 0.05);
  const auto            predicted = design.predicted_states(p0 + dp);
  ASSERT_EQ(predicted.size(), 1u);
  ASSERT_EQ(predicted[0].size(), z0.size());
  const double size  = (S * dp).norm();
  const double route = (predicted[0] - z0 - S * dp).norm() / size;
  std::printf("prediction against z + S dp: relative difference %.2e\n", route);
  EXPECT_LT(route, 1e-9);
  ASSERT_TRUE(design.update(p0 + dp));
  EXPECT_EQ(design.predicted_starts, 1u);
  EXPECT_EQ(design.failed_predictions, 0u);
  const Eigen::VectorXd from_prediction = design.state(0);
  const double          off             = (from_prediction - predicted[0]).norm() / size;
  std::printf("prediction against the re-solved state: %.2e of the change\n", off);
  EXPECT_LT(off, 0.05);
  EXPECT_EQ(design.predicted_states(p0)[0].size(), 0);
  // The same design solved from the last state (no factorisation at hand: the update starts there).
  ASSERT_TRUE(design.update(p0));
  ASSERT_TRUE(design.update(p0 + dp));
  const double same = (design.state(0) - from_prediction).norm() / from_prediction.norm();
  std::printf("state from the prediction against the state from the last one: %.2e\n", same);
  EXPECT_LT(same, 1e-10);
}

TEST(HarmonicDesign, MassTunedToResonanceHasTheClosedFormOptimum)
{
  // m x'' + a m x' + k x = F cos(w t): the amplitude F / sqrt((k - m w^2)^2 + (a m w)^2) is largest
  // for m = k / (w^2 + a^2). Start from m = 0.3 (plus the oscillator's 1 kg... here 0.2 kg base) and
  // maximise the amplitude by L-BFGS over an added mass.
  auto s                                              = duffing(0.0);
  s->model                                            = make_duffing_model(0.2, 1.0, 0.0);
  const double                                  omega = 1.3, a = 0.1, k = 1.0;
  std::vector<std::shared_ptr<DesignParameter>> p = {
      make_point_mass_parameter("mass", s->model, {1}, 0.1, 0.0, 2.0)};
  DesignCase c;
  c.omega = omega;
  c.objectives.push_back(std::make_shared<AmplitudeObjective>(std::vector<std::size_t>{1}, 100.0));
  HarmonicDesign       design(s->rebuild(), p, {c}, {s->solved(omega)});
  OptimizationSettings os;
  os.relative_tolerance          = 1e-14;
  const OptimizationResult r     = optimize_design(design, os);
  const double             exact = k / (omega * omega + a * a) - 0.2;
  std::printf("tuned mass: %.10f (closed form %.10f), %u evaluations, %s\n", design.values()[0], exact,
              r.evaluations, r.stop_reason.c_str());
  EXPECT_NEAR(design.values()[0], exact, 1e-6 * exact);
  // The amplitude there is the closed-form peak: A = 4 X for a pure cosine.
  const double m = exact + 0.2;
  const double X = 0.3 / std::sqrt(std::pow(k - m * omega * omega, 2) + std::pow(a * m * omega, 2));
  EXPECT_NEAR(design.balance().amplitude(design.state(0), omega, {1}), 4 * X, 1e-8 * X);
}

TEST(HarmonicDesign, RejectsInvertedBoundsAndBadTargets)
{
  auto s = duffing(0.5);
  EXPECT_THROW(make_point_mass_parameter("mass", s->model, {1}, 0.1, 1.0, 0.5), std::exception);
  EXPECT_THROW(make_point_mass_parameter("mass", s->model, {1}, 0.1, -1.0, 0.5), std::exception);
  EXPECT_THROW(TrajectoryObjective({1}, Eigen::MatrixXd::Zero(1, 64), 5), std::exception); // does not move
  EXPECT_THROW(TrajectoryObjective({1}, ellipse(1, 0, 8, 1), 5), std::exception);          // too short
  Eigen::MatrixXd bad = ellipse(1, 0, 64, 1);
  bad(0, 3)           = std::nan("");
  EXPECT_THROW(TrajectoryObjective({1}, bad, 5), std::exception);
  // An initial value outside the bounds.
  std::vector<std::shared_ptr<DesignParameter>> p = {
      make_point_mass_parameter("mass", s->model, {1}, 0.1, 0.0, 2.0)};
  p[0]->set(3.0);
  DesignCase c;
  c.omega = 1.0;
  c.objectives.push_back(std::make_shared<AmplitudeObjective>(std::vector<std::size_t>{1}, 1.0));
  EXPECT_THROW(HarmonicDesign(s->rebuild(), p, {c}, {Eigen::VectorXd::Zero(11)}), std::exception);
}

TEST(HarmonicDesign, ParameterContinuationFollowsTheStateAroundFolds)
{
  // The forced hardening Duffing at w = 2.2 beyond the fold of its curve: the small-amplitude state
  // of F = 0.3. Raised to F = 3.6 at fixed w, that branch ends at a fold (the jump up); the state
  // over F is an S: forwards to the fold, back along the unstable middle branch to the other fold,
  // forwards on the large branch. The parameter continuation must pass both folds and end on the
  // large-amplitude state at F = 3.6, which the frequency-response curve of F = 3.6 traced from
  // w = 0.5 (a second method) reaches at w = 2.2 too.
  auto                                          s     = duffing(1.0);
  const double                                  omega = 2.2;
  std::vector<std::shared_ptr<DesignParameter>> p     = {
          make_force_amplitude_parameter("force", s->forces, {0}, 0.1, 20.0)};
  DesignCase c;
  c.omega = omega;
  c.objectives.push_back(std::make_shared<AmplitudeObjective>(std::vector<std::size_t>{1}, 100.0));
  HarmonicDesign design(s->rebuild(), p, {c}, {s->solved(omega)});
  const double   small = design.balance().amplitude(design.state(0), omega, {1});
  std::string    why;
  ASSERT_TRUE(design.continue_to(Eigen::VectorXd::Constant(1, 12.0), &why)) << why;
  const double A = design.balance().amplitude(design.state(0), omega, {1});
  std::printf("continuation in F: amplitude %.6f -> %.10f, %u steps, %u folds\n", small, A,
              design.continuation_steps, design.continuation_folds);
  EXPECT_EQ(design.continuation_folds, 2u);
  EXPECT_NEAR(design.values()[0], 12.0, 1e-14);
  const Eigen::VectorXd h = design.balance().residual(design.state(0), omega);
  EXPECT_LT(h.lpNorm<Eigen::Infinity>(), 1e-9 * 3.6);

  ContinuationSettings cs;
  cs.omega_start = 0.5, cs.omega_end = omega, cs.tracked_dofs = {1}, cs.stability = StabilityMethod::none;
  cs.relative_tolerance       = 1e-12;
  const HarmonicBalance  &hb  = design.balance();
  const FrequencyResponse frc = trace_frequency_response(hb, hb.static_coefficients(s->rest), cs);
  ASSERT_TRUE(frc.completed);
  const double reference = frc.points.back().amplitude;
  std::printf("  the frequency-response curve of F = 3.6 at w = 2.2: %.10f\n", reference);
  EXPECT_NEAR(A, reference, 1e-7 * reference);
  EXPECT_GT(A, 20 * small);
}

TEST(HarmonicDesign, MechanismSpringAndWeightGradientsMatchCentralDifferences)
{
  // A shaken planar leg under gravity (models/dynamics/mechanism.h) with stiffness damping: a
  // spring's stiffness, another's rest length, attachment coordinates on both ends' links, an
  // added joint mass with its weight and two link lengths (one changed from the built geometry);
  // amplitude and trajectory of the toe.
  MechanismDescription d;
  d.joints         = {{{0, 0}}, {{-0.06, 0}}, {{0.03, -0.12}}, {{-0.02, -0.24}}, {{0.06, -0.27}}};
  d.masses         = {0.01, 0.01, 0.03, 0.02, 0.01};
  d.links          = {{{0, 1}}, {{0, 2}}, {{2, 3}}, {{3, 4}}};
  d.springs        = {{0, 2, 1.0, 0.0, 0.3, 0.0, 70.2, 0.146}, {2, 3, 0.2, 0.0, 1.0, 0.0, 16.0, 0.088}};
  d.link_stiffness = 1e4, d.angle_stiffness = 10, d.gravity = 9.81;
  for (const bool trajectory : {false, true})
    {
      const MechanismModel mech = make_mechanism_model(d);
      auto                 s    = std::make_unique<::Setup>();
      s->model                  = mech.model;
      s->settings.n_harmonics   = 5;
      s->settings.rayleigh_mass = 1.0, s->settings.rayleigh_stiffness = 2e-3;
      s->rest = mech.rest_positions;
      for (const std::size_t j : {0u, 1u})
        for (const std::size_t i : {0u, 1u})
          s->drives.push_back(
              {2 * j + i, i == 1 ? 0.002 : 0.0, 0.0, 0.0, s->rest[Eigen::Index(2 * j + i)], {}, {}});
      Eigen::VectorXd gravity = Eigen::VectorXd::Zero(10);
      for (Eigen::Index j = 0; j < 5; ++j)
        gravity[2 * j + 1] = -d.gravity;
      std::vector<std::shared_ptr<DesignParameter>> p;
      p.push_back(make_spring_parameter("k_0", s->model, 0, 5, 70.2, 10.0, 200.0));
      p.push_back(make_spring_parameter("L0_1", s->model, 1, 4, 0.088, 0.02, 0.2));
      p.push_back(make_spring_parameter("u_b_0", s->model, 0, 2, 0.3, 0.0, 1.0));
      p.push_back(make_spring_parameter("w_a_1", s->model, 1, 1, 0.05, -0.5, 0.5));
      p.push_back(make_point_mass_parameter("mass", s->model, {6, 7}, 0.01, 0.0, 0.1, gravity));
      p.push_back(make_link_length_parameter("L_link_2", s->model, 2, 0.14, 0.05, 0.3)); // 0.130 built
      p.push_back(make_link_length_parameter("L_link_3", s->model, 3, 0.0854, 0.05, 0.3));
      {
        Model held = s->model; // the static state under gravity, drives at their centres
        for (const auto &dr : s->drives)
          held.fix(dr.dof, dr.center);
        minimize_with_newton(held, s->rest);
      }
      const double omega = 18.85;
      DesignCase   c;
      c.omega = omega;
      if (trajectory)
        c.objectives.push_back(std::make_shared<TrajectoryObjective>(std::vector<std::size_t>{8, 9},
                                                                     ellipse(0.01, 0.004, 64, 2), 5));
      else
        c.objectives.push_back(std::make_shared<AmplitudeObjective>(std::vector<std::size_t>{8, 9}, 1.0));
      DesignSettings ds;
      ds.solve.relative_tolerance = 1e-13;
      HarmonicDesign design(s->rebuild(), p, {c}, {s->solved(omega)}, ds);
      std::printf("mechanism, %s objective:\n", trajectory ? "trajectory" : "amplitude");
      const double error = gradient_error(design);
      std::printf("  largest relative difference %.2e\n", error);
      EXPECT_LT(error, 1e-6);
    }
}

namespace
{
  /// A peak case of the Duffing's amplitude near `omega`, in [low, high].
  DesignCase peak_case(double omega, double low, double high)
  {
    DesignCase c;
    c.omega = omega, c.peak = true, c.omega_low = low, c.omega_high = high, c.peak_dofs = {1};
    return c;
  }
} // namespace

TEST(HarmonicDesign, ResonancePeakGradientsMatchCentralDifferences)
{
  // The hardening Duffing's resonance peak as the design case: its height (the envelope theorem:
  // the fixed-frequency adjoint at the peak) and its frequency (the extended system's adjoint with
  // the second derivatives along the curve), each against central differences of the objective
  // with the peak found again at p +- h. Parameters of every kind the oscillator has. The peak is
  // also checked against the frequency-response curve's own refined peak (a second method).
  for (const int kind : {0, 1, 2})
    {
      auto s                 = duffing(0.5);
      s->forces[0].amplitude = 0.05; // hardening: the peak lies above sqrt(k / m) = 0.913 rad/s
      std::vector<std::shared_ptr<DesignParameter>> p;
      p.push_back(make_point_mass_parameter("mass", s->model, {1}, 0.2, 0.0, 2.0));
      p.push_back(make_force_amplitude_parameter("force", s->forces, {0}, 0.1, 3.0));
      p.push_back(make_term_modulus_parameter("stiffness", s->model, 0, 1.0, 0.1, 10.0));
      DesignCase c = peak_case(0.93, 0.6, 1.6);
      if (kind != 1)
        c.objectives.push_back(std::make_shared<AmplitudeObjective>(std::vector<std::size_t>{1}, 10.0));
      if (kind != 0)
        c.objectives.push_back(std::make_shared<PeakFrequencyObjective>(1.5));
      const Eigen::VectorXd z0 = s->solved(0.93);
      DesignSettings        ds;
      ds.solve.relative_tolerance = 1e-13;
      HarmonicDesign design(s->rebuild(), p, {c}, {z0}, ds);
      const double   w = design.omega(0);
      std::printf("peak case %d: w* = %.10f, A* = %.10f, %u searches, %u points\n", kind, w,
                  design.balance().amplitude(design.state(0), w, {1}), design.peak_searches,
                  design.peak_search_points);
      EXPECT_GT(w, 0.93);
      const double err = gradient_error(design, 1e-4);
      std::printf("  worst relative difference %.3e\n", err);
      EXPECT_LT(err, 1e-6);

      ContinuationSettings cs;
      cs.omega_start = 0.6, cs.omega_end = 1.6, cs.tracked_dofs = {1}, cs.stability = StabilityMethod::none;
      cs.relative_tolerance       = 1e-13;
      const HarmonicBalance  &hb  = design.balance();
      const FrequencyResponse frc = trace_frequency_response(hb, hb.static_coefficients(s->rest), cs);
      ASSERT_FALSE(frc.peaks.empty());
      std::printf("  the curve's peak: w = %.10f, A = %.10f\n", frc.peaks.front().omega,
                  frc.peaks.front().amplitude);
      EXPECT_NEAR(frc.peaks.front().omega, design.omega(0), 1e-8);
      EXPECT_NEAR(frc.peaks.front().amplitude, hb.amplitude(design.state(0), design.omega(0), {1}),
                  1e-9 * frc.peaks.front().amplitude);
    }
}

TEST(HarmonicDesign, PeakPlacedAtATargetFrequencyHasTheClosedFormMass)
{
  // m x'' + a m x' + k x = F cos(w t): X(w) = F / sqrt((k - m w^2)^2 + (a m w)^2) peaks at
  // w*^2 = k / m - a^2 / 2, so the peak lies at w_t for m = k / (w_t^2 + a^2 / 2). L-BFGS moves an
  // added mass until the peak frequency objective (w* - w_t)^2 vanishes.
  auto s                                          = duffing(0.0);
  s->model                                        = make_duffing_model(0.2, 1.0, 0.0);
  const double                                  a = 0.1, k = 1.0, target = 1.3;
  std::vector<std::shared_ptr<DesignParameter>> p = {
      make_point_mass_parameter("mass", s->model, {1}, 0.1, 0.0, 2.0)};
  DesignCase c = peak_case(1.6, 0.5, 3.0); // the peak of m = 0.3: 1.825 rad/s
  c.objectives.push_back(std::make_shared<PeakFrequencyObjective>(target));
  DesignSettings ds;
  ds.solve.relative_tolerance = 1e-13;
  HarmonicDesign design(s->rebuild(), p, {c}, {s->solved(1.6)}, ds);
  const double   w0 = design.omega(0);
  EXPECT_NEAR(w0, std::sqrt(k / 0.3 - a * a / 2), 1e-9);
  OptimizationSettings os;
  os.relative_tolerance          = 1e-14;
  const OptimizationResult r     = optimize_design(design, os);
  const double             exact = k / (target * target + a * a / 2) - 0.2;
  std::printf("peak at %.10f rad/s -> %.10f; mass %.10f (closed form %.10f), %u evaluations, %s\n", w0,
              design.omega(0), design.values()[0], exact, r.evaluations, r.stop_reason.c_str());
  EXPECT_NEAR(design.omega(0), target, 1e-7);
  EXPECT_NEAR(design.values()[0], exact, 1e-6 * exact);
}

TEST(HarmonicDesign, RefusesAPeakOutsideItsWindow)
{
  // The linear oscillator's peak lies at 1.825 rad/s: a window [0.5, 1.5] holds none.
  auto s                                          = duffing(0.0);
  s->model                                        = make_duffing_model(0.2, 1.0, 0.0);
  std::vector<std::shared_ptr<DesignParameter>> p = {
      make_point_mass_parameter("mass", s->model, {1}, 0.1, 0.0, 2.0)};
  DesignCase c = peak_case(1.0, 0.5, 1.5);
  c.objectives.push_back(std::make_shared<PeakFrequencyObjective>(1.0));
  try
    {
      HarmonicDesign design(s->rebuild(), p, {c}, {s->solved(1.0)});
      ADD_FAILURE() << "no error";
    }
  catch (const std::exception &e)
    {
      std::printf("%s\n", e.what());
      EXPECT_NE(std::string(e.what()).find("no resonance peak"), std::string::npos);
    }
  // The peak frequency objective belongs to a peak's case.
  DesignCase fixed;
  fixed.omega = 1.0;
  fixed.objectives.push_back(std::make_shared<PeakFrequencyObjective>(1.0));
  EXPECT_THROW(HarmonicDesign(s->rebuild(), p, {fixed}, {s->solved(1.0)}), std::exception);
}
