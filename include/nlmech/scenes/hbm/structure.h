#pragma once
// What the harmonic balance scene runs on, and the plugins that build it: each structure kind
// (duffing, two-spring-mass, shell, solid, plane, mechanism, rods) is one registered plugin with its
// own parameters, its Model with static state, drives, forces and tracked unknowns, and its own
// output of one period. A new structure is one new file with NLMECH_REGISTER_STRUCTURE.

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <nlmech/base/plugin_registry.h>
#include <nlmech/models/model.h>
#include <nlmech/solvers/hbm/harmonic_balance.h>

#include <Eigen/Dense>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace nlmech
{
  class RunContext;

  /// The Model with its static state, excitation and tracked unknowns.
  struct PeriodicStructure
  {
    Model                      model{0};
    Eigen::VectorXd            rest; // static state (full length)
    std::vector<HarmonicForce> forces;
    std::vector<HarmonicDrive> drives;
    std::vector<std::size_t>   tracked_dofs; // one point's coordinates
    std::size_t                tracked = 0;  // the coordinate whose half range is reported
    /// Newmark check: start from rest (small oscillators, whose transient decays onto the stable
    /// state) instead of from the HBM state (structures where a start from rest is a hard Newton
    /// problem).
    bool newmark_from_rest = false;
    /// The motion the first periodic state starts from, per free unknown, about the static state
    /// (`center`: the mean offset from it): a rotation drive's rigid motion of the whole structure,
    /// which a thin shell reaches from rest only by a long excitation ramp (a linearised rotation
    /// stretches the membrane). Empty: the static state.
    std::vector<HarmonicDrive> start_motion;

    // What design parameters (scenes/hbm/design_study.h) select on; set by the plugins that offer it.
    /// The unknowns of the vertex, joint or mass nearest to a point (point masses); empty: none.
    std::function<std::vector<std::size_t>(const dealii::Point<3> &)> point_dofs;
    /// The vertex, joint or mass's distance from that point [m] (a point mass far off the model is refused).
    std::function<double(const dealii::Point<3> &)> point_distance;
    /// Gravity's acceleration per unknown (full length; empty: none): a point mass's weight.
    Eigen::VectorXd gravity;
    /// Per material layer (from 0): its energy term and Young's modulus (term -1: no cells).
    std::vector<std::pair<long, double>> layer_terms;
    /// Young's modulus of every element of a plane-triangle model (empty: not a plane model).
    std::vector<double> element_moduli;
  };

  /// subsection Structure, the entries every excited structure shares: the translation drive, point
  /// forces, the tracked coordinate and the period frames.
  struct ExcitationSettings
  {
    dealii::Tensor<1, 3>                                           drive_direction; // normalised
    double                                                         drive_amplitude = 0;
    std::vector<std::pair<dealii::Point<3>, dealii::Tensor<1, 3>>> point_forces;
    unsigned int                                                   tracked_direction = 2;
    unsigned int                                                   period_frames     = 24;

    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(dealii::ParameterHandler &prm);
  };

  class StructurePlugin
  {
  public:
    virtual ~StructurePlugin() = default;
    /// Checks that need more than the parameter file (a mesh file exists).
    virtual void validate() const {}
    /// The structure, without its static state under constant loads (the scene solves for it).
    virtual PeriodicStructure build(RunContext &context, const HarmonicBalanceSettings &settings,
                                    const ExcitationSettings &excitation) = 0;
    /// What one period looks like beyond the tracked point's trajectory: x(dof, frame) at `times`.
    virtual void write_period(RunContext &context, const PeriodicStructure &structure,
                              const std::vector<double> &times, const Eigen::MatrixXd &x) const;
  };

  /// The harmonic balance unknowns the first periodic state starts from: the static state with the
  /// structure's `start_motion` on it.
  Eigen::VectorXd start_coefficients(const HarmonicBalance &hb, const PeriodicStructure &structure);

  using StructureRegistry     = PluginRegistry<StructurePlugin>;
  using StructureInfo         = PluginInfo<StructurePlugin>;
  using StructureRegistration = PluginRegistration<StructurePlugin>;
} // namespace nlmech

#define NLMECH_REGISTER_STRUCTURE(identifier, ...)                                        \
  namespace                                                                               \
  {                                                                                       \
    const nlmech::StructureRegistration identifier##_structure_registration(__VA_ARGS__); \
  }
