#pragma once
// The harmonic-balance scene's own settings, beside the structure plugins': damping (subsection
// Oscillator), the harmonic balance and its continuation (subsection Harmonic balance), the
// backbone (subsection Backbone) and the Newmark check (subsection Newmark check).

#include <deal.II/base/parameter_handler.h>

#include <nlmech/solvers/hbm/harmonic_balance.h>
#include <nlmech/solvers/hbm/periodic_solvers.h>

#include <vector>

namespace nlmech
{
  struct HarmonicBalanceSceneSettings
  {
    HarmonicBalanceSettings harmonic_balance;
    ContinuationSettings    continuation;
    bool                    trace_curve        = true;
    bool                    linear_reference   = true;
    double                  adaptive_threshold = 0, adaptive_frequency = 0;
    std::vector<double>     evaluation_frequencies;
    std::vector<double>     backbone_amplitudes;
    unsigned int            backbone_mode = 1;
    std::vector<double>     check_frequencies; // Newmark check; empty: off
    NewmarkSettings         newmark;
    double                  newmark_tolerance = 1e-3;

    /// `structure_names`: the registered structures, for the `Model` selection.
    static void declare_parameters(dealii::ParameterHandler &prm, const std::string &structure_names,
                                   const std::string &structure_descriptions);
    void        parse_parameters(dealii::ParameterHandler &prm);
  };
} // namespace nlmech
