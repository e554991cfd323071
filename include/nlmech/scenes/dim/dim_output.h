#pragma once
// What the dim-characterization scene writes besides its boundaries and plots: the samples of a
// test as CSV, and VTU of the periodic cell at rest and at its stretch limit along x.

#include <nlmech/dim/characterization.h>
#include <nlmech/dim/patterns.h>

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace nlmech
{
  class RunContext;

  /// samples-<test>.csv (rank 0 only): every sample with its target, outcome and strain point.
  void write_samples_csv(RunContext &context, const std::string &test,
                         const std::vector<dim::Sample> &samples);

  /// summary.json: the number of directions, the limits along x (stretch, compression, bending
  /// either way, only what was sampled), the range of travel c and the bending asymmetry.
  void report_directional_limits(RunContext &context, const std::vector<dim::DirectionalLimits> &stretch,
                                 const std::vector<dim::DirectionalLimits> &bend);

  /// cell-rest.vtu and cell-stretch-limit.vtu, 3 x 3 images of the cell; `at_limit` is the state at
  /// the stretch limit from this run's sample, solved again (to `far_strain`) when it is empty (the
  /// sample came from the checkpoint or another rank).
  void write_cell_states(RunContext &context, const dim::Pattern &pattern,
                         const dim::NativeSolveSettings &settings, double far_strain,
                         const Eigen::VectorXd &at_limit);
} // namespace nlmech
