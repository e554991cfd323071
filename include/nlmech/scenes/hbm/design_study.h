#pragma once
// subsection Design of the harmonic-balance scene (thesis 2.4-2.5): design parameters declared by
// kind and selection with bounds, the objective (amplitude 2.4.8 or trajectory 2.4.6-2.4.7 from a
// CSV) at one or more driving frequencies, and what is done with them: `apply` the parameters'
// values, `explore` the first-order predictions z + S dp against re-solved states along the
// objective's descent direction (error ~ |dp|^2), or `optimize` by bound-constrained L-BFGS. The
// structure is left at the resulting design, so the scene's curve, period output and Newmark check
// that follow are the optimised design's.
//
// Parameters, separated by `;`, each `KIND [SELECTION] = INITIAL in LOWER, UPPER`:
//   mass at X, Y, Z        an extra point mass [kg] at the vertex, joint or mass nearest to the point
//   force amplitude        a factor on the point forces' amplitudes [-]
//   force phase            an offset added to the point forces' phases [rad]
//   drive amplitude        a factor on the drives' motion [-]
//   layer modulus L        Young's modulus of material layer L (solid) [Pa]
//   element modulus        Young's modulus of every element of a plane model, one parameter each
//                          [Pa]; INITIAL is ignored (the layer's), LOWER and UPPER are factors on it

#include <deal.II/base/parameter_handler.h>

#include <nlmech/scenes/hbm/structure.h>
#include <nlmech/solvers/hbm/periodic_solvers.h>

#include <functional>
#include <string>
#include <vector>

namespace nlmech
{
  class RunContext;

  struct DesignStudySettings
  {
    std::string              mode = "off"; // off | apply | explore | optimize
    std::vector<std::string> parameters;
    std::vector<double>      frequencies;
    std::string              objective        = "amplitude";
    double                   target_amplitude = 1;
    /// peak amplitude | peak frequency: the resonance peak near each frequency, inside this window.
    double                    peak_low = 0, peak_high = 0, target_frequency = 0;
    std::vector<unsigned int> axes; // of the tracked point; empty: all
    /// The points the objective follows (empty: the scene's tracked point), "x, y[, z]" each.
    std::vector<std::string> objective_points;
    std::string              target_file;
    std::string              moduli_file; // Element moduli: initial moduli per element (CSV)
    unsigned int             phases    = 64;
    double                   sharpness = 50, change_penalty = 0;
    unsigned int             max_evaluations = 200;
    double                   tolerance = 1e-8, time_limit = 0;
    std::vector<double>      exploration_steps;
    bool                     initial_curve = true;

    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(dealii::ParameterHandler &prm);
    bool        enabled() const { return mode != "off"; }
    bool        peak() const { return objective.rfind("peak", 0) == 0; }
  };

  /// What a design run found, for the scene's curve before and after.
  struct DesignOutcome
  {
    bool                         ran = false;
    std::vector<double>          frequencies;
    std::vector<Eigen::VectorXd> states; // the design's periodic states, per frequency
  };

  /// Runs the design study on `s` (left at the resulting design): design_history.csv and .png,
  /// design_trajectories.csv and .png, design_parameters.csv, sensitivity_sweep.csv and .png
  /// (explore), optimized.prm (the parameter file `prm_text` with the design's values and Mode =
  /// apply), and the figures in summary.json. Clear errors for unknown kinds or selections,
  /// inverted bounds, a point far from the model and malformed targets; an optimiser stopped by a
  /// limit marks the run partial with the best design kept.
  /// Initial states at the driving frequencies: from rest, or along the curve from `continuation`'s
  /// start frequency where that fails. `initial_design` (if set) is called once the parameters'
  /// initial values are on `s`: the initial design's own output (its frequency-response curve).
  DesignOutcome run_design_study(RunContext &context, PeriodicStructure &s,
                                 const HarmonicBalanceSettings &hb_settings,
                                 const ContinuationSettings    &continuation,
                                 const DesignStudySettings &settings, const std::string &prm_text,
                                 const std::string                                    &source_directory,
                                 const std::function<void(const PeriodicStructure &)> &initial_design = {});
} // namespace nlmech
