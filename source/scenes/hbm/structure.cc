#include <nlmech/scenes/elastic_statics_parameters.h>
#include <nlmech/scenes/hbm/structure.h>

namespace nlmech
{
  using namespace dealii;

  void ExcitationSettings::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Structure");
    prm.declare_entry("Drive direction", "0, 0, 1", Patterns::Anything(), "d, normalised [-].");
    prm.declare_entry("Drive amplitude", "0.002", Patterns::Double(0), "a [m].");
    prm.declare_entry("Point forces", "", Patterns::Anything(),
                      "Harmonic forces F cos(w t) at the vertices nearest to points, `x, y, z: F_x, F_y, "
                      "F_z; ...` [m: N].");
    prm.declare_entry("Tracked direction", "z", Patterns::Selection("x|y|z"),
                      "The coordinate whose half range is plotted and reported [-].");
    prm.declare_entry("Period frames", "24", Patterns::Integer(0),
                      "Frames of one period (period.pvd for meshes, mechanism_period.csv) at the first "
                      "resonance peak, or at the end frequency without a peak; with a Design, of the "
                      "design's state at its first driving frequency; 0: none [-].");
    prm.leave_subsection();
  }

  void ExcitationSettings::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Structure");
    drive_direction = parse_vector<3>(prm.get("Drive direction"), "Drive direction");
    AssertThrow(drive_direction.norm() > 0, ExcMessage("Drive direction must not be zero."));
    drive_direction /= drive_direction.norm();
    drive_amplitude   = prm.get_double("Drive amplitude");
    point_forces      = parse_point_vectors(prm.get("Point forces"), "Point forces");
    tracked_direction = prm.get("Tracked direction") == "x" ? 0 : prm.get("Tracked direction") == "y" ? 1 : 2;
    period_frames     = unsigned(prm.get_integer("Period frames"));
    prm.leave_subsection();
  }

  Eigen::VectorXd start_coefficients(const HarmonicBalance &hb, const PeriodicStructure &structure)
  {
    Eigen::VectorXd   z = hb.static_coefficients(structure.rest);
    const std::size_t n = hb.n_free();
    for (const HarmonicDrive &d : structure.start_motion)
      {
        const long i = d.dof < std::size_t(structure.rest.size()) ? hb.free_position(d.dof) : -1;
        if (i < 0)
          continue;
        z[i] += d.center;
        for (unsigned int k = 1; k <= hb.n_harmonics(); ++k)
          {
            if (k <= d.sine.size())
              z[(2 * k - 1) * n + std::size_t(i)] = d.sine[k - 1];
            if (k <= d.cosine.size())
              z[2 * k * n + std::size_t(i)] = d.cosine[k - 1];
          }
        if (d.amplitude != 0)
          z[n + std::size_t(i)] -= d.amplitude * std::sin(d.phase),
              z[2 * n + std::size_t(i)] += d.amplitude * std::cos(d.phase);
      }
    return z;
  }

  void StructurePlugin::write_period(RunContext &, const PeriodicStructure &, const std::vector<double> &,
                                     const Eigen::MatrixXd &) const
  {
  }
} // namespace nlmech
