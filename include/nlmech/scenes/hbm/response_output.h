#pragma once
// What the harmonic-balance scene writes and checks besides the curve itself (each a function of
// the HBM system, the structure and the scene's settings).

#include <nlmech/scenes/hbm/scene_settings.h>
#include <nlmech/scenes/hbm/structure.h>
#include <nlmech/solvers/hbm/harmonic_balance.h>
#include <nlmech/solvers/hbm/periodic_solvers.h>

#include <string>
#include <utility>
#include <vector>

namespace nlmech
{
  class RunContext;

  /// CSV header of the harmonic coefficients of the tracked unknowns: x(t) = c0 + sum_k (cos_k
  /// cos(k w t) + sin_k sin(k w t)), abs_k = sqrt(cos_k^2 + sin_k^2), per tracked unknown (its index).
  std::string harmonics_header(const HarmonicBalance &hb, const PeriodicStructure &s);
  /// The coefficients of z in the order of harmonics_header.
  std::string harmonics_row(const HarmonicBalance &hb, const PeriodicStructure &s, const Eigen::VectorXd &z);

  /// frequency_response.csv (with the linear modal reference `lma`: amplitude and half range per
  /// point, or empty), resonance_peaks.csv, harmonics.csv, the plot and the curve's figures.
  void write_response(RunContext &context, const HarmonicBalance &hb, const PeriodicStructure &s,
                      const FrequencyResponse &frc, const std::vector<std::pair<double, double>> &lma,
                      const std::string &model_name);

  /// One period at frequency w: trajectory.csv and .png of the tracked point, then the structure's
  /// own output (VTU frames, joint or rod positions).
  void write_period(RunContext &context, const HarmonicBalance &hb, const PeriodicStructure &s,
                    const StructurePlugin &plugin, const Eigen::VectorXd &z, double w,
                    unsigned int period_frames);

  /// evaluation.csv: the periodic state at each evaluation frequency, on its own.
  void evaluate_frequencies(RunContext &context, const HarmonicBalance &hb, const PeriodicStructure &s,
                            const FrequencyResponse &frc, const HarmonicBalanceSceneSettings &settings);

  /// backbone.csv: the undamped, unforced periodic solutions (the nonlinear normal mode) by amplitude.
  void trace_backbone_curve(RunContext &context, const PeriodicStructure &s,
                            const HarmonicBalanceSceneSettings &settings);

  /// newmark_check.csv and trajectories.csv: Newmark to the periodic steady state against HBM; a
  /// disagreement beyond the tolerance is a failed check of the run.
  void newmark_checks(RunContext &context, const HarmonicBalance &hb, const PeriodicStructure &st,
                      const HarmonicBalanceSceneSettings &settings);
} // namespace nlmech
