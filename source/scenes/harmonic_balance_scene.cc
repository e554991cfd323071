// Scene "harmonic-balance": periodic steady states of forced nonlinear structures by the harmonic
// balance method (thesis ch. 2): a Duffing spring, a mass between two geometrically nonlinear
// springs, thin shells, St.Venant-Kirchhoff solids (tetrahedra, per-layer materials), plane
// triangle structures, and planar compliant mechanisms. The frequency-response curve by
// continuation with folds, stability and resonance peaks; the linear modal analysis response for
// comparison; one period as VTU/PVD and the tracked point's trajectory; Newmark runs to the
// periodic steady state at chosen frequencies as the time-domain check.

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/base/json.h>
#include <nlmech/base/progress.h>
#include <nlmech/base/run_context.h>
#include <nlmech/base/scene.h>
#include <nlmech/mesh/vertex_field_output.h>
#include <nlmech/models/dynamics/elastic_solids.h>
#include <nlmech/models/dynamics/mechanism.h>
#include <nlmech/models/dynamics/rod_network.h>
#include <nlmech/models/dynamics/spring_network.h>
#include <nlmech/models/dynamics/thin_shell.h>
#include <nlmech/scenes/elastic_statics_parameters.h>
#include <nlmech/solvers/hbm/backbone.h>
#include <nlmech/solvers/hbm/linear_modal.h>
#include <nlmech/solvers/hbm/periodic_solvers.h>
#include <nlmech/solvers/newton/newton_solver.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <set>
#include <sstream>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    /// "a, b, c; d, e, f" -> rows of numbers, each with `width` entries (0: any).
    std::vector<std::vector<double>> parse_rows(const std::string &text, const std::string &entry,
                                                const std::size_t width)
    {
      std::vector<std::vector<double>> rows;
      for (const auto &row : Utilities::split_string_list(text, ';'))
        if (!row.empty())
          {
            rows.push_back(parse_number_list(row, entry));
            AssertThrow(width == 0 || rows.back().size() == width,
                        ExcMessage(entry + ": every `;`-separated entry needs " + std::to_string(width) +
                                   " numbers (got <" + row + ">)."));
          }
      return rows;
    }

    unsigned int as_index(const double value, const std::string &entry)
    {
      AssertThrow(value >= 0 && value == std::floor(value) && value < 1e9,
                  ExcMessage(entry + ": <" + std::to_string(value) + "> is not an index."));
      return unsigned(value);
    }

    /// What the harmonic balance runs on: the Model with its static state, excitation and tracked
    /// unknowns, and what is needed to write its motion.
    struct Structure
    {
      Model                                    model{0};
      Eigen::VectorXd                          rest; // static state (full length)
      std::vector<HarmonicForce>               forces;
      std::vector<HarmonicDrive>               drives;
      std::vector<std::size_t>                 tracked_dofs; // one point's coordinates
      std::size_t                              tracked = 0;  // the coordinate whose half range is reported
      unsigned int                             dofs_per_vertex = 1;
      bool                                     has_mesh        = false;
      RawSimplexMesh<3>                        mesh;
      bool                                     is_mechanism = false;
      MechanismDescription                     mechanism;
      bool                                     is_rods      = false;
      std::size_t                              rod_vertices = 0;
      std::vector<std::array<unsigned int, 2>> rod_edges;
    };

    class HarmonicBalanceScene : public Scene
    {
    public:
      static void declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Oscillator");
        prm.declare_entry(
            "Model", "duffing",
            Patterns::Selection("duffing|two-spring-mass|shell|solid|plane|mechanism|rods"),
            "duffing: m x'' + c x' + k x + k3 x^3 = F cos(w t); two-spring-mass: a mass at the middle "
            "between "
            "two anchors at distance 2 Span, joined by geometric springs of rest length L0, forced across "
            "the "
            "span (a geometric nonlinearity); shell: a thin shell (CST St.Venant-Kirchhoff membrane + hinge "
            "bending) on the gmsh surface mesh of subsection Mesh; solid: St.Venant-Kirchhoff tetrahedra on "
            "a "
            "gmsh volume mesh (subsection Solid, per-layer materials); plane: plane-stress "
            "St.Venant-Kirchhoff "
            "triangles on a gmsh mesh in z = 0 (subsection Solid); mesh models are clamped, driven and "
            "tracked "
            "as subsection Structure says. mechanism: a planar compliant mechanism (subsection Mechanism); "
            "rods: "
            "a network of discrete elastic rods with rigid junctions (subsection Rods).");
        prm.declare_entry("Mass", "1", Patterns::Double(0), "m [kg].");
        prm.declare_entry("Stiffness", "1", Patterns::Double(0), "k, per spring [N/m].");
        prm.declare_entry("Cubic stiffness", "1", Patterns::Double(), "k3, per spring [N/m^3].");
        prm.declare_entry("Span", "1", Patterns::Double(0), "two-spring-mass: half the anchor distance [m].");
        prm.declare_entry("Rest length", "0.8", Patterns::Double(0), "two-spring-mass: L0 [m].");
        prm.declare_entry("Rayleigh mass damping", "0.1", Patterns::Double(0),
                          "D_alpha, D = D_alpha M [1/s].");
        prm.declare_entry("Rayleigh stiffness damping", "0", Patterns::Double(0),
                          "D_beta, D += D_beta K(x) [s].");
        prm.declare_entry("Force amplitude", "0.5", Patterns::Double(0), "F [N].");
        prm.leave_subsection();
        MeshParameters::declare_parameters(prm, NLMECH_SOURCE_DIR "/meshes/fork.geo", 0.012);
        prm.enter_subsection("Shell");
        prm.declare_entry("Young's modulus", "1e7", Patterns::Double(0), "[Pa].");
        prm.declare_entry("Poisson's ratio", "0.4", Patterns::Double(-1, 0.5), "[-].");
        prm.declare_entry("Density", "1100", Patterns::Double(0), "[kg/m^3].");
        prm.declare_entry("Thickness", "0.001", Patterns::Double(0), "[m].");
        prm.leave_subsection();
        prm.enter_subsection("Solid");
        prm.declare_entry("Young's modulus", "1e6", Patterns::Anything(),
                          "One value, or one per layer (comma-separated, from the low end of the layer axis "
                          "up) [Pa].");
        prm.declare_entry("Poisson's ratio", "0.3", Patterns::Double(-1, 0.5), "[-].");
        prm.declare_entry("Density", "1000", Patterns::Double(0), "[kg/m^3].");
        prm.declare_entry("Thickness", "0.01", Patterns::Double(0), "plane: out-of-plane thickness [m].");
        prm.declare_entry("Layer axis", "z", Patterns::Selection("x|y|z"),
                          "Layers are equal slabs of the mesh's extent along this axis [-].");
        prm.leave_subsection();
        prm.enter_subsection("Structure");
        prm.declare_entry("Clamped groups", "", Patterns::Anything(),
                          "Boundary or cell groups held at rest, comma-separated.");
        prm.declare_entry(
            "Driven groups", "handle", Patterns::Anything(),
            "Boundary or cell groups moved harmonically (Drive kind), comma-separated. Vertices "
            "along one straight edge alone leave a shell free to rotate about it.");
        prm.declare_entry(
            "Drive kind", "translation", Patterns::Selection("translation|rotation"),
            "translation: x = X + a d cos(w t); rotation: x = c + R(phi_0 cos(w t)) (X - c) about "
            "Rotation axis through Rotation center, exact up to the harmonics kept.");
        prm.declare_entry("Drive direction", "0, 0, 1", Patterns::Anything(), "d, normalised [-].");
        prm.declare_entry("Drive amplitude", "0.002", Patterns::Double(0), "a [m].");
        prm.declare_entry("Rotation axis", "1, 0, 0", Patterns::Anything(), "[-].");
        prm.declare_entry("Rotation center", "0, 0, 0", Patterns::Anything(), "c [m].");
        prm.declare_entry("Rotation amplitude", "0.1", Patterns::Double(0), "phi_0 [rad].");
        prm.declare_entry("Drive stiffness factor", "0", Patterns::Double(0),
                          "0: the driven vertices follow their motion exactly (eliminated); > 0: a penalty "
                          "(thesis 2.A.5) of this multiple of the largest diagonal entry of the stiffness "
                          "matrix at rest, whose forces limit the attainable residual [-].");
        prm.declare_entry("Point forces", "", Patterns::Anything(),
                          "Harmonic forces F cos(w t) at the vertices nearest to points, `x, y, z: F_x, F_y, "
                          "F_z; ...` [m: N].");
        prm.declare_entry(
            "Tracked point", "0.16, 0.0275, 0", Patterns::Anything(),
            "The vertex nearest to this point is the one whose amplitude (2.3.14) is traced [m].");
        prm.declare_entry("Tracked direction", "z", Patterns::Selection("x|y|z"),
                          "The coordinate whose half range is plotted and reported [-].");
        prm.declare_entry("Period frames", "24", Patterns::Integer(0),
                          "Frames of one period (period.pvd for meshes, mechanism_period.csv) at the first "
                          "resonance peak, or at the end frequency without a peak; 0: none [-].");
        prm.leave_subsection();
        prm.enter_subsection("Mechanism");
        prm.declare_entry("Joints", "", Patterns::Anything(),
                          "`x, y, m; ...` position [m] and mass [kg] per joint.");
        prm.declare_entry("Links", "", Patterns::Anything(),
                          "`a, b; ...` rigid links between joints (0-based).");
        prm.declare_entry("Rigid joints", "", Patterns::Anything(),
                          "`a, b, c; ...` the angle at b between links (a, b) and (b, c) is kept.");
        prm.declare_entry(
            "Springs", "", Patterns::Anything(),
            "`link_a, u_a, w_a, link_b, u_b, w_b, k, L0; ...`: a linear spring of stiffness k "
            "[N/m] and rest length L0 [m] (negative: its initial length) between points given in "
            "the local frames of two links (origin at the link's first joint, axes the link "
            "vector and its left normal).");
        prm.declare_entry("Fixed joints", "", Patterns::Anything(), "Joints held at rest, comma-separated.");
        prm.declare_entry(
            "Driven joints", "", Patterns::Anything(),
            "Joints moved by x = X + a d cos(w t) (Structure: Drive direction and amplitude, first "
            "two components), comma-separated.");
        prm.declare_entry("Tracked joint", "0", Patterns::Integer(0), "[-].");
        prm.declare_entry("Link stiffness", "1e5", Patterns::Double(0), "Rigid-link penalty k_l [N/m].");
        prm.declare_entry("Angle stiffness", "100", Patterns::Double(0),
                          "Rigid-joint penalty k_t [N m/rad^2].");
        prm.declare_entry("Gravity", "9.81", Patterns::Double(), "Along -y [m/s^2].");
        prm.leave_subsection();
        prm.enter_subsection("Rods");
        prm.declare_entry(
            "Polylines", "", Patterns::Anything(),
            "`x, y, z, x, y, z, ...; ...`: one rod per polyline [m], resampled to equal edges; a "
            "polyline whose ends coincide is a closed loop; rod ends that meet form a rigid "
            "junction.");
        prm.declare_entry("Segments per rod", "8", Patterns::Integer(1), "[-].");
        prm.declare_entry("Radius", "0.00055", Patterns::Double(0), "Wire radius [m].");
        prm.declare_entry("Young's modulus", "69e9", Patterns::Double(0), "[Pa].");
        prm.declare_entry("Poisson's ratio", "0.33", Patterns::Double(-1, 0.5), "[-].");
        prm.declare_entry("Density", "2700", Patterns::Double(0), "[kg/m^3].");
        prm.declare_entry("Added masses", "", Patterns::Anything(),
                          "`x, y, z, m; ...`: point masses [kg] at the vertices nearest to the points [m].");
        prm.declare_entry(
            "Driven points", "", Patterns::Anything(),
            "`x, y, z; ...`: the nearest vertices move by x = X + a d cos(w t) (Structure: Drive "
            "direction and amplitude); a driven junction is also held from turning (a clamp).");
        prm.declare_entry("Tracked point", "0, 0, 0", Patterns::Anything(), "[m].");
        prm.leave_subsection();
        prm.enter_subsection("Harmonic balance");
        prm.declare_entry("Harmonics", "7", Patterns::Integer(), "N_H [-].");
        prm.declare_entry("Time samples", "0", Patterns::Integer(), "N_AFT >= 2 N_H + 1; 0: automatic [-].");
        prm.declare_entry("Frequency range", "0.5, 2.5", Patterns::Anything(),
                          "Start and end of the frequency-response curve [rad/s].");
        prm.declare_entry("Maximum step", "0.05", Patterns::Double(0),
                          "Largest continuation step (scaled) [-].");
        prm.declare_entry("Maximum amplitude", "100", Patterns::Double(0),
                          "Stop the curve (partial result) beyond this half range [m].");
        prm.declare_entry("Tolerance", "1e-9", Patterns::Double(0), "|h| relative to the force scale [-].");
        prm.declare_entry("Maximum points", "2000", Patterns::Integer(1),
                          "Largest number of points on the frequency-response curve; beyond it the curve "
                          "stops (partial result) [-].");
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
        prm.declare_entry(
            "Stability", "hill", Patterns::Selection("hill|floquet|none"),
            "Stability of every point: hill (Hill's method: the Floquet exponents from the HBM "
            "Jacobian by shift-and-invert Arnoldi, reusing the continuation's factorisation; any "
            "size), floquet (monodromy matrix by RK4, dense: a time-domain cross-check for models "
            "of up to a few dozen free unknowns) or none.");
        prm.declare_entry(
            "Linear modal reference", "true", Patterns::Bool(),
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
                          "state and compared with the HBM state [rad/s]. Oscillators start from rest, other "
                          "models from the HBM state.");
        prm.declare_entry("Steps per period", "1024", Patterns::Integer(16), "[-].");
        prm.declare_entry("Period tolerance", "1e-8", Patterns::Double(0),
                          "e_p of thesis eq. (2.5.1), relative [-].");
        prm.declare_entry("Tolerance", "1e-3", Patterns::Double(0),
                          "Largest difference between the HBM and the Newmark trajectory of the tracked "
                          "unknown, relative to its half range; above it (or when Newmark reaches no "
                          "periodic state) the run keeps its results, says \"status\": \"check_failed\" "
                          "and exits with 1 [-].");
        prm.leave_subsection();
      }

      explicit HarmonicBalanceScene(ParameterHandler &prm)
      {
        prm.enter_subsection("Oscillator");
        model_kind = prm.get("Model");
        mass = prm.get_double("Mass"), k = prm.get_double("Stiffness"),
        k3   = prm.get_double("Cubic stiffness");
        span = prm.get_double("Span"), rest_length = prm.get_double("Rest length");
        settings.rayleigh_mass      = prm.get_double("Rayleigh mass damping");
        settings.rayleigh_stiffness = prm.get_double("Rayleigh stiffness damping");
        force                       = prm.get_double("Force amplitude");
        prm.leave_subsection();
        mesh.parse_parameters(prm);
        prm.enter_subsection("Shell");
        shell_material.youngs_modulus = prm.get_double("Young's modulus");
        shell_material.poissons_ratio = prm.get_double("Poisson's ratio");
        shell_material.density        = prm.get_double("Density");
        shell_material.thickness      = prm.get_double("Thickness");
        prm.leave_subsection();
        prm.enter_subsection("Solid");
        for (const double E : parse_number_list(prm.get("Young's modulus"), "Young's modulus"))
          {
            SolidMaterial m;
            m.youngs_modulus = E, m.poissons_ratio = prm.get_double("Poisson's ratio");
            m.density = prm.get_double("Density"), m.thickness = prm.get_double("Thickness");
            m.check();
            solid_materials.push_back(m);
          }
        AssertThrow(!solid_materials.empty(), ExcMessage("Solid: Young's modulus needs at least one value."));
        layer_axis = prm.get("Layer axis") == "x" ? 0 : prm.get("Layer axis") == "y" ? 1 : 2;
        prm.leave_subsection();
        prm.enter_subsection("Structure");
        for (const auto &g : Utilities::split_string_list(prm.get("Clamped groups"), ','))
          if (!g.empty())
            clamped_groups.push_back(g);
        for (const auto &g : Utilities::split_string_list(prm.get("Driven groups"), ','))
          if (!g.empty())
            driven_groups.push_back(g);
        rotation_drive  = prm.get("Drive kind") == "rotation";
        drive_direction = parse_vector<3>(prm.get("Drive direction"), "Drive direction");
        AssertThrow(drive_direction.norm() > 0, ExcMessage("Drive direction must not be zero."));
        drive_direction /= drive_direction.norm();
        drive_amplitude    = prm.get_double("Drive amplitude");
        rotation_axis      = parse_vector<3>(prm.get("Rotation axis"), "Rotation axis");
        rotation_center    = parse_vector<3>(prm.get("Rotation center"), "Rotation center");
        rotation_amplitude = prm.get_double("Rotation amplitude");
        AssertThrow(!rotation_drive || rotation_axis.norm() > 0,
                    ExcMessage("Rotation axis must not be zero."));
        drive_stiffness_factor = prm.get_double("Drive stiffness factor");
        point_forces           = parse_point_vectors(prm.get("Point forces"), "Point forces");
        tracked_point          = Point<3>(parse_vector<3>(prm.get("Tracked point"), "Tracked point"));
        tracked_direction      = prm.get("Tracked direction") == "x"   ? 0
                                 : prm.get("Tracked direction") == "y" ? 1
                                                                       : 2;
        period_frames          = prm.get_integer("Period frames");
        prm.leave_subsection();
        prm.enter_subsection("Mechanism");
        if (model_kind == "mechanism")
          parse_mechanism(prm);
        prm.leave_subsection();
        prm.enter_subsection("Rods");
        if (model_kind == "rods")
          {
            for (const auto &row : parse_rows(prm.get("Polylines"), "Polylines", 0))
              {
                AssertThrow(
                    row.size() >= 6 && row.size() % 3 == 0,
                    ExcMessage("Polylines: each polyline needs at least two points of three coordinates."));
                std::vector<std::array<double, 3>> line;
                for (std::size_t i = 0; i < row.size(); i += 3)
                  line.push_back({{row[i], row[i + 1], row[i + 2]}});
                rod_polylines.push_back(line);
              }
            AssertThrow(!rod_polylines.empty(), ExcMessage("Rods: Polylines are needed."));
            rod_segments                = prm.get_integer("Segments per rod");
            rod_material.radius         = prm.get_double("Radius");
            rod_material.youngs_modulus = prm.get_double("Young's modulus");
            rod_material.poissons_ratio = prm.get_double("Poisson's ratio");
            rod_material.density        = prm.get_double("Density");
            rod_masses                  = parse_rows(prm.get("Added masses"), "Added masses", 4);
            rod_driven                  = parse_rows(prm.get("Driven points"), "Driven points", 3);
            rod_tracked = Point<3>(parse_vector<3>(prm.get("Tracked point"), "Tracked point"));
            for (const auto &m : rod_masses)
              AssertThrow(m[3] >= 0, ExcMessage("Added masses must not be negative."));
          }
        prm.leave_subsection();
        prm.enter_subsection("Harmonic balance");
        const long harmonics = prm.get_integer("Harmonics"), samples = prm.get_integer("Time samples");
        AssertThrow(harmonics >= 1,
                    ExcMessage("Harmonics must be at least 1 (got " + std::to_string(harmonics) + ")."));
        AssertThrow(samples >= 0, ExcMessage("Time samples must not be negative."));
        settings.n_harmonics = unsigned(harmonics), settings.n_samples = unsigned(samples);
        AssertThrow(settings.n_samples == 0 || settings.n_samples >= 2 * settings.n_harmonics + 1,
                    ExcMessage("Time samples (N_AFT = " + std::to_string(samples) +
                               ") must be at least 2 N_H + 1 = " + std::to_string(2 * harmonics + 1) + "."));
        const auto range = parse_number_list(prm.get("Frequency range"), "Frequency range");
        AssertThrow(range.size() == 2 && range[0] > 0 && range[1] > 0 && range[0] != range[1],
                    ExcMessage("Frequency range needs two different positive frequencies [rad/s]."));
        continuation.omega_start = range[0], continuation.omega_end = range[1];
        continuation.max_step           = prm.get_double("Maximum step");
        continuation.max_amplitude      = prm.get_double("Maximum amplitude");
        continuation.relative_tolerance = prm.get_double("Tolerance");
        continuation.max_points         = unsigned(prm.get_integer("Maximum points"));
        trace_curve                     = prm.get_bool("Frequency response");
        evaluation_frequencies =
            parse_number_list(prm.get("Evaluation frequencies"), "Evaluation frequencies");
        for (const double w : evaluation_frequencies)
          AssertThrow(w > 0, ExcMessage("Evaluation frequencies must be positive [rad/s]."));
        linear_reference = prm.get_bool("Linear modal reference");
        {
          const std::string method = prm.get("Stability");
          continuation.stability   = method == "floquet" ? StabilityMethod::floquet
                                     : method == "none"  ? StabilityMethod::none
                                                         : StabilityMethod::hill;
        }
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
        newmark.steps_per_period = prm.get_integer("Steps per period");
        newmark.period_tolerance = prm.get_double("Period tolerance");
        newmark_tolerance        = prm.get_double("Tolerance");
        prm.leave_subsection();
        AssertThrow(mass > 0, ExcMessage("Mass must be positive."));
      }

      void validate() const override
      {
        if (model_kind != "duffing" && model_kind != "two-spring-mass" && model_kind != "mechanism" &&
            model_kind != "rods")
          mesh.check_exists();
      }

      void run(RunContext &context) override
      {
        Structure s;
        {
          TimerOutput::Scope t(context.timer, "model");
          build_structure(context, s);
        }
        if (adaptive_threshold > 0)
          {
            TimerOutput::Scope    t(context.timer, "adaptive number of harmonics");
            const double          w = adaptive_frequency > 0 ? adaptive_frequency : continuation.omega_start;
            const HarmonicsChoice choice = choose_harmonics(s.model, settings, s.forces, s.drives, s.rest, w,
                                                            adaptive_threshold, settings.n_harmonics, 25, 2);
            std::ostringstream    changes;
            for (const auto &c : choice.changes)
              changes << " N_H " << c.first << ": " << c.second << ";";
            context.pcout << "adaptive harmonics at w = " << w << " rad/s:" << changes.str()
                          << " -> N_H = " << choice.n_harmonics
                          << (choice.converged ? "" : " (threshold not met at N_H = 25)") << std::endl;
            context.summary.add_number("adaptive_harmonics_converged", choice.converged);
            if (!choice.changes.empty())
              context.summary.add_figure("adaptive_last_trajectory_change", choice.changes.back().second,
                                         "1");
            settings.n_harmonics = choice.n_harmonics;
            if (settings.n_samples != 0)
              settings.n_samples = std::max(settings.n_samples, 2 * settings.n_harmonics + 1);
          }
        const HarmonicBalance hb(s.model, settings, s.forces, s.drives);
        context.summary.add_string("model", model_kind);
        context.summary.add_number("harmonics", settings.n_harmonics);
        context.summary.add_number("time_samples", hb.n_samples());
        context.summary.add_number("unknowns", hb.n_unknowns());
        context.summary.add_number("free_unknowns", hb.n_free());

        ProgressReporter progress("frequency response", 1.0, context.comm, context.pcout.get_stream());
        continuation.tracked_dofs = s.tracked_dofs;
        double reported           = 0;
        continuation.progress     = [&](double done) {
          if (done >= reported + 0.1)
            progress.report(done), reported = done;
        };
        FrequencyResponse frc;
        frc.completed = true;
        if (trace_curve)
          {
            TimerOutput::Scope t(context.timer, "frequency response (HBM continuation)");
            frc = trace_frequency_response(hb, hb.static_coefficients(s.rest), continuation);
          }
        // Linear modal analysis at the static state, at the same frequencies.
        std::vector<std::pair<double, double>> lma; // (amplitude A, half range) per point
        if (linear_reference && hb.n_free() <= 3000 && !frc.points.empty())
          {
            TimerOutput::Scope       t(context.timer, "linear modal analysis");
            const LinearModes        modes = linear_modes(hb, s.rest);
            std::vector<std::size_t> tracked_free;
            long                     half_index = -1;
            for (const std::size_t d : s.tracked_dofs)
              {
                const auto it = std::find(hb.free().begin(), hb.free().end(), d);
                if (it != hb.free().end())
                  tracked_free.push_back(std::size_t(it - hb.free().begin()));
                if (it != hb.free().end() && d == s.tracked)
                  half_index = long(it - hb.free().begin());
              }
            for (const auto &p : frc.points)
              {
                const Eigen::VectorXcd U = linear_modal_response(hb, modes, p.omega);
                lma.emplace_back(linear_amplitude(U, p.omega, tracked_free),
                                 half_index >= 0 ? std::abs(U[half_index]) : 0.0);
              }
            for (Eigen::Index m = 0; m < std::min<Eigen::Index>(3, modes.frequencies.size()); ++m)
              context.summary.add_figure("natural_frequency_" + std::to_string(m + 1), modes.frequencies[m],
                                         "rad/s");
            context.pcout << "linear modes: lowest natural frequencies";
            for (Eigen::Index m = 0; m < std::min<Eigen::Index>(4, modes.frequencies.size()); ++m)
              context.pcout << " " << modes.frequencies[m];
            context.pcout << " rad/s" << std::endl;
          }
        write_response(context, hb, s, frc, lma);
        if (period_frames > 0 && context.is_root() && !frc.points.empty())
          {
            TimerOutput::Scope     t(context.timer, "output (one period)");
            const Eigen::VectorXd &z = frc.peaks.empty() ? frc.points.back().z : frc.peaks.front().z;
            const double           w = frc.peaks.empty() ? frc.points.back().omega : frc.peaks.front().omega;
            write_period(context, hb, s, z, w);
          }
        evaluate_frequencies(context, hb, s, frc);
        trace_backbone_curve(context, s);
        if (!frc.completed)
          {
            context.partial_reason = "frequency response stopped: " + frc.stop_reason;
            return;
          }
        newmark_checks(context, hb, s);
      }

    private:
      /// Header of the harmonic coefficients of the tracked unknowns: x(t) = c0 + sum_k (cos_k cos(k w t)
      /// + sin_k sin(k w t)), abs_k = sqrt(cos_k^2 + sin_k^2), per tracked unknown (its index).
      std::string harmonics_header(const HarmonicBalance &hb, const Structure &s) const
      {
        std::string header;
        for (const std::size_t d : s.tracked_dofs)
          {
            const std::string u = ",x" + std::to_string(d) + "_";
            header += u + "c0";
            for (unsigned int k = 1; k <= hb.n_harmonics(); ++k)
              header += u + "cos" + std::to_string(k) + u + "sin" + std::to_string(k) + u + "abs" +
                        std::to_string(k);
          }
        return header;
      }

      std::string harmonics_row(const HarmonicBalance &hb, const Structure &s, const Eigen::VectorXd &z) const
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
      void evaluate_frequencies(RunContext &context, const HarmonicBalance &hb, const Structure &s,
                                const FrequencyResponse &frc) const
      {
        if (evaluation_frequencies.empty())
          return;
        TimerOutput::Scope t(context.timer, "evaluation frequencies");
        std::ostringstream csv;
        csv << "omega,amplitude_A,half_range,converged,iterations,relative_residual,start"
            << harmonics_header(hb, s) << "\n";
        unsigned int failed = 0;
        for (const double w : evaluation_frequencies)
          {
            Eigen::VectorXd z     = hb.static_coefficients(s.rest);
            std::string     start = "rest, excitation ramped";
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
            ps.relative_tolerance = continuation.relative_tolerance;
            PeriodicSolveResult r = frc.points.empty() ? solve_with_excitation_ramp(hb, z, w, ps)
                                                       : solve_periodic_state(hb, z, w, ps);
            if (!r.converged && !frc.points.empty())
              {
                z = hb.static_coefficients(s.rest), start = "rest, excitation ramped";
                r = solve_with_excitation_ramp(hb, z, w, ps);
              }
            failed += !r.converged;
            csv << json_number(w) << "," << json_number(hb.amplitude(z, w, s.tracked_dofs)) << ","
                << json_number(hb.half_range(z, w, s.tracked)) << "," << r.converged << "," << r.iterations
                << "," << json_number(r.residual) << "," << start << harmonics_row(hb, s, z) << "\n";
            context.pcout << "evaluation at w = " << w << " rad/s: "
                          << (r.converged ? "half range " + json_number(hb.half_range(z, w, s.tracked))
                                          : "no periodic state found (" + r.message + ")")
                          << std::endl;
          }
        context.summary.add_number("evaluation_frequencies", evaluation_frequencies.size());
        context.summary.add_number("evaluation_failures", failed);
        if (context.is_root())
          write_file_atomically(context.output.file("evaluation.csv"), csv.str());
        if (failed > 0 && context.partial_reason.empty())
          context.partial_reason = std::to_string(failed) + " evaluation frequencies found no periodic state";
      }

      /// The backbone of the undamped, unforced structure (the nonlinear normal mode) by amplitude.
      void trace_backbone_curve(RunContext &context, const Structure &s) const
      {
        if (backbone_amplitudes.empty())
          return;
        TimerOutput::Scope t(context.timer, "backbone");
        AssertThrow(
            s.drives.empty(),
            ExcMessage("Backbone: the structure is driven (its drives fix unknowns); the backbone needs "
                       "a structure loaded by forces only."));
        HarmonicBalanceSettings free_settings = settings;
        free_settings.rayleigh_mass = free_settings.rayleigh_stiffness = 0;
        const HarmonicBalance hb(s.model, free_settings);
        const auto            it = std::find(hb.free().begin(), hb.free().end(), s.tracked);
        AssertThrow(it != hb.free().end(), ExcMessage("Backbone: the tracked unknown is not free."));
        BackboneSettings b;
        b.reference = std::size_t(it - hb.free().begin());
        b.mode      = backbone_mode;
        b.tolerance = continuation.relative_tolerance;
        std::string                      stop;
        const std::vector<BackbonePoint> points = trace_backbone(hb, s.rest, backbone_amplitudes, b, &stop);
        std::ostringstream               csv;
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
        context.pcout << "backbone (mode " << backbone_mode << "): " << points.size() << " of "
                      << backbone_amplitudes.size() << " amplitudes" << (stop.empty() ? "" : "; " + stop)
                      << std::endl;
        if (context.is_root())
          write_file_atomically(context.output.file("backbone.csv"), csv.str());
        if (!stop.empty() && context.partial_reason.empty())
          context.partial_reason = "backbone: " + stop;
      }

      void write_response(RunContext &context, const HarmonicBalance &hb, const Structure &s,
                          const FrequencyResponse &frc, const std::vector<std::pair<double, double>> &lma)
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
                << json_number(hb.half_range(p.z, p.omega, s.tracked)) << "," << p.stable << "," << p.fold
                << "," << json_number(p.max_multiplier) << "," << p.iterations;
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
            run_plot("frequency_response.py", {context.output.file("frequency_response.csv"),
                                               context.output.file("frequency_response.png"),
                                               "HBM frequency response (" + model_kind + ")",
                                               context.output.file("resonance_peaks.csv")});
          }
      }

      /// One period at frequency w: the tracked point's trajectory (CSV, PNG), VTU frames of meshes,
      /// joint positions of mechanisms (CSV, PNG) with their constraint violations.
      void write_period(RunContext &context, const HarmonicBalance &hb, const Structure &s,
                        const Eigen::VectorXd &z, const double w) const
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
          run_plot("trajectory.py", {context.output.file("trajectory.csv"),
                                     context.output.file("trajectory.png"), title.str()});
        }
        if (s.has_mesh)
          {
            const unsigned int                                                d = s.dofs_per_vertex;
            std::vector<std::vector<std::pair<std::string, Eigen::VectorXd>>> frames;
            for (unsigned int f = 0; f < period_frames; ++f)
              {
                Eigen::VectorXd u = Eigen::VectorXd::Zero(3 * s.mesh.vertices.size());
                for (std::size_t v = 0; v < s.mesh.vertices.size(); ++v)
                  for (unsigned int i = 0; i < d; ++i)
                    u[3 * v + i] = x(d * v + i, f) - s.mesh.vertices[v][i];
                frames.push_back({{"displacement", u}});
              }
            write_vertex_fields_pvd(s.mesh,
                                    std::filesystem::path(context.output.file("period.pvd")).parent_path(),
                                    "period", times, frames);
          }
        if (s.is_rods)
          {
            std::ostringstream csv;
            csv << "t";
            for (std::size_t v = 0; v < s.rod_vertices; ++v)
              csv << ",x" << v << ",y" << v << ",z" << v;
            csv << "\n";
            for (unsigned int f = 0; f < period_frames; ++f)
              {
                csv << json_number(times[f]);
                for (std::size_t i = 0; i < 3 * s.rod_vertices; ++i)
                  csv << "," << json_number(x(i, f));
                csv << "\n";
              }
            std::ostringstream edges;
            for (const auto &e : s.rod_edges)
              edges << e[0] << "-" << e[1] << " ";
            write_file_atomically(context.output.file("rod_period.csv"), csv.str());
            run_plot("rods.py", {context.output.file("rod_period.csv"), context.output.file("rod_period.png"),
                                 edges.str()});
          }
        if (s.is_mechanism)
          {
            std::ostringstream    csv;
            std::array<double, 2> worst = {{0, 0}};
            csv << "t";
            for (std::size_t j = 0; j < s.mechanism.joints.size(); ++j)
              csv << ",x" << j << ",y" << j;
            csv << "\n";
            for (unsigned int f = 0; f < period_frames; ++f)
              {
                csv << json_number(times[f]);
                for (Eigen::Index i = 0; i < x.rows(); ++i)
                  csv << "," << json_number(x(i, f));
                csv << "\n";
                const auto v = mechanism_constraint_violation(s.mechanism, x.col(f));
                worst[0] = std::max(worst[0], v[0]), worst[1] = std::max(worst[1], v[1]);
              }
            std::ostringstream links;
            for (const auto &l : s.mechanism.links)
              links << l[0] << "-" << l[1] << " ";
            write_file_atomically(context.output.file("mechanism_period.csv"), csv.str());
            run_plot("mechanism.py", {context.output.file("mechanism_period.csv"),
                                      context.output.file("mechanism_period.png"), links.str()});
            context.summary.add_figure("max_link_length_change_relative", worst[0], "1");
            context.summary.add_figure("max_rigid_angle_change", worst[1], "rad");
          }
      }

      void run_plot(const std::string &script, const std::vector<std::string> &arguments) const
      {
        std::string command =
            std::string(NLMECH_PYTHON) + " '" + NLMECH_SOURCE_DIR + "/contrib/plot/" + script + "'";
        for (const auto &a : arguments)
          command += " '" + a + "'";
        if (std::system(command.c_str()) != 0)
          std::cerr << "nlmech: warning: the plot " << script << " could not be drawn (python3/matplotlib)."
                    << std::endl;
      }

      void build_structure(RunContext &context, Structure &s)
      {
        if (model_kind == "duffing" || model_kind == "two-spring-mass")
          {
            s.model        = model_kind == "duffing" ? make_duffing_model(mass, k, k3)
                                                     : make_two_spring_mass_model(mass, k, k3, span, rest_length);
            s.tracked      = model_kind == "duffing" ? 1 : 3;
            s.forces       = {{s.tracked, force, 0.0}};
            s.tracked_dofs = {s.tracked};
            s.rest         = Eigen::VectorXd::Zero(s.model.n_unknowns());
            for (const auto &f : s.model.fixed())
              s.rest[f.first] = f.second;
            return;
          }
        if (model_kind == "mechanism")
          build_mechanism(context, s);
        else if (model_kind == "rods")
          build_rods(context, s);
        else
          build_mesh_structure(context, s);
        // A static state under constant loads (gravity) with the drives at their centres: the
        // start of the curve.
        bool constant_loads = false;
        for (const auto &t : s.model.terms())
          constant_loads = constant_loads || dynamic_cast<const ConstantForceTerm *>(t.get()) != nullptr;
        if (constant_loads)
          {
            Model held = s.model;
            for (const auto &d : s.drives)
              held.fix(d.dof, d.center);
            const NewtonResult r = minimize_with_newton(held, s.rest);
            context.pcout << "static state under gravity: " << r.iterations << " Newton iterations"
                          << std::endl;
            context.summary.add_number("static_newton_iterations", r.iterations);
          }
      }

      /// Vertices of a boundary group or a cell group of the mesh.
      static std::set<unsigned int> group_vertices(const RawSimplexMesh<3> &m, const std::string &group)
      {
        std::set<unsigned int> vertices;
        if (m.groups.material_ids.count(group))
          {
            const unsigned int id = m.groups.material_ids.at(group);
            for (std::size_t c = 0; c < m.cells.size(); ++c)
              if (m.cell_material[c] == id)
                vertices.insert(m.cells[c].begin(), m.cells[c].end());
          }
        else
          {
            const unsigned int id = m.groups.boundary_id(group); // clear error if missing
            for (std::size_t f = 0; f < m.boundary_faces.size(); ++f)
              if (m.boundary_face_id[f] == id)
                vertices.insert(m.boundary_faces[f].begin(), m.boundary_faces[f].end());
          }
        AssertThrow(!vertices.empty(), ExcMessage("The group <" + group + "> has no vertices."));
        return vertices;
      }

      /// Shell, solid or plane structure on a gmsh mesh: clamped, driven, forced and tracked vertices.
      void build_mesh_structure(RunContext &context, Structure &s)
      {
        const int cell_dim = model_kind == "solid" ? 3 : 2;
        s.mesh             = read_simplex_mesh<3>(mesh.options(mesh.element_size), cell_dim);
        check_simplex_mesh(s.mesh, cell_dim);
        s.has_mesh = true;
        if (model_kind == "shell")
          {
            ShellModel shell = make_shell_model(s.mesh, shell_material);
            s.model = std::move(shell.model), s.rest = shell.rest_positions, s.dofs_per_vertex = 3;
          }
        else
          {
            const auto layers = cell_layers(s.mesh, layer_axis, solid_materials.size());
            SolidModel solid  = model_kind == "solid" ? make_tet_solid_model(s.mesh, solid_materials, layers)
                                                      : make_plane_model(s.mesh, solid_materials, layers);
            s.model = std::move(solid.model), s.rest = solid.rest_positions, s.dofs_per_vertex = solid.dim;
          }
        const unsigned int d = s.dofs_per_vertex;
        for (const auto &g : clamped_groups)
          for (const unsigned int v : group_vertices(s.mesh, g))
            for (unsigned int i = 0; i < d; ++i)
              s.model.fix(d * v + i, s.rest[d * v + i]);
        AssertThrow(!driven_groups.empty() || !point_forces.empty(),
                    ExcMessage("The structure needs driven groups or point forces: nothing excites it."));
        double largest_diagonal = 0;
        {
          const Eigen::SparseMatrix<double> K = s.model.hessian(s.rest);
          for (Eigen::Index i = 0; i < K.rows(); ++i)
            largest_diagonal = std::max(largest_diagonal, K.coeff(i, i));
        }
        std::set<unsigned int> driven;
        for (const auto &g : driven_groups)
          for (const unsigned int v : group_vertices(s.mesh, g))
            {
              AssertThrow(!s.model.is_fixed(d * v),
                          ExcMessage("A driven vertex is also clamped (group <" + g + ">)."));
              driven.insert(v);
            }
        const double penalty = drive_stiffness_factor * largest_diagonal;
        if (rotation_drive)
          {
            std::vector<std::array<double, 3>>      points;
            std::vector<std::array<std::size_t, 3>> dofs;
            for (const unsigned int v : driven)
              {
                points.push_back({{s.mesh.vertices[v][0], s.mesh.vertices[v][1], s.mesh.vertices[v][2]}});
                dofs.push_back({{d * v, d * v + 1, d * v + 2}});
              }
            AssertThrow(d == 3,
                        ExcMessage("Rotation drives need a 3D model (shell or solid); a plane structure is "
                                   "driven by translation."));
            s.drives = rotation_drives(points, dofs, {{rotation_axis[0], rotation_axis[1], rotation_axis[2]}},
                                       {{rotation_center[0], rotation_center[1], rotation_center[2]}},
                                       rotation_amplitude, settings.n_harmonics, penalty);
          }
        else
          for (const unsigned int v : driven)
            for (unsigned int i = 0; i < d; ++i)
              s.drives.push_back(
                  {d * v + i, drive_amplitude * drive_direction[i], 0.0, penalty, s.rest[d * v + i], {}, {}});
        auto nearest = [&](const Point<3> &p) {
          std::size_t best = 0;
          for (std::size_t v = 1; v < s.mesh.vertices.size(); ++v)
            if (s.mesh.vertices[v].distance(p) < s.mesh.vertices[best].distance(p))
              best = v;
          return best;
        };
        for (const auto &pf : point_forces)
          {
            const std::size_t v = nearest(pf.first);
            for (unsigned int i = 0; i < d; ++i)
              if (pf.second[i] != 0)
                s.forces.push_back({d * v + i, pf.second[i], 0.0});
          }
        const std::size_t t = nearest(tracked_point);
        for (unsigned int i = 0; i < d; ++i)
          s.tracked_dofs.push_back(d * t + i);
        AssertThrow(tracked_direction < d,
                    ExcMessage("Tracked direction z does not exist in a plane model."));
        s.tracked = d * t + tracked_direction;
        AssertThrow(!s.model.is_fixed(s.tracked), ExcMessage("The tracked vertex is clamped."));
        context.pcout << model_kind << ": " << s.mesh.vertices.size() << " vertices, " << s.mesh.cells.size()
                      << " cells, " << solid_materials.size() << " material layer(s), " << driven.size()
                      << " driven vertices, tracked vertex " << t << " at " << s.mesh.vertices[t]
                      << std::endl;
        context.summary.add_number("n_vertices", s.mesh.vertices.size());
        context.summary.add_number("n_cells", s.mesh.cells.size());
      }

      void parse_mechanism(ParameterHandler &prm)
      {
        MechanismDescription &m = mechanism;
        for (const auto &row : parse_rows(prm.get("Joints"), "Joints", 3))
          m.joints.push_back({{row[0], row[1]}}), m.masses.push_back(row[2]);
        for (const auto &row : parse_rows(prm.get("Links"), "Links", 2))
          m.links.push_back({{as_index(row[0], "Links"), as_index(row[1], "Links")}});
        for (const auto &row : parse_rows(prm.get("Rigid joints"), "Rigid joints", 3))
          m.rigid_angles.push_back({{as_index(row[0], "Rigid joints"), as_index(row[1], "Rigid joints"),
                                     as_index(row[2], "Rigid joints")}});
        for (const auto &row : parse_rows(prm.get("Springs"), "Springs", 8))
          {
            MechanismSpring sp;
            sp.link_a = as_index(row[0], "Springs"), sp.u_a = row[1], sp.w_a = row[2];
            sp.link_b = as_index(row[3], "Springs"), sp.u_b = row[4], sp.w_b = row[5];
            sp.stiffness = row[6], sp.rest_length = row[7];
            m.springs.push_back(sp);
          }
        for (const double j : parse_number_list(prm.get("Fixed joints"), "Fixed joints"))
          fixed_joints.push_back(as_index(j, "Fixed joints"));
        for (const double j : parse_number_list(prm.get("Driven joints"), "Driven joints"))
          driven_joints.push_back(as_index(j, "Driven joints"));
        tracked_joint     = prm.get_integer("Tracked joint");
        m.link_stiffness  = prm.get_double("Link stiffness");
        m.angle_stiffness = prm.get_double("Angle stiffness");
        m.gravity         = prm.get_double("Gravity");
        AssertThrow(!m.joints.empty() && !m.links.empty(),
                    ExcMessage("Mechanism: Joints and Links are needed."));
        for (const unsigned int j : fixed_joints)
          AssertThrow(j < m.joints.size(),
                      ExcMessage("Mechanism: fixed joint " + std::to_string(j) + " is missing."));
        for (const unsigned int j : driven_joints)
          AssertThrow(j < m.joints.size(),
                      ExcMessage("Mechanism: driven joint " + std::to_string(j) + " is missing."));
        AssertThrow(tracked_joint < m.joints.size(), ExcMessage("Mechanism: the tracked joint is missing."));
      }

      void build_rods(RunContext &context, Structure &s)
      {
        RodNetworkDescription d = rods_from_polylines(rod_polylines, rod_segments, 1e-9);
        d.material              = rod_material;
        RodNetwork net          = make_rod_network(d);
        s.model = std::move(net.model), s.rest = net.rest_positions, s.dofs_per_vertex = 3;
        s.is_rods = true, s.rod_vertices = d.vertices.size(), s.rod_edges = net.edges;
        auto nearest = [&](const std::vector<double> &p) {
          std::size_t best = 0;
          double      gap  = std::numeric_limits<double>::max();
          for (std::size_t v = 0; v < d.vertices.size(); ++v)
            {
              const double g =
                  std::hypot(d.vertices[v][0] - p[0], d.vertices[v][1] - p[1], d.vertices[v][2] - p[2]);
              if (g < gap)
                gap = g, best = v;
            }
          return best;
        };
        for (const auto &m : rod_masses)
          for (int i = 0; i < 3; ++i)
            s.model.lumped_mass()[3 * nearest(m) + i] += m[3];
        AssertThrow(!rod_driven.empty() || !point_forces.empty(),
                    ExcMessage("The rods need driven points or point forces: nothing excites them."));
        for (const auto &p : rod_driven)
          {
            const std::size_t v = nearest(p);
            for (unsigned int i = 0; i < 3; ++i)
              s.drives.push_back(
                  {3 * v + i, drive_amplitude * drive_direction[i], 0.0, 0.0, s.rest[3 * v + i], {}, {}});
            for (std::size_t j = 0; j < net.junction_vertices.size(); ++j)
              if (net.junction_vertices[j] == v)
                for (unsigned int i = 0; i < 3; ++i)
                  s.model.fix(net.rotation_offset + 3 * j + i, 0.0);
          }
        for (const auto &pf : point_forces)
          {
            const std::size_t v = nearest({pf.first[0], pf.first[1], pf.first[2]});
            for (unsigned int i = 0; i < 3; ++i)
              if (pf.second[i] != 0)
                s.forces.push_back({3 * v + i, pf.second[i], 0.0});
          }
        const std::size_t t = nearest({rod_tracked[0], rod_tracked[1], rod_tracked[2]});
        s.tracked_dofs      = {3 * t, 3 * t + 1, 3 * t + 2};
        s.tracked           = 3 * t + tracked_direction;
        AssertThrow(!s.model.is_fixed(s.tracked), ExcMessage("The tracked vertex is held."));
        context.pcout << "rods: " << d.rods.size() << " rods, " << d.vertices.size() << " vertices, "
                      << net.edges.size() << " edges, " << net.junction_vertices.size() << " junctions, "
                      << rod_masses.size() << " added masses, tracked vertex " << t << std::endl;
        context.summary.add_number("n_vertices", d.vertices.size());
        context.summary.add_number("n_junctions", net.junction_vertices.size());
      }

      void build_mechanism(RunContext &context, Structure &s) const
      {
        MechanismModel mech = make_mechanism_model(mechanism);
        s.model = std::move(mech.model), s.rest = mech.rest_positions, s.dofs_per_vertex = 2;
        s.is_mechanism = true, s.mechanism = mechanism;
        for (const unsigned int j : fixed_joints)
          for (unsigned int i = 0; i < 2; ++i)
            s.model.fix(2 * j + i, s.rest[2 * j + i]);
        AssertThrow(!driven_joints.empty() || !point_forces.empty(),
                    ExcMessage("The mechanism needs driven joints or point forces: nothing excites it."));
        for (const unsigned int j : driven_joints)
          {
            AssertThrow(!s.model.is_fixed(2 * j), ExcMessage("A driven joint is also fixed."));
            for (unsigned int i = 0; i < 2; ++i)
              s.drives.push_back(
                  {2 * j + i, drive_amplitude * drive_direction[i], 0.0, 0.0, s.rest[2 * j + i], {}, {}});
          }
        for (const auto &pf : point_forces)
          {
            std::size_t best = 0;
            for (std::size_t j = 1; j < mechanism.joints.size(); ++j)
              if (std::hypot(mechanism.joints[j][0] - pf.first[0], mechanism.joints[j][1] - pf.first[1]) <
                  std::hypot(mechanism.joints[best][0] - pf.first[0],
                             mechanism.joints[best][1] - pf.first[1]))
                best = j;
            for (unsigned int i = 0; i < 2; ++i)
              if (pf.second[i] != 0)
                s.forces.push_back({2 * best + i, pf.second[i], 0.0});
          }
        s.tracked_dofs = {2 * tracked_joint, 2 * tracked_joint + 1};
        AssertThrow(tracked_direction < 2,
                    ExcMessage("Tracked direction z does not exist in a planar mechanism."));
        s.tracked = 2 * tracked_joint + tracked_direction;
        AssertThrow(!s.model.is_fixed(s.tracked), ExcMessage("The tracked joint is fixed."));
        context.pcout << "mechanism: " << mechanism.joints.size() << " joints, " << mechanism.links.size()
                      << " rigid links, " << mechanism.rigid_angles.size() << " rigid joints, "
                      << mechanism.springs.size() << " springs" << std::endl;
      }

      /// HBM state reached from rest (Newton from the linear response) against Newmark from rest.
      void newmark_checks(RunContext &context, const HarmonicBalance &hb, const Structure &st) const
      {
        context.summary.add_number("newmark_check_frequencies", double(check_frequencies.size()));
        if (check_frequencies.empty())
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
        for (const double w : check_frequencies)
          {
            // Oscillators: Newmark from rest (the transient decays to the stable state; HBM is then
            // started from Newmark's last period, so both are on the same branch). Shells: a flat
            // sheet started from rest is a hard Newton problem in the first steps, so Newmark starts
            // from the HBM state (thesis 2.5.1 does either) and must stay on it.
            const Eigen::VectorXd x_rest  = st.rest;
            const std::size_t     tracked = st.tracked;
            Eigen::VectorXd       z       = hb.static_coefficients(x_rest);
            Eigen::VectorXd       x0 = x_rest, v0 = Eigen::VectorXd::Zero(x_rest.size());
            if (model_kind != "duffing" && model_kind != "two-spring-mass")
              {
                const PeriodicSolveResult r = solve_with_excitation_ramp(hb, z, w);
                AssertThrow(r.converged,
                            ExcMessage("HBM found no periodic state at w = " + std::to_string(w) + "."));
                x0 = hb.positions_at(z, w, {0.0}).col(0), v0 = hb.velocities_at(z, w, {0.0}).col(0);
              }
            const NewmarkResult nm = newmark_steady_state(hb, w, x0, v0, newmark);
            if (!nm.converged)
              {
                context.fail_check(
                    "Newmark did not reach a periodic steady state at w = " + std::to_string(w) +
                    " rad/s in " + std::to_string(nm.periods) + " periods");
                continue;
              }
            if (model_kind == "duffing" || model_kind == "two-spring-mass")
              {
                std::vector<double> t(newmark.steps_per_period);
                const std::size_t   n = hb.n_free();
                for (std::size_t i = 0; i < n; ++i)
                  for (unsigned int kk = 0; kk <= hb.n_harmonics(); ++kk)
                    {
                      double s = 0, c = 0;
                      for (unsigned int j = 0; j < t.size(); ++j)
                        {
                          const double th = 2 * pi * j / t.size(), x = nm.last_period(hb.free()[i], j);
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
            std::vector<double> t(newmark.steps_per_period);
            for (unsigned int j = 0; j < t.size(); ++j)
              t[j] = 2 * pi / w * j / t.size();
            const Eigen::MatrixXd x    = hb.positions_at(z, w, t);
            const double          size = hb.half_range(z, w, tracked);
            const double          diff =
                (x.row(tracked) - nm.last_period.row(tracked)).lpNorm<Eigen::Infinity>() / size;
            worst = std::max(worst, diff);
            const double nm_half =
                0.5 * (nm.last_period.row(tracked).maxCoeff() - nm.last_period.row(tracked).minCoeff());
            table << json_number(w) << "," << json_number(size) << "," << json_number(nm_half) << ","
                  << json_number(diff) << "," << nm.periods << "," << json_number(nm.seconds) << "\n";
            for (unsigned int j = 0; j < t.size(); j += std::max(1u, unsigned(t.size() / 128)))
              trajectories << json_number(w) << "," << json_number(t[j]) << "," << json_number(x(tracked, j))
                           << "," << json_number(nm.last_period(tracked, j)) << "\n";
            context.pcout << "Newmark check at w = " << w << ": " << nm.periods << " periods, HBM vs Newmark "
                          << diff << " relative" << std::endl;
            if (!(diff <= newmark_tolerance))
              context.fail_check("the HBM and Newmark trajectories at w = " + std::to_string(w) +
                                 " rad/s differ by " + std::to_string(diff) +
                                 " of the half range (tolerance " + std::to_string(newmark_tolerance) + ")");
          }
        context.summary.add_figure("newmark_max_difference_relative", worst, "1");
        if (context.is_root())
          {
            write_file_atomically(context.output.file("newmark_check.csv"), table.str());
            write_file_atomically(context.output.file("trajectories.csv"), trajectories.str());
          }
      }

      MeshParameters             mesh;
      ShellMaterial              shell_material;
      std::vector<SolidMaterial> solid_materials;
      unsigned int               layer_axis = 2;
      std::vector<std::string>   clamped_groups, driven_groups;
      bool                       rotation_drive = false;
      Tensor<1, 3>               drive_direction, rotation_axis, rotation_center;
      double                     drive_amplitude = 0, drive_stiffness_factor = 0, rotation_amplitude = 0;
      std::vector<std::pair<Point<3>, Tensor<1, 3>>>  point_forces;
      Point<3>                                        tracked_point;
      unsigned int                                    tracked_direction = 2, period_frames = 0;
      MechanismDescription                            mechanism;
      std::vector<unsigned int>                       fixed_joints, driven_joints;
      unsigned int                                    tracked_joint = 0;
      std::vector<std::vector<std::array<double, 3>>> rod_polylines;
      unsigned int                                    rod_segments = 8;
      RodMaterial                                     rod_material;
      std::vector<std::vector<double>>                rod_masses, rod_driven;
      Point<3>                                        rod_tracked;
      std::string                                     model_kind;
      double                  mass = 1, k = 1, k3 = 1, span = 1, rest_length = 0.8, force = 0.5;
      HarmonicBalanceSettings settings;
      ContinuationSettings    continuation;
      bool                    linear_reference   = true;
      double                  adaptive_threshold = 0, adaptive_frequency = 0;
      std::vector<double>     check_frequencies;
      NewmarkSettings         newmark;
      double                  newmark_tolerance = 1e-3;
      bool                    trace_curve       = true;
      std::vector<double>     evaluation_frequencies, backbone_amplitudes;
      unsigned int            backbone_mode = 1;
    };
  } // namespace

  NLMECH_REGISTER_SCENE(harmonic_balance,
                        (SceneInfo{
                            "harmonic-balance",
                            "Periodic steady states of forced nonlinear structures (oscillators, shells, "
                            "solids, plane structures, compliant mechanisms) by harmonic balance: "
                            "frequency-response curve, folds, stability, resonance peaks, linear modal "
                            "reference, Newmark check.",
                            &HarmonicBalanceScene::declare_parameters,
                            [](ParameterHandler &prm) -> std::unique_ptr<Scene> {
                              return std::make_unique<HarmonicBalanceScene>(prm);
                            }}))
} // namespace nlmech
