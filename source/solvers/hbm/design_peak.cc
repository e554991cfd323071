// Resonance peaks as design cases (design.h): the peak found again after every parameter change,
// the peak frequency objective, and the gradient by the adjoint of the peak's extended system.
#include <deal.II/base/exceptions.h>

#include <nlmech/solvers/hbm/design.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace nlmech
{
  namespace
  {
    /// |harmonics| of z (the mean left out): the size of the motion.
    double harmonic_norm(const HarmonicBalance &hb, const Eigen::VectorXd &z)
    {
      return z.tail(z.size() - Eigen::Index(hb.n_free())).norm();
    }
  } // namespace

  PeakFrequencyObjective::PeakFrequencyObjective(const double target_in)
      : target(target_in)
  {
    AssertThrow(target > 0 && std::isfinite(target),
                dealii::ExcMessage("Peak frequency objective: the target frequency must be positive."));
  }

  double PeakFrequencyObjective::evaluate(const HarmonicBalance &, const Eigen::VectorXd &z,
                                          const double omega, Eigen::VectorXd *gradient) const
  {
    if (gradient)
      gradient->setZero(z.size());
    return (omega - target) * (omega - target);
  }

  double PeakFrequencyObjective::omega_derivative(const HarmonicBalance &, const Eigen::VectorXd &,
                                                  const double omega) const
  {
    return 2 * (omega - target);
  }

  bool HarmonicDesign::locate_peak(const std::size_t c, std::string *why)
  {
    DesignCase     &dc = cases[c];
    Eigen::VectorXd z  = states[c];
    const double    w  = dc.omega;
    ++peak_searches;
    // dA/dw along the curve through the state: uphill is where the peak lies.
    Eigen::VectorXd gA;
    const double    A = hb->amplitude(z, w, dc.peak_dofs, &gA);
    lu.factorize(hb->jacobian(z, w));
    factorized_case             = -1; // at the state before the peak moved
    const Eigen::VectorXd phi   = -lu.solve(hb->d_residual_d_omega(z, w));
    const double          slope = gA.dot(phi);
    if (!std::isfinite(slope))
      {
        if (why)
          *why = "the curve's slope at w = " + std::to_string(w) + " rad/s is not finite (dh/dz singular)";
        return false;
      }
    // Still the peak (the parameters did not change it): dA/dw vanishes to the refinement's level.
    if (std::abs(slope) * w <= 1e-10 * A)
      return true;
    ContinuationSettings cs;
    cs.omega_start = w, cs.omega_end = slope > 0 ? dc.omega_high : dc.omega_low;
    cs.tracked_dofs          = dc.peak_dofs;
    cs.stability             = StabilityMethod::none;
    cs.stop_after_first_peak = true;
    cs.max_step              = settings.peak_search_step;
    cs.initial_step          = std::min(cs.initial_step, cs.max_step);
    cs.relative_tolerance    = settings.solve.relative_tolerance;
    cs.max_points            = 500;
    FrequencyResponse frc;
    try
      {
        frc = trace_frequency_response(*hb, z, cs);
      }
    catch (const std::exception &e)
      {
        if (why)
          *why = std::string("the peak search failed (") + e.what() + ")";
        return false;
      }
    peak_search_points += unsigned(frc.points.size());
    if (frc.peaks.empty() || !frc.peaks.front().z.allFinite())
      {
        if (why)
          *why = "no resonance peak in [" + std::to_string(dc.omega_low) + ", " +
                 std::to_string(dc.omega_high) + "] rad/s uphill from w = " + std::to_string(w) +
                 " rad/s (the curve " +
                 (frc.completed ? "reached the window's end" : "stopped: " + frc.stop_reason) + ")";
        return false;
      }
    dc.omega  = frc.peaks.front().omega;
    states[c] = frc.peaks.front().z;
    return true;
  }

  Eigen::VectorXd HarmonicDesign::peak_gradient(const std::size_t c, const Eigen::VectorXd &df_dz,
                                                const double df_dw)
  {
    // Unknowns y = (z, phi, w), residual R = (h, h_z phi + h_w, grad A . phi), objective J(z, w).
    // dJ/dp = -Lambda^T R_p with R_y^T Lambda = (J_z, 0, J_w). With b = h_z^-T grad A (the
    // amplitude's adjoint), alpha = h_z^-T J_z, B = d/de h_z(z + e phi, w + e),
    // c = d/de h_w(z + e phi, w + e) and beta = h_z^-T (grad^2 A phi - B^T b), block elimination gives
    //   Lambda_3 = (h_w . alpha - J_w) / (h_w . beta + c . b),
    //   Lambda_2 = -Lambda_3 b,   Lambda_1 = alpha - Lambda_3 beta,
    //   dJ/dp = -Lambda_1^T h_p + Lambda_3 b^T d/de h_p(z + e phi, w + e).
    // At the peak h_w . b = -grad A . phi = 0, so for J = J(A) alone Lambda_3 = 0 (envelope theorem).
    const DesignCase      &dc        = cases[c];
    const Eigen::VectorXd &z         = states[c];
    const double           w         = dc.omega;
    const Eigen::VectorXd  hw        = hb->d_residual_d_omega(z, w);
    const Eigen::VectorXd  alpha     = lu.solve(df_dz, true);
    const double           numerator = hw.dot(alpha) - df_dw;
    if (std::abs(numerator) <= 1e-14 * (hw.norm() * alpha.norm() + std::abs(df_dw)))
      return -adjoint_parameter_products(*hb, parameters, z, w, alpha); // Lambda_3 = 0

    Eigen::VectorXd gA;
    hb->amplitude(z, w, dc.peak_dofs, &gA);
    const Eigen::VectorXd b   = lu.solve(gA, true);
    const Eigen::VectorXd phi = -lu.solve(hw);
    // Directional derivatives along (phi, 1) by central differences of exact derivatives: a step
    // changing w and the motion by about 1e-6 of themselves.
    const double          zn  = std::max(harmonic_norm(*hb, z), 1e-300);
    const double          eps = 1e-6 * w / std::max(1.0, w * harmonic_norm(*hb, phi) / zn);
    const Eigen::VectorXd zp = z + eps * phi, zm = z - eps * phi;
    const double          wp = w + eps, wm = w - eps;
    const Eigen::VectorXd BTb =
        (hb->jacobian(zp, wp).transpose() * b - hb->jacobian(zm, wm).transpose() * b) / (2 * eps);
    const Eigen::VectorXd cw = (hb->d_residual_d_omega(zp, wp) - hb->d_residual_d_omega(zm, wm)) / (2 * eps);
    Eigen::VectorXd       gAp, gAm;
    hb->amplitude(zp, wp, dc.peak_dofs, &gAp);
    hb->amplitude(zm, wm, dc.peak_dofs, &gAm);
    const Eigen::VectorXd beta        = lu.solve((gAp - gAm) / (2 * eps) - BTb, true);
    const double          denominator = hw.dot(beta) + cw.dot(b);
    AssertThrow(std::isfinite(denominator) && denominator != 0,
                dealii::ExcMessage("Design: the resonance peak at w = " + std::to_string(w) +
                                   " rad/s is degenerate (d^2A/dw^2 = 0): its frequency has no derivative."));
    const double    lambda3 = numerator / denominator;
    Eigen::VectorXd g       = -adjoint_parameter_products(*hb, parameters, z, w, alpha - lambda3 * beta);
    g += lambda3 *
         (adjoint_parameter_products(*hb, parameters, zp, wp, b) -
          adjoint_parameter_products(*hb, parameters, zm, wm, b)) /
         (2 * eps);
    return g;
  }
} // namespace nlmech
