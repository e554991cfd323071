#pragma once
// The time-domain reference of harmonic balance: Newmark (beta = 1/4, gamma = 1/2) on the same
// equations of motion, to the periodic steady state with the period-difference criterion (thesis
// 2.5.1).

#include <nlmech/solvers/hbm/harmonic_balance.h>

#include <Eigen/Dense>

namespace dealii
{
  class ParameterHandler;
}

namespace nlmech
{
  struct NewmarkSettings
  {
    unsigned int steps_per_period = 1024;
    double       period_tolerance = 1e-7; // e_p of (2.5.1), relative to the trajectory's size
    unsigned int max_periods      = 10000;
    double       newton_tolerance = 1e-12; // relative

    /// "Steps per period" and "Period tolerance" in the current subsection.
    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(const dealii::ParameterHandler &prm);
  };

  struct NewmarkResult
  {
    bool            converged = false;
    unsigned int    periods = 0, newton_iterations = 0;
    double          period_difference = 0; // relative e_p of the last period
    double          seconds           = 0;
    Eigen::MatrixXd last_period; // full positions at t_i = i T / steps, i = 0..steps-1
  };

  /// Integrates the same equations of motion in time from (x0, v0) (full length) until two
  /// successive periods differ by less than the tolerance.
  NewmarkResult newmark_steady_state(const HarmonicBalance &hb, double omega, const Eigen::VectorXd &x0,
                                     const Eigen::VectorXd &v0, const NewmarkSettings &settings = {});
} // namespace nlmech
