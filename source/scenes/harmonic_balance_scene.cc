// Scene "harmonic-balance": periodic steady states of a small nonlinear oscillator (a Duffing
// spring, or a mass between two geometrically nonlinear springs) under harmonic forcing, by the
// harmonic balance method: the frequency-response curve by continuation with folds, stability and
// resonance peaks, and a Newmark run to steady state at chosen frequencies as the time-domain check.

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/base/json.h>
#include <nlmech/base/progress.h>
#include <nlmech/base/run_context.h>
#include <nlmech/base/scene.h>
#include <nlmech/mesh/vertex_field_output.h>
#include <nlmech/models/dynamics/spring_network.h>
#include <nlmech/models/dynamics/thin_shell.h>
#include <nlmech/scenes/elastic_statics_parameters.h>
#include <nlmech/solvers/hbm/periodic_solvers.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    class HarmonicBalanceScene : public Scene
    {
    public:
      static void declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Oscillator");
        prm.declare_entry("Model", "duffing", Patterns::Selection("duffing|two-spring-mass|shell"),
                          "duffing: m x'' + c x' + k x + k3 x^3 = F cos(w t); two-spring-mass: a mass at the "
                          "middle between two anchors at distance 2 Span, joined by geometric springs of "
                          "rest length L0, forced across the span (a geometric nonlinearity); shell: a thin "
                          "shell (CST St.Venant-Kirchhoff membrane + hinge bending) on the gmsh surface mesh "
                          "of subsection Mesh, with the subsections Shell and Structure.");
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
        prm.enter_subsection("Structure");
        prm.declare_entry("Clamped groups", "", Patterns::Anything(),
                          "Edge or surface groups held at rest, comma-separated.");
        prm.declare_entry("Driven groups", "handle", Patterns::Anything(),
                          "Edge or surface groups moved harmonically: x = X + a d cos(w t) by a stiff "
                          "penalty (thesis 2.A.5), comma-separated. Vertices along one straight edge alone "
                          "leave the shell free to rotate about it.");
        prm.declare_entry("Drive direction", "0, 0, 1", Patterns::Anything(), "d, normalised [-].");
        prm.declare_entry("Drive amplitude", "0.002", Patterns::Double(0), "a [m].");
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
        prm.declare_entry("Period frames", "24", Patterns::Integer(0),
                          "VTU frames (period.pvd) of one period at the first resonance peak, or at the end "
                          "frequency without a peak; 0: none [-].");
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
        prm.leave_subsection();
        prm.enter_subsection("Newmark check");
        prm.declare_entry(
            "Frequencies", "", Patterns::Anything(),
            "Frequencies at which Newmark (beta 1/4, gamma 1/2) from rest is run to the periodic "
            "steady state and compared with the HBM state reached from rest [rad/s].");
        prm.declare_entry("Steps per period", "1024", Patterns::Integer(16), "[-].");
        prm.declare_entry("Period tolerance", "1e-8", Patterns::Double(0),
                          "e_p of thesis eq. (2.5.1), relative [-].");
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
        prm.enter_subsection("Structure");
        for (const auto &g : Utilities::split_string_list(prm.get("Clamped groups"), ','))
          if (!g.empty())
            clamped_groups.push_back(g);
        for (const auto &g : Utilities::split_string_list(prm.get("Driven groups"), ','))
          if (!g.empty())
            driven_groups.push_back(g);
        drive_direction = parse_vector<3>(prm.get("Drive direction"), "Drive direction");
        AssertThrow(drive_direction.norm() > 0, ExcMessage("Drive direction must not be zero."));
        drive_direction /= drive_direction.norm();
        drive_amplitude        = prm.get_double("Drive amplitude");
        drive_stiffness_factor = prm.get_double("Drive stiffness factor");
        point_forces           = parse_point_vectors(prm.get("Point forces"), "Point forces");
        tracked_point          = Point<3>(parse_vector<3>(prm.get("Tracked point"), "Tracked point"));
        period_frames          = prm.get_integer("Period frames");
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
        prm.leave_subsection();
        prm.enter_subsection("Newmark check");
        check_frequencies = parse_number_list(prm.get("Frequencies"), "Frequencies");
        for (const double w : check_frequencies)
          AssertThrow(w > 0, ExcMessage("Newmark check frequencies must be positive."));
        newmark.steps_per_period = prm.get_integer("Steps per period");
        newmark.period_tolerance = prm.get_double("Period tolerance");
        prm.leave_subsection();
        AssertThrow(mass > 0, ExcMessage("Mass must be positive."));
      }

      void run(RunContext &context) override
      {
        Model                      model(0);
        std::size_t                tracked = 0;
        std::vector<HarmonicForce> forces;
        std::vector<HarmonicDrive> drives;
        std::vector<std::size_t>   tracked_dofs;
        if (model_kind == "shell")
          {
            TimerOutput::Scope t(context.timer, "mesh and shell model");
            build_shell(context, model, forces, drives, tracked_dofs);
            tracked = tracked_dofs[2];
          }
        else
          {
            model        = build_model();
            tracked      = model_kind == "duffing" ? 1 : 3;
            forces       = {{tracked, force, 0.0}};
            tracked_dofs = {tracked};
          }
        const HarmonicBalance hb(model, settings, forces, drives);
        context.summary.add_string("model", model_kind);
        context.summary.add_number("harmonics", settings.n_harmonics);
        context.summary.add_number("time_samples", hb.n_samples());
        context.summary.add_number("unknowns", hb.n_unknowns());

        ProgressReporter progress("frequency response", 1.0, context.comm, context.pcout.get_stream());
        continuation.tracked_dofs = tracked_dofs;
        double reported           = 0;
        continuation.progress     = [&](double done) {
          if (done >= reported + 0.1)
            progress.report(done), reported = done;
        };
        FrequencyResponse frc;
        {
          TimerOutput::Scope t(context.timer, "frequency response (HBM continuation)");
          frc = trace_frequency_response(hb, hb.static_coefficients(rest_state(model)), continuation);
        }
        std::ostringstream csv, peaks;
        csv << "omega,amplitude_A,half_range,stable,fold,max_floquet_multiplier,corrector_iterations\n";
        unsigned int folds = 0, unstable = 0;
        for (const auto &p : frc.points)
          {
            csv << json_number(p.omega) << "," << json_number(p.amplitude) << "," << json_number(p.half_range)
                << "," << p.stable << "," << p.fold << "," << json_number(p.max_multiplier) << ","
                << p.iterations << "\n";
            folds += p.fold, unstable += p.stable == 0;
          }
        peaks << "omega,amplitude_A,half_range\n";
        for (const auto &p : frc.peaks)
          peaks << json_number(p.omega) << "," << json_number(p.amplitude) << ","
                << json_number(hb.half_range(p.z, p.omega, tracked)) << "\n";
        context.summary.add_number("points", frc.points.size());
        context.summary.add_number("folds", folds);
        context.summary.add_number("unstable_points", unstable);
        context.summary.add_number("resonance_peaks", frc.peaks.size());
        if (!frc.peaks.empty())
          {
            context.summary.add_figure("first_peak_frequency", frc.peaks.front().omega, "rad/s");
            context.summary.add_figure("first_peak_half_range",
                                       hb.half_range(frc.peaks.front().z, frc.peaks.front().omega, tracked),
                                       "m");
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
            plot(context);
          }
        if (model_kind == "shell" && period_frames > 0 && context.is_root() && !frc.points.empty())
          {
            TimerOutput::Scope     t(context.timer, "output (period VTU/PVD)");
            const Eigen::VectorXd &z = frc.peaks.empty() ? frc.points.back().z : frc.peaks.front().z;
            const double           w = frc.peaks.empty() ? frc.points.back().omega : frc.peaks.front().omega;
            std::vector<double>    times;
            for (unsigned int f = 0; f < period_frames; ++f)
              times.push_back(2 * pi / w * f / period_frames);
            const Eigen::MatrixXd x = hb.positions_at(z, w, times);
            std::vector<std::vector<std::pair<std::string, Eigen::VectorXd>>> frames;
            for (unsigned int f = 0; f < period_frames; ++f)
              frames.push_back({{"displacement", Eigen::VectorXd(x.col(f) - rest_positions)}});
            write_vertex_fields_pvd(shell_mesh,
                                    std::filesystem::path(context.output.file("period.pvd")).parent_path(),
                                    "period", times, frames);
            context.summary.add_figure("period_frames_frequency", w, "rad/s");
          }
        if (!frc.completed)
          {
            context.partial_reason = "frequency response stopped: " + frc.stop_reason;
            return;
          }
        newmark_checks(context, hb, model, tracked);
      }

    private:
      Model build_model() const
      {
        return model_kind == "duffing" ? make_duffing_model(mass, k, k3)
                                       : make_two_spring_mass_model(mass, k, k3, span, rest_length);
      }

      Eigen::VectorXd rest_state(const Model &model) const
      {
        if (model_kind == "shell")
          return rest_positions;
        Eigen::VectorXd x = Eigen::VectorXd::Zero(model.n_unknowns());
        for (const auto &f : model.fixed())
          x[f.first] = f.second;
        return x;
      }

      /// The shell Model, its clamped and driven vertices and its harmonic point forces.
      void build_shell(RunContext &context, Model &model, std::vector<HarmonicForce> &forces,
                       std::vector<HarmonicDrive> &drives, std::vector<std::size_t> &tracked_dofs)
      {
        shell_mesh = read_simplex_mesh<3>(mesh.options(mesh.element_size), 2);
        check_simplex_mesh(shell_mesh, 2);
        ShellModel shell = make_shell_model(shell_mesh, shell_material);
        model            = std::move(shell.model);
        rest_positions   = shell.rest_positions;
        // Vertices of an edge group or of a surface (cell) group.
        auto group_vertices = [&](const std::string &group) {
          std::set<unsigned int> vertices;
          if (shell_mesh.groups.material_ids.count(group))
            {
              const unsigned int id = shell_mesh.groups.material_ids.at(group);
              for (std::size_t c = 0; c < shell_mesh.cells.size(); ++c)
                if (shell_mesh.cell_material[c] == id)
                  vertices.insert(shell_mesh.cells[c].begin(), shell_mesh.cells[c].end());
            }
          else
            {
              const unsigned int id = shell_mesh.groups.boundary_id(group); // clear error if missing
              for (std::size_t f = 0; f < shell_mesh.boundary_faces.size(); ++f)
                if (shell_mesh.boundary_face_id[f] == id)
                  vertices.insert(shell_mesh.boundary_faces[f].begin(), shell_mesh.boundary_faces[f].end());
            }
          AssertThrow(!vertices.empty(), ExcMessage("The group <" + group + "> has no vertices."));
          return vertices;
        };
        for (const auto &g : clamped_groups)
          for (const unsigned int v : group_vertices(g))
            for (unsigned int i = 0; i < 3; ++i)
              model.fix(3 * v + i, rest_positions[3 * v + i]);
        AssertThrow(!driven_groups.empty() || !point_forces.empty(),
                    ExcMessage("The shell needs driven groups or point forces: nothing excites it."));
        double largest_diagonal = 0;
        {
          const Eigen::SparseMatrix<double> K = model.hessian(rest_positions);
          for (Eigen::Index i = 0; i < K.rows(); ++i)
            largest_diagonal = std::max(largest_diagonal, K.coeff(i, i));
        }
        std::size_t n_driven = 0;
        for (const auto &g : driven_groups)
          for (const unsigned int v : group_vertices(g))
            {
              AssertThrow(!model.is_fixed(3 * v),
                          ExcMessage("A driven vertex is also clamped (group <" + g + ">)."));
              for (unsigned int i = 0; i < 3; ++i)
                drives.push_back({3 * v + i, drive_amplitude * drive_direction[i], 0.0,
                                  drive_stiffness_factor * largest_diagonal, rest_positions[3 * v + i]});
              ++n_driven;
            }
        auto nearest = [&](const Point<3> &p) {
          std::size_t best = 0;
          for (std::size_t v = 1; v < shell_mesh.vertices.size(); ++v)
            if (shell_mesh.vertices[v].distance(p) < shell_mesh.vertices[best].distance(p))
              best = v;
          return best;
        };
        for (const auto &pf : point_forces)
          {
            const std::size_t v = nearest(pf.first);
            for (unsigned int i = 0; i < 3; ++i)
              if (pf.second[i] != 0)
                forces.push_back({3 * v + i, pf.second[i], 0.0});
          }
        const std::size_t t = nearest(tracked_point);
        tracked_dofs        = {3 * t, 3 * t + 1, 3 * t + 2};
        context.pcout << "shell: " << shell_mesh.vertices.size() << " vertices, " << shell_mesh.cells.size()
                      << " triangles, " << n_driven << " driven vertices, tracked vertex " << t << " at "
                      << shell_mesh.vertices[t] << std::endl;
        context.summary.add_number("n_vertices", shell_mesh.vertices.size());
        context.summary.add_number("n_triangles", shell_mesh.cells.size());
      }

      void plot(RunContext &context) const
      {
        const std::string script  = std::string(NLMECH_SOURCE_DIR) + "/contrib/plot/frequency_response.py";
        const std::string command = std::string(NLMECH_PYTHON) + " '" + script + "' '" +
                                    context.output.file("frequency_response.csv") + "' '" +
                                    context.output.file("frequency_response.png") +
                                    "' 'HBM frequency response (" + model_kind + ")' '" +
                                    context.output.file("resonance_peaks.csv") + "'";
        if (std::system(command.c_str()) != 0)
          std::cerr << "nlmech: warning: the frequency-response plot could not be drawn (python3/matplotlib)."
                    << std::endl;
      }

      /// HBM state reached from rest (Newton from the linear response) against Newmark from rest.
      void newmark_checks(RunContext &context, const HarmonicBalance &hb, const Model &model,
                          std::size_t tracked) const
      {
        if (check_frequencies.empty())
          return;
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
            const Eigen::VectorXd x_rest = rest_state(model);
            Eigen::VectorXd       z      = hb.static_coefficients(x_rest);
            Eigen::VectorXd       x0 = x_rest, v0 = Eigen::VectorXd::Zero(x_rest.size());
            if (model_kind == "shell")
              {
                const PeriodicSolveResult r = solve_with_excitation_ramp(hb, z, w);
                AssertThrow(r.converged,
                            ExcMessage("HBM found no periodic state at w = " + std::to_string(w) + "."));
                x0 = hb.positions_at(z, w, {0.0}).col(0), v0 = hb.velocities_at(z, w, {0.0}).col(0);
              }
            const NewmarkResult nm = newmark_steady_state(hb, w, x0, v0, newmark);
            AssertThrow(nm.converged, ExcMessage("Newmark did not reach a periodic steady state at w = " +
                                                 std::to_string(w) + " rad/s in " +
                                                 std::to_string(nm.periods) + " periods."));
            if (model_kind != "shell")
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
          }
        context.summary.add_figure("newmark_max_difference_relative", worst, "1");
        if (context.is_root())
          {
            write_file_atomically(context.output.file("newmark_check.csv"), table.str());
            write_file_atomically(context.output.file("trajectories.csv"), trajectories.str());
          }
      }

      MeshParameters                                 mesh;
      ShellMaterial                                  shell_material;
      std::vector<std::string>                       clamped_groups, driven_groups;
      Tensor<1, 3>                                   drive_direction;
      double                                         drive_amplitude = 0, drive_stiffness_factor = 1e3;
      std::vector<std::pair<Point<3>, Tensor<1, 3>>> point_forces;
      Point<3>                                       tracked_point;
      unsigned int                                   period_frames = 0;
      RawSimplexMesh<3>                              shell_mesh;
      Eigen::VectorXd                                rest_positions;
      std::string                                    model_kind;
      double                  mass = 1, k = 1, k3 = 1, span = 1, rest_length = 0.8, force = 0.5;
      HarmonicBalanceSettings settings;
      ContinuationSettings    continuation;
      std::vector<double>     check_frequencies;
      NewmarkSettings         newmark;
    };
  } // namespace

  NLMECH_REGISTER_SCENE(harmonic_balance,
                        (SceneInfo{
                            "harmonic-balance",
                            "Periodic steady states of a forced nonlinear oscillator by harmonic balance: "
                            "frequency-response curve, folds, stability, resonance peaks, Newmark check.",
                            &HarmonicBalanceScene::declare_parameters,
                            [](ParameterHandler &prm) -> std::unique_ptr<Scene> {
                              return std::make_unique<HarmonicBalanceScene>(prm);
                            }}))
} // namespace nlmech
