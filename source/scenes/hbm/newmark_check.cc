// The harmonic-balance scene's time-domain check: Newmark (beta 1/4, gamma 1/2) to the periodic
// steady state at chosen frequencies against the HBM state there (thesis 2.5.1).

#include <deal.II/base/exceptions.h>
#include <deal.II/base/numbers.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/base/json.h>
#include <nlmech/base/run_context.h>
#include <nlmech/scenes/hbm/response_output.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
  } // namespace

  /// HBM state reached from rest (Newton from the linear response) against Newmark from rest.
  void newmark_checks(RunContext &context, const HarmonicBalance &hb, const PeriodicStructure &st,
                      const HarmonicBalanceSceneSettings &settings)
  {
    context.summary.add_number("newmark_check_frequencies", double(settings.check_frequencies.size()));
    if (settings.check_frequencies.empty())
      {
        context.pcout << "Newmark check: off (opt-in: set `Frequencies` in subsection `Newmark check`)"
                      << std::endl;
        return;
      }
    TimerOutput::Scope t(context.timer, "Newmark checks");
    std::ostringstream table, trajectories;
    table << "omega,hbm_half_range,newmark_half_range,max_difference_relative,newmark_periods,newmark_"
             "seconds\n";
    trajectories << "omega,t,x_hbm,x_newmark\n";
    double worst = 0;
    for (const double w : settings.check_frequencies)
      {
        // Oscillators: Newmark from rest (the transient decays to the stable state; HBM is then
        // started from Newmark's last period, so both are on the same branch). Shells: a flat
        // sheet started from rest is a hard Newton problem in the first steps, so Newmark starts
        // from the HBM state (thesis 2.5.1 does either) and must stay on it.
        const Eigen::VectorXd x_rest  = st.rest;
        const std::size_t     tracked = st.tracked;
        Eigen::VectorXd       z       = hb.static_coefficients(x_rest);
        Eigen::VectorXd       x0 = x_rest, v0 = Eigen::VectorXd::Zero(x_rest.size());
        if (!st.newmark_from_rest)
          {
            const PeriodicSolveResult r = solve_with_excitation_ramp(hb, z, w);
            AssertThrow(r.converged,
                        ExcMessage("HBM found no periodic state at w = " + std::to_string(w) + "."));
            x0 = hb.positions_at(z, w, {0.0}).col(0), v0 = hb.velocities_at(z, w, {0.0}).col(0);
          }
        const NewmarkResult nm = newmark_steady_state(hb, w, x0, v0, settings.newmark);
        if (!nm.converged)
          {
            context.fail_check("Newmark did not reach a periodic steady state at w = " + std::to_string(w) +
                               " rad/s in " + std::to_string(nm.periods) + " periods");
            continue;
          }
        if (st.newmark_from_rest)
          {
            std::vector<double> t(settings.newmark.steps_per_period);
            const std::size_t   n = hb.n_free();
            for (std::size_t i = 0; i < n; ++i)
              for (unsigned int kk = 0; kk <= hb.n_harmonics(); ++kk)
                {
                  double s = 0, c = 0;
                  for (unsigned int j = 0; j < t.size(); ++j)
                    {
                      const double th = 2 * dealii::numbers::PI * j / t.size(),
                                   x  = nm.last_period(hb.free()[i], j);
                      s += x * std::sin(kk * th), c += x * std::cos(kk * th);
                    }
                  if (kk == 0)
                    z[i] = c / t.size();
                  else
                    z[(2 * kk - 1) * n + i] = 2 * s / t.size(), z[(2 * kk) * n + i] = 2 * c / t.size();
                }
            const PeriodicSolveResult r = solve_periodic_state(hb, z, w);
            AssertThrow(r.converged,
                        ExcMessage("HBM found no periodic state at w = " + std::to_string(w) + "."));
          }
        std::vector<double> t(settings.newmark.steps_per_period);
        for (unsigned int j = 0; j < t.size(); ++j)
          t[j] = 2 * dealii::numbers::PI / w * j / t.size();
        const Eigen::MatrixXd x    = hb.positions_at(z, w, t);
        const double          size = hb.half_range(z, w, tracked);
        const double diff = (x.row(tracked) - nm.last_period.row(tracked)).lpNorm<Eigen::Infinity>() / size;
        worst             = std::max(worst, diff);
        const double nm_half =
            0.5 * (nm.last_period.row(tracked).maxCoeff() - nm.last_period.row(tracked).minCoeff());
        table << json_number(w) << "," << json_number(size) << "," << json_number(nm_half) << ","
              << json_number(diff) << "," << nm.periods << "," << json_number(nm.seconds) << "\n";
        for (unsigned int j = 0; j < t.size(); j += std::max(1u, unsigned(t.size() / 128)))
          trajectories << json_number(w) << "," << json_number(t[j]) << "," << json_number(x(tracked, j))
                       << "," << json_number(nm.last_period(tracked, j)) << "\n";
        context.pcout << "Newmark check at w = " << w << ": " << nm.periods << " periods, HBM vs Newmark "
                      << diff << " relative" << std::endl;
        if (!(diff <= settings.newmark_tolerance))
          context.fail_check("the HBM and Newmark trajectories at w = " + std::to_string(w) +
                             " rad/s differ by " + std::to_string(diff) + " of the half range (tolerance " +
                             std::to_string(settings.newmark_tolerance) + ")");
      }
    context.summary.add_figure("newmark_max_difference_relative", worst, "1");
    if (context.is_root())
      {
        write_file_atomically(context.output.file("newmark_check.csv"), table.str());
        write_file_atomically(context.output.file("trajectories.csv"), trajectories.str());
      }
  }

} // namespace nlmech
