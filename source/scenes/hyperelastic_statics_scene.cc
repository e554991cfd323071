// Scene "hyperelastic-statics": forward static equilibrium of a neo-Hookean or St.Venant-Kirchhoff
// solid on a gmsh tetrahedral mesh, by the Asymptotic Numerical Method and/or Newton with load
// stepping, side by side on the same Model.

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/base/gravity_parameter.h>
#include <nlmech/base/rank_sharing.h>
#include <nlmech/base/run_context.h>
#include <nlmech/base/scene.h>
#include <nlmech/mesh/vertex_field_output.h>
#include <nlmech/models/solid/hyperelastic_model.h>
#include <nlmech/scenes/elastic_statics_parameters.h>
#include <nlmech/solvers/anm/anm_solver.h>
#include <nlmech/solvers/newton/nox_newton.h>
#include <nlmech/solvers/relaxation/kinetic_damping.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>
#include <sstream>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    class HyperelasticStaticsScene : public Scene
    {
    public:
      static void declare_parameters(ParameterHandler &prm)
      {
        MeshParameters::declare_parameters(prm, NLMECH_SOURCE_DIR "/meshes/cantilever.geo", 0.05);
        HyperelasticMaterialParameters::declare_parameters(prm, 1e5, 0.4, 1100);
        prm.enter_subsection("Boundary conditions");
        prm.declare_entry("Clamped groups", "clamped", Patterns::Anything(),
                          "Comma-separated face groups held at their rest position.");
        prm.declare_entry("Roller groups", "", Patterns::Anything(),
                          "Face groups with one fixed component, as `group: x|y|z; ...`.");
        prm.leave_subsection();
        prm.enter_subsection("Loads");
        GravityParameter::declare_parameters(prm, 3);
        prm.declare_entry("Tractions", "", Patterns::Anything(),
                          "Nominal tractions per rest area, `group: t_x, t_y, t_z; ...` [Pa].");
        prm.declare_entry(
            "Point loads", "", Patterns::Anything(),
            "Forces at the vertices nearest to given points, `x, y, z: f_x, f_y, f_z; ...` [m: N].");
        prm.leave_subsection();
        prm.enter_subsection("Solver");
        prm.declare_entry(
            "Methods", "anm", Patterns::MultipleSelection("anm|newton|newton-nox|kinetic-damping"),
            "Comma-separated, run side by side on the same model: anm (Asymptotic Numerical Method), newton "
            "(Newton with line search and load stepping, CHOLMOD), newton-nox (Trilinos NOX line-search "
            "Newton with load stepping, Amesos KLU/MUMPS; rows distributed over MPI ranks), kinetic-damping "
            "(implicit Euler dynamic relaxation "
            "with "
            "kinetic damping).");
        AnmSettings::declare_parameters(prm);
        prm.declare_entry("Newton load steps", "10", Patterns::Integer(1), "Load increments for Newton [-].");
        NewtonSettings::declare_parameters(prm);
        prm.declare_entry(
            "Load scales", "", Patterns::Anything(),
            "After the ANM reaches lambda = 1: other load factors to explore, comma-separated [-]. "
            "Inside the radius of the series at lambda = 1 a scale costs a polynomial root and a "
            "series evaluation (paper section 5.1); outside it, a new continuation from lambda = 1.");
        prm.leave_subsection();
      }

      explicit HyperelasticStaticsScene(ParameterHandler &prm)
      {
        mesh.parse_parameters(prm);
        material_parameters.parse_parameters(prm);
        material = material_parameters.material;
        prm.enter_subsection("Boundary conditions");
        for (const auto &g : Utilities::split_string_list(prm.get("Clamped groups"), ','))
          if (!g.empty())
            conditions.clamped.push_back(g);
        for (const auto &item : Utilities::split_string_list(prm.get("Roller groups"), ';'))
          {
            if (item.empty())
              continue;
            const auto parts = Utilities::split_string_list(item, ':');
            AssertThrow(parts.size() == 2 && (parts[1] == "x" || parts[1] == "y" || parts[1] == "z"),
                        ExcMessage("Roller groups must read `group: x|y|z; ...`; <" + item + "> does not."));
            conditions.rollers.emplace_back(parts[0], parts[1] == "x" ? 0u : parts[1] == "y" ? 1u : 2u);
          }
        prm.leave_subsection();
        prm.enter_subsection("Loads");
        const std::vector<double> g = GravityParameter::parse_parameters(prm, 3);
        loads.gravity               = Tensor<1, 3>({g[0], g[1], g[2]});
        loads.tractions             = parse_group_vectors(prm.get("Tractions"), "Tractions");
        loads.point_loads           = parse_point_vectors(prm.get("Point loads"), "Point loads");
        prm.leave_subsection();
        prm.enter_subsection("Solver");
        for (const auto &m : Utilities::split_string_list(prm.get("Methods"), ','))
          methods.insert(m);
        anm.parse_parameters(prm);
        newton_steps = prm.get_integer("Newton load steps");
        newton.parse_parameters(prm);
        load_scales = parse_number_list(prm.get("Load scales"), "Load scales");
        prm.leave_subsection();
      }

      void validate() const override { mesh.check_exists(); }

      void run(RunContext &context) override
      {
        // Under mpirun every rank evaluates its block of the elements; the solvers see the sums.
        const ShareElementsOverRanks sharing(context.comm);
        context.summary.add_number("element_sharing_ranks", element_sharing_ranks());
        RawSimplexMesh<3> raw;
        {
          TimerOutput::Scope t(context.timer, "mesh (gmsh + checks)");
          raw = read_simplex_mesh<3>(mesh.options(mesh.element_size), 3);
          check_simplex_mesh(raw, 3);
        }
        const HyperelasticProblem problem = make_hyperelastic_problem(raw, material, conditions, loads);
        context.pcout << "hyperelastic statics: " << raw.vertices.size() << " vertices, " << raw.cells.size()
                      << " tetrahedra, " << FreeDofMap(problem.internal).n_free() << " free unknowns"
                      << std::endl;
        context.summary.add_number("n_vertices", raw.vertices.size());
        context.summary.add_number("n_tetrahedra", raw.cells.size());
        context.summary.add_figure("total_force", resultant_force(problem.load).norm(), "N");

        std::vector<std::pair<std::string, Eigen::VectorXd>> fields;
        Eigen::VectorXd                                      x_anm, x_newton;
        double                                               scale = 0;
        if (methods.count("anm"))
          {
            TimerOutput::Scope t(context.timer, "ANM");
            x_anm                  = problem.rest_positions;
            const AnmResult result = AnmSolver(problem.internal, problem.load, anm).solve(x_anm);
            JsonObject      s;
            s.add_bool("completed", result.completed);
            s.add_number("lambda_reached", result.lambda);
            s.add_number("largest_lambda_on_path", result.extreme_lambda);
            s.add_number("steps", result.steps.size());
            s.add_number("factorizations", result.factorizations);
            s.add_number("back_substitutions", result.back_substitutions);
            s.add_figure("series_time", result.series_seconds, "s");
            s.add_figure("factorization_time", result.factorization_seconds, "s");
            s.add_figure("back_substitution_time", result.solve_seconds, "s");
            s.add_figure("wall_time", result.total_seconds, "s");
            s.add_figure("max_displacement", (x_anm - problem.rest_positions).lpNorm<Eigen::Infinity>(), "m");
            s.add_figure("min_det_F", problem.elastic->min_jacobian(x_anm), "1");
            context.summary.add_object("anm", s);
            std::ostringstream csv;
            csv << "step,lambda_begin,lambda_end,step_length,series_radius,corrections,relative_residual,"
                   "limited_by_inversion,pade_radius,used_pade\n";
            for (std::size_t i = 0; i < result.steps.size(); ++i)
              {
                const auto &r = result.steps[i];
                csv << i << "," << json_number(r.lambda_begin) << "," << json_number(r.lambda_end) << ","
                    << json_number(r.step_length) << "," << json_number(r.series_radius) << ","
                    << r.corrections << "," << json_number(r.residual) << "," << r.limited_by_inversion << ","
                    << json_number(r.pade_radius) << "," << r.used_pade << "\n";
              }
            if (context.is_root())
              write_file_atomically(context.output.file("anm_steps.csv"), csv.str());
            context.pcout << "ANM: " << (result.completed ? "reached" : "stopped at")
                          << " lambda = " << result.lambda << " in " << result.steps.size() << " steps, "
                          << result.factorizations << " factorizations, " << result.total_seconds << " s"
                          << std::endl;
            fields.emplace_back("displacement_anm", x_anm - problem.rest_positions);
            if (result.completed && !load_scales.empty())
              explore_load_scales(context, problem, x_anm);
            scale = std::max(scale, (x_anm - problem.rest_positions).lpNorm<Eigen::Infinity>());
            if (!result.completed)
              context.partial_reason = "ANM: " + result.stop_reason;
          }
        if (methods.count("newton") && context.partial_reason.empty())
          {
            TimerOutput::Scope t(context.timer, "Newton with load stepping");
            x_newton                        = problem.rest_positions;
            const LoadSteppingResult result = solve_with_load_stepping(
                problem.internal, problem.load, x_newton, newton_steps, anm.residual_tolerance, newton);
            JsonObject s;
            s.add_number("load_steps", newton_steps);
            s.add_number("iterations", result.iterations);
            s.add_number("factorizations", result.factorizations);
            s.add_figure("wall_time", result.seconds, "s");
            s.add_figure("max_displacement", (x_newton - problem.rest_positions).lpNorm<Eigen::Infinity>(),
                         "m");
            context.summary.add_object("newton", s);
            context.pcout << "Newton: " << result.iterations << " iterations in " << newton_steps
                          << " load steps, " << result.seconds << " s" << std::endl;
            fields.emplace_back("displacement_newton", x_newton - problem.rest_positions);
            scale = std::max(scale, (x_newton - problem.rest_positions).lpNorm<Eigen::Infinity>());
          }
        Eigen::VectorXd x_nox;
        if (methods.count("newton-nox") && context.partial_reason.empty())
          {
            TimerOutput::Scope t(context.timer, "NOX Newton with load stepping");
            x_nox = problem.rest_positions;
            NoxNewtonSettings settings;
            settings.load_steps         = newton_steps;
            settings.relative_tolerance = anm.residual_tolerance;
            const ModelEquilibrium system(problem.internal);
            const auto             energy = [&](const Eigen::VectorXd &q) {
              return problem.internal.is_valid(q) ? problem.internal.energy(q)
                                                              : std::numeric_limits<double>::infinity();
            };
            const NoxNewtonResult result =
                solve_equilibrium_with_nox(system, problem.load, x_nox, settings, context.comm, energy);
            JsonObject s;
            s.add_number("load_steps", newton_steps);
            s.add_number("iterations", result.iterations);
            s.add_number("factorizations", result.factorizations);
            s.add_number("residual_evaluations", result.residuals);
            s.add_string("direct_solver", result.direct_solver);
            s.add_figure("wall_time", result.seconds, "s");
            s.add_figure("max_displacement", (x_nox - problem.rest_positions).lpNorm<Eigen::Infinity>(), "m");
            context.summary.add_object("newton_nox", s);
            context.pcout << "NOX Newton (" << result.direct_solver << "): " << result.iterations
                          << " iterations in " << newton_steps << " load steps, " << result.seconds << " s"
                          << std::endl;
            fields.emplace_back("displacement_newton_nox", x_nox - problem.rest_positions);
            scale = std::max(scale, (x_nox - problem.rest_positions).lpNorm<Eigen::Infinity>());
          }
        Eigen::VectorXd x_relaxed;
        if (methods.count("kinetic-damping") && context.partial_reason.empty())
          {
            TimerOutput::Scope t(context.timer, "kinetic damping");
            x_relaxed = problem.rest_positions;
            KineticDampingSettings settings;
            settings.relative_tolerance = anm.residual_tolerance;
            const KineticDampingResult result =
                solve_with_kinetic_damping(problem.internal, problem.load, x_relaxed, settings);
            JsonObject s;
            s.add_bool("converged", result.converged);
            s.add_number("time_steps", result.time_steps);
            s.add_figure("time_step", result.time_step, "s");
            s.add_number("velocity_resets", result.velocity_resets);
            s.add_number("newton_iterations", result.newton_iterations);
            s.add_number("factorizations", result.factorizations);
            s.add_figure("wall_time", result.seconds, "s");
            s.add_number("final_relative_residual", result.residual);
            context.summary.add_object("kinetic_damping", s);
            context.pcout << "kinetic damping: " << (result.converged ? "converged" : "NOT converged")
                          << " in " << result.time_steps << " time steps, " << result.factorizations
                          << " factorizations, " << result.seconds << " s" << std::endl;
            fields.emplace_back("displacement_kinetic_damping", x_relaxed - problem.rest_positions);
            scale = std::max(scale, (x_relaxed - problem.rest_positions).lpNorm<Eigen::Infinity>());
            if (!result.converged)
              context.partial_reason = "kinetic damping did not converge in " +
                                       std::to_string(result.time_steps) + " time steps (relative residual " +
                                       std::to_string(result.residual) + ", at lambda = 1)";
          }
        if (x_anm.size() && x_newton.size())
          context.summary.add_figure("anm_newton_difference_relative",
                                     (x_anm - x_newton).lpNorm<Eigen::Infinity>() / scale, "1");
        if (x_anm.size() && x_nox.size())
          context.summary.add_figure("anm_newton_nox_difference_relative",
                                     (x_anm - x_nox).lpNorm<Eigen::Infinity>() / scale, "1");
        if (x_newton.size() && x_nox.size())
          context.summary.add_figure("newton_newton_nox_difference_relative",
                                     (x_newton - x_nox).lpNorm<Eigen::Infinity>() / scale, "1");
        if (x_anm.size() && x_relaxed.size())
          context.summary.add_figure("anm_kinetic_damping_difference_relative",
                                     (x_anm - x_relaxed).lpNorm<Eigen::Infinity>() / scale, "1");
        if (context.is_root())
          {
            TimerOutput::Scope t(context.timer, "output (VTU)");
            write_vertex_fields_vtu(raw, fields, {}, context.output.file("solution.vtu"));
            if (!fields.empty())
              write_vertex_displacements_csv(raw, fields.front().second,
                                             context.output.file("vertex_displacements.csv"));
          }
      }

    private:
      /// Section 5.1: other load scales from the series at the solution, or a new continuation.
      void explore_load_scales(RunContext &context, const HyperelasticProblem &problem,
                               const Eigen::VectorXd &solution) const
      {
        TimerOutput::Scope t(context.timer, "ANM load-scale changes");
        const AnmSolver    solver(problem.internal, problem.load, anm);
        const AnmSeries    series = solver.series_at(solution, 1.0);
        const FreeDofMap   free(problem.internal);
        const double       g = free.restrict(problem.load).norm();
        std::ostringstream csv;
        csv << "load_scale,how,relative_residual,max_displacement_m,wall_time_s\n";
        for (const double scale : load_scales)
          {
            const auto      start = std::chrono::steady_clock::now();
            const double    a     = series.parameter_for(scale);
            Eigen::VectorXd x     = solution;
            std::string     how   = "series";
            if (std::isfinite(a))
              x = series.state(a);
            else
              {
                how                    = "continuation";
                const AnmResult result = solver.solve(x, 1.0, scale);
                if (!result.completed)
                  how = "continuation stopped: " + result.stop_reason;
              }
            const double seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            const double residual =
                (free.restrict(problem.internal.gradient(x)) - scale * free.restrict(problem.load)).norm() /
                g;
            csv << json_number(scale) << "," << how << "," << json_number(residual) << ","
                << json_number((x - problem.rest_positions).lpNorm<Eigen::Infinity>()) << ","
                << json_number(seconds) << "\n";
            context.pcout << "load scale " << scale << ": " << how << ", relative residual " << residual
                          << ", " << seconds << " s" << std::endl;
          }
        if (context.is_root())
          write_file_atomically(context.output.file("load_scales.csv"), csv.str());
      }

      MeshParameters                 mesh;
      HyperelasticMaterialParameters material_parameters;
      HyperelasticMaterial           material;
      HyperelasticBoundaryConditions conditions;
      HyperelasticLoads              loads;
      std::set<std::string>          methods;
      AnmSettings                    anm;
      unsigned int                   newton_steps = 10;
      NewtonSettings                 newton;
      std::vector<double>            load_scales;
    };
  } // namespace

  NLMECH_REGISTER_SCENE(hyperelastic_statics,
                        (SceneInfo{
                            "hyperelastic-statics",
                            "Neo-Hookean / St.Venant-Kirchhoff static equilibrium on a gmsh mesh by the "
                            "Asymptotic Numerical Method and/or Newton with load stepping.",
                            &HyperelasticStaticsScene::declare_parameters,
                            [](ParameterHandler &prm) -> std::unique_ptr<Scene> {
                              return std::make_unique<HyperelasticStaticsScene>(prm);
                            }}))
} // namespace nlmech
