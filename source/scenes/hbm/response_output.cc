// Output and studies of the harmonic-balance scene: the frequency-response table with harmonic
// coefficients and its plot, one period (the tracked point's trajectory, then the structure's own
// output), evaluation frequencies, the backbone and the Newmark check.

#include <deal.II/base/exceptions.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/base/json.h>
#include <nlmech/base/plot.h>
#include <nlmech/base/run_context.h>
#include <nlmech/scenes/hbm/response_output.h>
#include <nlmech/solvers/hbm/backbone.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    constexpr double pi = 3.14159265358979323846;
  } // namespace

  /// Header of the harmonic coefficients of the tracked unknowns: x(t) = c0 + sum_k (cos_k cos(k w t)
  /// + sin_k sin(k w t)), abs_k = sqrt(cos_k^2 + sin_k^2), per tracked unknown (its index).
  std::string harmonics_header(const HarmonicBalance &hb, const PeriodicStructure &s)
  {
    std::string header;
    for (const std::size_t d : s.tracked_dofs)
      {
        const std::string u = ",x" + std::to_string(d) + "_";
        header += u + "c0";
        for (unsigned int k = 1; k <= hb.n_harmonics(); ++k)
          header +=
              u + "cos" + std::to_string(k) + u + "sin" + std::to_string(k) + u + "abs" + std::to_string(k);
      }
    return header;
  }

  std::string harmonics_row(const HarmonicBalance &hb, const PeriodicStructure &s, const Eigen::VectorXd &z)
  {
    std::string       row;
    const auto       &free = hb.free();
    const std::size_t n    = hb.n_free();
    for (const std::size_t d : s.tracked_dofs)
      {
        const auto        it      = std::find(free.begin(), free.end(), d);
        const bool        is_free = it != free.end();
        const std::size_t i       = is_free ? std::size_t(it - free.begin()) : 0;
        // A fixed or driven unknown has no coefficients of its own: its static value, zeros.
        row += "," + json_number(is_free ? z[Eigen::Index(i)] : s.rest[Eigen::Index(d)]);
        for (unsigned int k = 1; k <= hb.n_harmonics(); ++k)
          {
            const double sk = is_free ? z[Eigen::Index((2 * k - 1) * n + i)] : 0.0;
            const double ck = is_free ? z[Eigen::Index(2 * k * n + i)] : 0.0;
            row += "," + json_number(ck) + "," + json_number(sk) + "," + json_number(std::hypot(ck, sk));
          }
      }
    return row;
  }

  /// The periodic state at each evaluation frequency, on its own: from the nearest point of the
  /// curve, or from rest with the excitation ramped up.
  void evaluate_frequencies(RunContext &context, const HarmonicBalance &hb, const PeriodicStructure &s,
                            const FrequencyResponse &frc, const HarmonicBalanceSceneSettings &settings)
  {
    if (settings.evaluation_frequencies.empty())
      return;
    TimerOutput::Scope t(context.timer, "evaluation frequencies");
    std::ostringstream csv;
    csv << "omega,amplitude_A,half_range,converged,iterations,relative_residual,start"
        << harmonics_header(hb, s) << "\n";
    unsigned int failed = 0;
    for (const double w : settings.evaluation_frequencies)
      {
        Eigen::VectorXd z = start_coefficients(hb, s);
        std::string     start =
            s.start_motion.empty() ? "rest, excitation ramped" : "rigid drive motion, excitation ramped";
        if (!frc.points.empty())
          {
            const auto nearest = std::min_element(frc.points.begin(), frc.points.end(),
                                                  [&](const ResponsePoint &a, const ResponsePoint &b) {
                                                    return std::abs(a.omega - w) < std::abs(b.omega - w);
                                                  });
            z                  = nearest->z;
            start              = "curve point at w = " + json_number(nearest->omega);
          }
        PeriodicSolveSettings ps;
        ps.relative_tolerance = settings.continuation.relative_tolerance;
        PeriodicSolveResult r = frc.points.empty() ? solve_with_excitation_ramp(hb, z, w, ps)
                                                   : solve_periodic_state(hb, z, w, ps);
        if (!r.converged && !frc.points.empty())
          {
            z = start_coefficients(hb, s), start = s.start_motion.empty()
                                                       ? "rest, excitation ramped"
                                                       : "rigid drive motion, excitation ramped";
            r = solve_with_excitation_ramp(hb, z, w, ps);
          }
        failed += !r.converged;
        csv << json_number(w) << "," << json_number(hb.amplitude(z, w, s.tracked_dofs)) << ","
            << json_number(hb.half_range(z, w, s.tracked)) << "," << r.converged << "," << r.iterations << ","
            << json_number(r.residual) << "," << start << harmonics_row(hb, s, z) << "\n";
        context.pcout << "evaluation at w = " << w << " rad/s: "
                      << (r.converged ? "half range " + json_number(hb.half_range(z, w, s.tracked))
                                      : "no periodic state found (" + r.message + ")")
                      << std::endl;
      }
    context.summary.add_number("settings.evaluation_frequencies", settings.evaluation_frequencies.size());
    context.summary.add_number("evaluation_failures", failed);
    if (context.is_root())
      write_file_atomically(context.output.file("evaluation.csv"), csv.str());
    if (failed > 0 && context.partial_reason.empty())
      context.partial_reason = std::to_string(failed) + " evaluation frequencies found no periodic state";
  }

  /// The backbone of the undamped, unforced structure (the nonlinear normal mode) by amplitude.
  void trace_backbone_curve(RunContext &context, const PeriodicStructure &s,
                            const HarmonicBalanceSceneSettings &settings)
  {
    if (settings.backbone_amplitudes.empty())
      return;
    TimerOutput::Scope t(context.timer, "backbone");
    AssertThrow(s.drives.empty(),
                ExcMessage("Backbone: the structure is driven (its drives fix unknowns); the backbone needs "
                           "a structure loaded by forces only."));
    HarmonicBalanceSettings free_settings = settings.harmonic_balance;
    free_settings.rayleigh_mass = free_settings.rayleigh_stiffness = 0;
    const HarmonicBalance hb(s.model, free_settings);
    const auto            it = std::find(hb.free().begin(), hb.free().end(), s.tracked);
    AssertThrow(it != hb.free().end(), ExcMessage("Backbone: the tracked unknown is not free."));
    BackboneSettings b;
    b.reference = std::size_t(it - hb.free().begin());
    b.mode      = settings.backbone_mode;
    b.tolerance = settings.continuation.relative_tolerance;
    std::string                      stop;
    const std::vector<BackbonePoint> points =
        trace_backbone(hb, s.rest, settings.backbone_amplitudes, b, &stop);
    std::ostringstream csv;
    csv << "amplitude_cos1,omega,half_range,amplitude_A,gauss_newton_iterations,relative_residual"
        << harmonics_header(hb, s) << "\n";
    for (const auto &p : points)
      csv << json_number(p.amplitude) << "," << json_number(p.omega) << ","
          << json_number(hb.half_range(p.z, p.omega, s.tracked)) << ","
          << json_number(hb.amplitude(p.z, p.omega, s.tracked_dofs)) << "," << p.iterations << ","
          << json_number(p.residual) << harmonics_row(hb, s, p.z) << "\n";
    context.summary.add_number("backbone_points", points.size());
    if (!points.empty())
      context.summary.add_figure("backbone_last_frequency", points.back().omega, "rad/s");
    context.pcout << "backbone (mode " << settings.backbone_mode << "): " << points.size() << " of "
                  << settings.backbone_amplitudes.size() << " amplitudes" << (stop.empty() ? "" : "; " + stop)
                  << std::endl;
    if (context.is_root())
      write_file_atomically(context.output.file("backbone.csv"), csv.str());
    if (!stop.empty() && context.partial_reason.empty())
      context.partial_reason = "backbone: " + stop;
  }

  void write_response(RunContext &context, const HarmonicBalance &hb, const PeriodicStructure &s,
                      const FrequencyResponse &frc, const std::vector<std::pair<double, double>> &lma,
                      const std::string &model_name)
  {
    std::ostringstream csv, peaks;
    csv << "omega,amplitude_A,half_range,stable,fold,max_floquet_multiplier,corrector_iterations";
    if (!lma.empty())
      csv << ",lma_amplitude_A,lma_half_range";
    csv << "\n";
    unsigned int folds = 0, unstable = 0, undetermined = 0, hill = 0;
    for (std::size_t i = 0; i < frc.points.size(); ++i)
      {
        const auto &p = frc.points[i];
        csv << json_number(p.omega) << "," << json_number(p.amplitude) << ","
            << json_number(hb.half_range(p.z, p.omega, s.tracked)) << "," << p.stable << "," << p.fold << ","
            << json_number(p.max_multiplier) << "," << p.iterations;
        if (!lma.empty())
          csv << "," << json_number(lma[i].first) << "," << json_number(lma[i].second);
        csv << "\n";
        folds += p.fold, unstable += p.stable == 0, undetermined += p.stable < 0, hill += p.hill;
      }
    std::ostringstream harmonics;
    harmonics << "point,omega" << harmonics_header(hb, s) << "\n";
    for (std::size_t i = 0; i < frc.points.size(); ++i)
      harmonics << i << "," << json_number(frc.points[i].omega) << harmonics_row(hb, s, frc.points[i].z)
                << "\n";
    peaks << "omega,amplitude_A,half_range\n";
    for (const auto &p : frc.peaks)
      peaks << json_number(p.omega) << "," << json_number(p.amplitude) << ","
            << json_number(hb.half_range(p.z, p.omega, s.tracked)) << "\n";
    context.summary.add_number("points", frc.points.size());
    context.summary.add_number("folds", folds);
    context.summary.add_number("unstable_points", unstable);
    context.summary.add_number("stability_undetermined_points", undetermined);
    context.summary.add_string("stability_method", undetermined == frc.points.size() ? "none"
                                                   : hill > 0                        ? "hill"
                                                                                     : "floquet");
    context.summary.add_figure("stability_time", frc.stability_seconds, "s");
    context.summary.add_number("resonance_peaks", frc.peaks.size());
    if (!frc.peaks.empty())
      {
        context.summary.add_figure("first_peak_frequency", frc.peaks.front().omega, "rad/s");
        context.summary.add_figure("first_peak_half_range",
                                   hb.half_range(frc.peaks.front().z, frc.peaks.front().omega, s.tracked),
                                   "m");
      }
    if (!lma.empty())
      {
        // The HBM-to-LMA ratio of the tracked half range where the motion is smallest (the
        // nearly linear end) and at the first peak frequency.
        std::size_t smallest = 0;
        for (std::size_t i = 0; i < frc.points.size(); ++i)
          if (frc.points[i].amplitude < frc.points[smallest].amplitude)
            smallest = i;
        const auto &p = frc.points[smallest];
        if (lma[smallest].second > 0)
          context.summary.add_figure("hbm_over_lma_at_smallest_motion",
                                     hb.half_range(p.z, p.omega, s.tracked) / lma[smallest].second, "1");
      }
    context.summary.add_number("continuation_factorizations", frc.factorizations);
    context.summary.add_number("continuation_rejected_steps", frc.rejected_steps);
    context.summary.add_number("residual_evaluations", frc.residuals);
    context.summary.add_number("jacobian_evaluations", frc.jacobians);
    context.summary.add_figure("continuation_time", frc.seconds, "s");
    context.summary.add_figure("residual_time", frc.residual_seconds, "s");
    context.summary.add_figure("jacobian_time", frc.jacobian_seconds, "s");
    context.summary.add_figure("factorization_time", frc.factorization_seconds, "s");
    context.summary.add_figure("solve_time", frc.solve_seconds, "s");
    context.pcout << "frequency response: " << frc.points.size() << " points, " << folds << " folds, "
                  << frc.peaks.size() << " resonance peak(s)" << std::endl;
    if (context.is_root())
      {
        write_file_atomically(context.output.file("frequency_response.csv"), csv.str());
        write_file_atomically(context.output.file("resonance_peaks.csv"), peaks.str());
        write_file_atomically(context.output.file("harmonics.csv"), harmonics.str());
        run_plot("frequency_response.py",
                 {context.output.file("frequency_response.csv"),
                  context.output.file("frequency_response.png"),
                  "HBM frequency response (" + model_name + ")", context.output.file("resonance_peaks.csv")});
      }
  }

  void write_period(RunContext &context, const HarmonicBalance &hb, const PeriodicStructure &s,
                    const StructurePlugin &plugin, const Eigen::VectorXd &z, const double w,
                    const unsigned int period_frames)
  {
    std::vector<double> times;
    for (unsigned int f = 0; f < period_frames; ++f)
      times.push_back(2 * pi / w * f / period_frames);
    const Eigen::MatrixXd x = hb.positions_at(z, w, times);
    context.summary.add_figure("period_frames_frequency", w, "rad/s");
    {
      std::vector<double> fine(256);
      for (unsigned int j = 0; j < fine.size(); ++j)
        fine[j] = 2 * pi / w * j / fine.size();
      const Eigen::MatrixXd xf = hb.positions_at(z, w, fine);
      std::ostringstream    csv;
      csv << "t,x,y,z\n";
      for (unsigned int j = 0; j < fine.size(); ++j)
        {
          csv << json_number(fine[j]);
          for (unsigned int i = 0; i < 3; ++i)
            csv << "," << json_number(i < s.tracked_dofs.size() ? xf(s.tracked_dofs[i], j) : 0.0);
          csv << "\n";
        }
      write_file_atomically(context.output.file("trajectory.csv"), csv.str());
      std::ostringstream title;
      title << "tracked point over one period at w = " << w << " rad/s";
      run_plot("trajectory.py",
               {context.output.file("trajectory.csv"), context.output.file("trajectory.png"), title.str()});
    }
    plugin.write_period(context, s, times, x);
  }
} // namespace nlmech
