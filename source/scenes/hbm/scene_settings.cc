#include <deal.II/base/exceptions.h>

#include <nlmech/base/parse.h>
#include <nlmech/scenes/hbm/scene_settings.h>

#include <algorithm>

namespace nlmech
{
  using namespace dealii;

  void HarmonicBalanceSceneSettings::declare_parameters(ParameterHandler  &prm,
                                                        const std::string &structure_names,
                                                        const std::string &structure_descriptions)
  {
    prm.enter_subsection("Oscillator");
    prm.declare_entry("Model", "duffing", Patterns::Selection(structure_names),
                      structure_descriptions + ". Mesh models are clamped, driven and tracked as subsection "
                                               "Structure says.");
    prm.declare_entry("Rayleigh mass damping", "0.1", Patterns::Double(0), "D_alpha, D = D_alpha M [1/s].");
    prm.declare_entry("Rayleigh stiffness damping", "0", Patterns::Double(0),
                      "D_beta, D += D_beta K(x) [s].");
    prm.leave_subsection();
    prm.enter_subsection("Harmonic balance");
    prm.declare_entry("Harmonics", "7", Patterns::Integer(), "N_H [-].");
    prm.declare_entry("Time samples", "0", Patterns::Integer(), "N_AFT >= 2 N_H + 1; 0: automatic [-].");
    ContinuationSettings::declare_parameters(prm);
    prm.declare_entry("Frequency response", "true", Patterns::Bool(),
                      "Trace the frequency-response curve over the frequency range; false: only the "
                      "evaluation frequencies and the backbone below.");
    prm.declare_entry("Evaluation frequencies", "", Patterns::Anything(),
                      "Frequencies at which the periodic state is solved on its own (from the nearest "
                      "point of the curve when one is traced, else from rest with the excitation "
                      "ramped up) and written to evaluation.csv with its harmonic coefficients "
                      "[rad/s]; empty: none.");
    prm.declare_entry(
        "Adaptive harmonics", "0", Patterns::Double(0),
        "0: use Harmonics as given; > 0: raise N_H from Harmonics in steps of 2 (up to 25) until "
        "the trajectory at the adaptive frequency changes by less than this fraction of its "
        "size (thesis 2.5.1; e.g. 1e-3) [-].");
    prm.declare_entry("Adaptive frequency", "0", Patterns::Double(0),
                      "Where the number of harmonics is chosen; 0: the start frequency [rad/s].");
    prm.declare_entry("Linear modal reference", "true", Patterns::Bool(),
                      "Add the linear modal analysis response at the static state (dense eigenproblem, up "
                      "to 3000 free unknowns) to the curve's CSV and plot.");
    prm.leave_subsection();
    prm.enter_subsection("Backbone");
    prm.declare_entry("Amplitudes", "", Patterns::Anything(),
                      "First-harmonic (cosine) amplitudes of the tracked unknown at which the undamped, "
                      "unforced periodic solution (the nonlinear normal mode, as NLvib's NMA) is solved, "
                      "ascending, continued from the linear mode; written to backbone.csv [m]; empty: "
                      "none. Structures with forces only (no drives).");
    prm.declare_entry("Mode", "1", Patterns::Integer(1), "The linear mode the backbone starts from [-].");
    prm.leave_subsection();
    prm.enter_subsection("Newmark check");
    prm.declare_entry("Frequencies", "", Patterns::Anything(),
                      "Frequencies at which Newmark (beta 1/4, gamma 1/2) is run to the periodic steady "
                      "state and compared with the HBM state [rad/s]; empty: no check (it often costs more "
                      "than the frequency response). Oscillators start from rest, other models from the "
                      "HBM state.");
    NewmarkSettings::declare_parameters(prm);
    prm.declare_entry("Tolerance", "1e-3", Patterns::Double(0),
                      "Largest difference between the HBM and the Newmark trajectory of the tracked "
                      "unknown, relative to its half range; above it (or when Newmark reaches no "
                      "periodic state) the run keeps its results, says \"status\": \"check_failed\" "
                      "and exits with 1 [-].");
    prm.leave_subsection();
  }

  void HarmonicBalanceSceneSettings::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Oscillator");
    harmonic_balance.rayleigh_mass      = prm.get_double("Rayleigh mass damping");
    harmonic_balance.rayleigh_stiffness = prm.get_double("Rayleigh stiffness damping");
    prm.leave_subsection();
    prm.enter_subsection("Harmonic balance");
    const long harmonics = prm.get_integer("Harmonics"), samples = prm.get_integer("Time samples");
    AssertThrow(harmonics >= 1,
                ExcMessage("Harmonics must be at least 1 (got " + std::to_string(harmonics) + ")."));
    AssertThrow(samples >= 0, ExcMessage("Time samples must not be negative."));
    harmonic_balance.n_harmonics = unsigned(harmonics), harmonic_balance.n_samples = unsigned(samples);
    AssertThrow(harmonic_balance.n_samples == 0 ||
                    harmonic_balance.n_samples >= 2 * harmonic_balance.n_harmonics + 1,
                ExcMessage("Time samples (N_AFT = " + std::to_string(samples) +
                           ") must be at least 2 N_H + 1 = " + std::to_string(2 * harmonics + 1) + "."));
    continuation.parse_parameters(prm);
    trace_curve            = prm.get_bool("Frequency response");
    evaluation_frequencies = parse_number_list(prm.get("Evaluation frequencies"), "Evaluation frequencies");
    for (const double w : evaluation_frequencies)
      AssertThrow(w > 0, ExcMessage("Evaluation frequencies must be positive [rad/s]."));
    linear_reference   = prm.get_bool("Linear modal reference");
    adaptive_threshold = prm.get_double("Adaptive harmonics");
    adaptive_frequency = prm.get_double("Adaptive frequency");
    prm.leave_subsection();
    prm.enter_subsection("Backbone");
    backbone_amplitudes = parse_number_list(prm.get("Amplitudes"), "Backbone amplitudes");
    backbone_mode       = unsigned(prm.get_integer("Mode"));
    AssertThrow(std::is_sorted(backbone_amplitudes.begin(), backbone_amplitudes.end()) &&
                    (backbone_amplitudes.empty() || backbone_amplitudes.front() > 0),
                ExcMessage("Backbone: the amplitudes must be positive and ascending."));
    prm.leave_subsection();
    prm.enter_subsection("Newmark check");
    check_frequencies = parse_number_list(prm.get("Frequencies"), "Frequencies");
    for (const double w : check_frequencies)
      AssertThrow(w > 0, ExcMessage("Newmark check frequencies must be positive."));
    newmark.parse_parameters(prm);
    newmark_tolerance = prm.get_double("Tolerance");
    prm.leave_subsection();
  }
} // namespace nlmech
