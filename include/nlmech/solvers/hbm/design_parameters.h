#pragma once
// The kinds of harmonic-balance design parameter (solvers/hbm/design.h), each on the parts of a
// structure it changes: an extra point mass on a vertex's unknowns; a mechanism spring's stiffness,
// rest length or attachment, and a rigid link's length; the amplitude factor and the
// phase of point forces; the amplitude factor of the drives (penalty or prescribed); the Young's
// modulus of a whole energy term (a layer, a material group: the term's energy is linear in it at
// fixed Poisson's ratio) or of a group of elements within a plane-triangle term (a modulus per
// element). Parameters keep references to the structure's Model, forces and drives: those must
// outlive them.

#include <nlmech/models/model.h>
#include <nlmech/solvers/hbm/design.h>

#include <memory>
#include <string>
#include <vector>

namespace nlmech
{
  /// An extra mass m >= 0 at a vertex: every listed unknown's lumped mass is its initial one plus m;
  /// with `gravity` (acceleration per unknown, full length) also its weight m g.
  std::shared_ptr<DesignParameter> make_point_mass_parameter(std::string name, Model &model,
                                                             std::vector<std::size_t> dofs, double initial,
                                                             double lower, double upper,
                                                             Eigen::VectorXd gravity = {});

  /// The factor p on the amplitudes of the listed point forces (1: as declared).
  std::shared_ptr<DesignParameter> make_force_amplitude_parameter(std::string                 name,
                                                                  std::vector<HarmonicForce> &forces,
                                                                  std::vector<std::size_t>    which,
                                                                  double lower, double upper);
  /// A phase offset p [rad] added to the listed point forces' phases.
  std::shared_ptr<DesignParameter> make_force_phase_parameter(std::string                 name,
                                                              std::vector<HarmonicForce> &forces,
                                                              std::vector<std::size_t> which, double lower,
                                                              double upper);
  /// The factor p on every drive's motion about its centre (1: as declared), penalty and prescribed.
  std::shared_ptr<DesignParameter> make_drive_amplitude_parameter(std::string                 name,
                                                                  std::vector<HarmonicDrive> &drives,
                                                                  double lower, double upper);

  /// One datum of link spring `spring` of a mechanism (models/dynamics/mechanism.h): `datum` 0-3 an
  /// attachment coordinate u_a, w_a, u_b, w_b (in its link's frame), 4 the rest length [m], 5 the
  /// stiffness [N/m]. The springs' term is replaced by one whose data the parameters share.
  std::shared_ptr<DesignParameter> make_spring_parameter(std::string name, Model &model, std::size_t spring,
                                                         unsigned int datum, double initial, double lower,
                                                         double upper);

  /// The length [m] of rigid link `link` of a mechanism (its length penalty's rest length): the
  /// links' term is replaced by one whose lengths the parameters share. The joints' rest angles
  /// stay; the periodic state's mean finds the new geometry.
  std::shared_ptr<DesignParameter> make_link_length_parameter(std::string name, Model &model,
                                                              std::size_t link, double initial, double lower,
                                                              double upper);

  /// The Young's modulus E of the model's energy term `term` (initially `modulus`): the term is
  /// replaced by itself times E / modulus.
  std::shared_ptr<DesignParameter> make_term_modulus_parameter(std::string name, Model &model,
                                                               std::size_t term, double modulus, double lower,
                                                               double upper);

  /// Young's moduli of groups of elements of the model's plane-triangle term: one parameter per
  /// group (`groups[g]`: its elements; `moduli[g]`: its initial modulus). The term is replaced by one
  /// with a factor per element; the parameters share it.
  std::vector<std::shared_ptr<DesignParameter>> make_element_modulus_parameters(
      const std::string &name, Model &model, const std::vector<std::vector<std::size_t>> &groups,
      const std::vector<double> &moduli, double lower_factor, double upper_factor);
} // namespace nlmech
