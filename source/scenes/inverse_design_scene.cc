// Scene "inverse-design": the rest shape X of a neo-Hookean (or St.Venant-Kirchhoff) object that
// deforms into the given target shape x under its loads (ANM paper, section 4), by the ANM and/or
// Newton, with the forward check built in: the forward solve from X under the same loads and the
// largest distance to the target relative to the bounding-box diagonal.

#include <deal.II/base/exceptions.h>
#include <deal.II/base/function_parser.h>
#include <deal.II/base/utilities.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/base/run_context.h>
#include <nlmech/base/scene.h>
#include <nlmech/mesh/vertex_field_output.h>
#include <nlmech/models/solid/hyperelastic_model.h>
#include <nlmech/models/solid/inverse_hyperelastic.h>
#include <nlmech/scenes/elastic_statics_parameters.h>
#include <nlmech/solvers/anm/anm_solver.h>
#include <nlmech/solvers/linear/sparse_factorization.h>
#include <nlmech/solvers/relaxation/levenberg_marquardt.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    /// The rest shape as a gmsh 2.2 ASCII mesh with the physical groups of the target.
    std::string rest_shape_msh(const RawSimplexMesh<3> &mesh, const Eigen::VectorXd &X)
    {
      std::ostringstream out;
      out.precision(17);
      out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n"
          << mesh.groups.boundary_ids.size() + mesh.groups.material_ids.size() << "\n";
      for (const auto &g : mesh.groups.boundary_ids)
        out << "2 " << g.second << " \"" << g.first << "\"\n";
      for (const auto &g : mesh.groups.material_ids)
        out << "3 " << g.second << " \"" << g.first << "\"\n";
      out << "$EndPhysicalNames\n$Nodes\n" << mesh.vertices.size() << "\n";
      for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
        out << v + 1 << " " << X[3 * v] << " " << X[3 * v + 1] << " " << X[3 * v + 2] << "\n";
      out << "$EndNodes\n$Elements\n" << mesh.boundary_faces.size() + mesh.cells.size() << "\n";
      std::size_t id = 1;
      for (std::size_t f = 0; f < mesh.boundary_faces.size(); ++f, ++id)
        out << id << " 2 2 " << mesh.boundary_face_id[f] << " " << mesh.boundary_face_id[f] << " "
            << mesh.boundary_faces[f][0] + 1 << " " << mesh.boundary_faces[f][1] + 1 << " "
            << mesh.boundary_faces[f][2] + 1 << "\n";
      for (std::size_t c = 0; c < mesh.cells.size(); ++c, ++id)
        out << id << " 4 2 " << mesh.cell_material[c] << " " << mesh.cell_material[c] << " "
            << mesh.cells[c][0] + 1 << " " << mesh.cells[c][1] + 1 << " " << mesh.cells[c][2] + 1 << " "
            << mesh.cells[c][3] + 1 << "\n";
      out << "$EndElements\n";
      return out.str();
    }

    Eigen::VectorXd target_positions(const RawSimplexMesh<3> &mesh)
    {
      Eigen::VectorXd x(3 * mesh.vertices.size());
      for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
        for (int i = 0; i < 3; ++i)
          x[3 * v + i] = mesh.vertices[v][i];
      return x;
    }

    /// u(x) from three muparser expressions separated by `;`, parsed and evaluated once here so that
    /// a bad expression is one clear error (deal.II's parser reports to std::cerr, silenced here).
    std::unique_ptr<FunctionParser<3>> displacement_function(const std::string &text, const std::string &name)
    {
      auto                  u     = std::make_unique<FunctionParser<3>>(3);
      const auto            parts = Utilities::split_string_list(text, ';');
      std::ostringstream    silenced;
      std::streambuf *const saved = std::cerr.rdbuf(silenced.rdbuf());
      bool                  ok    = parts.size() == 3;
      try
        {
          if (ok)
            {
              u->initialize("x,y,z", parts, {});
              for (unsigned int i = 0; i < 3; ++i)
                ok = ok && std::isfinite(u->value(Point<3>(), i));
            }
        }
      catch (...)
        {
          ok = false;
        }
      std::cerr.rdbuf(saved);
      AssertThrow(ok, ExcMessage(name + ": cannot parse the target displacement <" + text +
                                 "> (three expressions in x, y, z separated by `;`)."));
      return u;
    }

    class InverseDesignScene : public Scene
    {
    public:
      static void declare_parameters(ParameterHandler &prm)
      {
        MeshParameters::declare_parameters(prm, NLMECH_SOURCE_DIR "/meshes/cantilever.geo", 0.05);
        HyperelasticMaterialParameters::declare_parameters(prm, 1e5, 0.45, 1100);
        prm.enter_subsection("Supports");
        prm.declare_entry(
            "Clamped groups", "clamped", Patterns::Anything(),
            "Face groups attached to the support: their rest position is their target position.");
        prm.leave_subsection();
        prm.enter_subsection("Loads");
        prm.declare_entry("Gravity", "0, 0, -9.81", Patterns::Anything(),
                          "Gravitational acceleration [m/s^2]; the weight is that of the target shape.");
        prm.declare_entry(
            "Point loads", "", Patterns::Anything(),
            "Forces at the target vertices nearest to given points, `x, y, z: f_x, f_y, f_z; ...` "
            "[m: N].");
        prm.leave_subsection();
        prm.enter_subsection("Solver");
        prm.declare_entry(
            "Methods", "anm", Patterns::MultipleSelection("anm|newton|levenberg-marquardt"),
            "Comma-separated, side by side on the same target; the first listed gives the rest shape: anm "
            "(Asymptotic Numerical Method from X = x), newton (Newton with line search on the residual, load "
            "stepped), levenberg-marquardt (the paper's baseline, from X = x).");
        prm.declare_entry("ANM order", "20", Patterns::Integer(2, 31), "Truncation order n [-].");
        prm.declare_entry("Series tolerance", "1e-6", Patterns::Double(0), "r of eqs. (19)-(20) [-].");
        prm.declare_entry("Residual tolerance", "1e-9", Patterns::Double(0),
                          "|residual| <= tol |load| at the end [-].");
        prm.declare_entry("Newton load steps", "5", Patterns::Integer(1), "Load increments for Newton [-].");
        prm.declare_entry("Round trip tolerance", "1e-6", Patterns::Double(0),
                          "The forward solve from the rest shape under the same loads must land within this "
                          "distance of the target, relative to the target's bounding-box diagonal [-]; above "
                          "it (or when the target is an unstable equilibrium of the rest shape) the run "
                          "keeps its results, says \"status\": \"check_failed\" and exits with 1.");
        prm.leave_subsection();
        // Multi-target design (paper section 5.2): further targets x_t with loads g_t.
        for (unsigned int c = 2; c <= max_load_cases; ++c)
          {
            prm.enter_subsection("Load case " + std::to_string(c));
            prm.declare_entry("Target mesh", "", Patterns::Anything(),
                              "Target shape x_t of this case: a .msh (or .geo, meshed like the main "
                              "target) with the main target's vertices and tetrahedra in the same order; "
                              "empty: the main target (moved by `Target displacement`, if given).");
            prm.declare_entry("Target displacement", "", Patterns::Anything(),
                              "x_t = x + u(x) on the main target, u as three muparser expressions in x, y, "
                              "z separated by `;` [m], e.g. `0; 0; -0.01*(x/0.3)^2`; empty: none.");
            prm.declare_entry("Load scale", "1", Patterns::Double(0),
                              "g_t = scale * (gravity and point loads of the main case) + the point "
                              "loads below [-].");
            prm.declare_entry("Point loads", "", Patterns::Anything(),
                              "Extra forces of this case at the target vertices nearest to given points, "
                              "`x, y, z: f_x, f_y, f_z; ...` [m: N].");
            prm.leave_subsection();
          }
        prm.enter_subsection("Solver");
        prm.declare_entry(
            "Multi-target design", "false", Patterns::Bool(),
            "Use the load cases 2, 3, ...: each target gets its own ANM rest shape and series, the "
            "rest shape written is the reduced-basis least-squares one over all cases (section 5.2), "
            "and multi_target.csv gives each case's forward distance to its target.");
        prm.leave_subsection();
      }

      explicit InverseDesignScene(ParameterHandler &prm)
      {
        mesh.parse_parameters(prm);
        material_parameters.parse_parameters(prm);
        material = material_parameters.material;
        prm.enter_subsection("Supports");
        for (const auto &g : Utilities::split_string_list(prm.get("Clamped groups"), ','))
          if (!g.empty())
            supports.push_back(g);
        prm.leave_subsection();
        AssertThrow(!supports.empty(),
                    ExcMessage("Inverse design needs at least one clamped (support) group."));
        prm.enter_subsection("Loads");
        loads.gravity     = parse_vector<3>(prm.get("Gravity"), "Gravity");
        loads.point_loads = parse_point_vectors(prm.get("Point loads"), "Point loads");
        prm.leave_subsection();
        prm.enter_subsection("Solver");
        methods                 = Utilities::split_string_list(prm.get("Methods"), ',');
        anm.order               = prm.get_integer("ANM order");
        anm.series_tolerance    = prm.get_double("Series tolerance");
        anm.residual_tolerance  = prm.get_double("Residual tolerance");
        newton_steps            = prm.get_integer("Newton load steps");
        round_trip_tolerance    = prm.get_double("Round trip tolerance");
        const bool multi_target = prm.get_bool("Multi-target design");
        prm.leave_subsection();
        for (unsigned int c = 2; c <= max_load_cases && multi_target; ++c)
          {
            prm.enter_subsection("Load case " + std::to_string(c));
            LoadCase load_case;
            if (!prm.get("Target mesh").empty())
              load_case.target_mesh =
                  resolve_input_path(prm.get("Target mesh"), current_parameter_directory());
            load_case.displacement = prm.get("Target displacement");
            load_case.scale        = prm.get_double("Load scale");
            load_case.point_loads  = parse_point_vectors(prm.get("Point loads"), "Point loads");
            AssertThrow(load_case.target_mesh.empty() || load_case.displacement.empty(),
                        ExcMessage("Load case " + std::to_string(c) +
                                   ": give a target mesh or a target displacement, not both."));
            if (!load_case.displacement.empty())
              displacement_function(load_case.displacement, "Load case " + std::to_string(c));
            if (!load_case.target_mesh.empty() || !load_case.displacement.empty() || load_case.scale != 1.0 ||
                !load_case.point_loads.empty())
              load_cases.push_back(load_case);
            prm.leave_subsection();
          }
        AssertThrow(
            !multi_target || !load_cases.empty(),
            ExcMessage("Multi-target design is on but no load case 2, 3, ... differs from the main one."));
      }

      void validate() const override
      {
        mesh.check_exists();
        for (const auto &c : load_cases)
          AssertThrow(c.target_mesh.empty() || std::filesystem::exists(c.target_mesh),
                      ExcMessage("The target mesh <" + c.target_mesh + "> of a load case does not exist."));
      }

      void run(RunContext &context) override
      {
        RawSimplexMesh<3> target_mesh;
        {
          TimerOutput::Scope t(context.timer, "mesh (gmsh + checks)");
          target_mesh = read_simplex_mesh<3>(mesh.options(mesh.element_size), 3);
          check_simplex_mesh(target_mesh, 3); // an inverted target element is a clear error here
        }
        HyperelasticBoundaryConditions conditions;
        conditions.clamped = supports;
        // The load vector (weight of the target shape, point loads) and the support vertices.
        const HyperelasticProblem on_target =
            make_hyperelastic_problem(target_mesh, material, conditions, loads);
        std::vector<unsigned int> support_vertices;
        for (const auto &f : on_target.internal.fixed())
          if (f.first % 3 == 0)
            support_vertices.push_back(f.first / 3);
        const Eigen::VectorXd          &x = on_target.rest_positions;
        const InverseHyperelasticSystem system(target_mesh, x, material, support_vertices);
        const double                    total_force = resultant_force(on_target.load).norm();
        context.pcout << "inverse design: " << target_mesh.vertices.size() << " vertices, "
                      << target_mesh.cells.size() << " tetrahedra, resultant load " << total_force << " N"
                      << std::endl;
        context.summary.add_figure("total_force", total_force, "N");
        context.summary.add_number("n_vertices", target_mesh.vertices.size());
        context.summary.add_number("n_tetrahedra", target_mesh.cells.size());

        Eigen::VectorXd rest = x, rest_newton;
        auto            uses = [&](const std::string &m) {
          return std::find(methods.begin(), methods.end(), m) != methods.end();
        };
        if (uses("anm"))
          {
            TimerOutput::Scope t(context.timer, "inverse ANM");
            const AnmResult    result = AnmSolver(system, on_target.load, anm).solve(rest);
            JsonObject         s;
            s.add_bool("completed", result.completed);
            s.add_number("lambda_reached", result.lambda);
            s.add_number("steps", result.steps.size());
            s.add_number("factorizations", result.factorizations);
            s.add_number("back_substitutions", result.back_substitutions);
            s.add_figure("series_time", result.series_seconds, "s");
            s.add_figure("factorization_time", result.factorization_seconds, "s");
            s.add_figure("wall_time", result.total_seconds, "s");
            context.summary.add_object("anm", s);
            context.pcout << "inverse ANM: " << (result.completed ? "reached" : "stopped at")
                          << " lambda = " << result.lambda << " in " << result.steps.size() << " steps, "
                          << result.factorizations << " factorizations, " << result.total_seconds << " s"
                          << std::endl;
            if (!result.completed)
              context.partial_reason = "inverse ANM: " + result.stop_reason;
          }
        if (uses("newton") && context.partial_reason.empty())
          {
            TimerOutput::Scope t(context.timer, "inverse Newton");
            rest_newton = x;
            JsonObject s;
            s.add_number("load_steps", newton_steps);
            try
              {
                const LoadSteppingResult result = solve_equilibrium_with_newton(
                    system, on_target.load, rest_newton, newton_steps, anm.residual_tolerance);
                s.add_bool("completed", true);
                s.add_number("iterations", result.iterations);
                s.add_number("factorizations", result.factorizations);
                s.add_figure("wall_time", result.seconds, "s");
                context.pcout << "inverse Newton: " << result.iterations << " iterations, " << result.seconds
                              << " s" << std::endl;
              }
            catch (const ExceptionBase &e)
              {
                // The baseline failing is a result, not an error of the run (unless it is the only method).
                std::ostringstream message;
                e.print_info(message);
                AssertThrow(methods.size() > 1, ExcMessage("inverse Newton: " + message.str()));
                s.add_bool("completed", false);
                s.add_string("failure", message.str());
                context.pcout << "inverse Newton failed: " << message.str() << std::endl;
                rest_newton.resize(0);
              }
            context.summary.add_object("newton", s);
            if (methods.front() == "newton")
              rest = rest_newton;
            else if (rest_newton.size() && uses("anm"))
              context.summary.add_figure("anm_newton_difference",
                                         (rest - rest_newton).lpNorm<Eigen::Infinity>(), "m");
          }

        if (uses("levenberg-marquardt") && context.partial_reason.empty())
          {
            TimerOutput::Scope         t(context.timer, "inverse Levenberg-Marquardt");
            Eigen::VectorXd            rest_lm = x;
            LevenbergMarquardtSettings settings;
            settings.relative_tolerance = anm.residual_tolerance;
            const LevenbergMarquardtResult result =
                solve_with_levenberg_marquardt(system, on_target.load, rest_lm, settings);
            JsonObject s;
            s.add_bool("converged", result.converged);
            s.add_number("iterations", result.iterations);
            s.add_number("factorizations", result.factorizations);
            s.add_figure("wall_time", result.seconds, "s");
            s.add_number("final_relative_residual", result.residual);
            context.summary.add_object("levenberg_marquardt", s);
            context.pcout << "inverse Levenberg-Marquardt: "
                          << (result.converged ? "converged" : "NOT converged") << " in " << result.iterations
                          << " iterations, " << result.seconds << " s" << std::endl;
            if (methods.front() == "levenberg-marquardt")
              {
                rest = rest_lm;
                if (!result.converged)
                  context.partial_reason = "Levenberg-Marquardt did not converge (relative residual " +
                                           std::to_string(result.residual) + ")";
              }
          }

        if (!load_cases.empty() && uses("anm") && context.partial_reason.empty())
          rest = multi_target_rest_shape(context, target_mesh, system, on_target.load, rest, conditions,
                                         support_vertices);

        // Verification: forward from the rest shape under the same loads must return the target.
        double lo[3], hi[3];
        for (int i = 0; i < 3; ++i)
          lo[i] = hi[i] = x[i];
        for (std::size_t v = 0; v < target_mesh.vertices.size(); ++v)
          for (int i = 0; i < 3; ++i)
            lo[i] = std::min(lo[i], x[3 * v + i]), hi[i] = std::max(hi[i], x[3 * v + i]);
        const double diagonal =
            std::sqrt(std::pow(hi[0] - lo[0], 2) + std::pow(hi[1] - lo[1], 2) + std::pow(hi[2] - lo[2], 2));
        Eigen::VectorXd x_forward = rest;
        if (context.partial_reason.empty())
          {
            TimerOutput::Scope t(context.timer, "forward check");
            RawSimplexMesh<3>  rest_mesh = target_mesh;
            for (std::size_t v = 0; v < rest_mesh.vertices.size(); ++v)
              rest_mesh.vertices[v] = Point<3>(rest[3 * v], rest[3 * v + 1], rest[3 * v + 2]);
            HyperelasticProblem forward = make_hyperelastic_problem(rest_mesh, material, conditions, {});
            forward.load                = on_target.load;
            // Stability of the target as an equilibrium of the rest shape: a positive definite
            // Hessian there. An unstable target cannot be realised by the fabricated part.
            SparseFactorization stability;
            stability.factorize(FreeDofMap(forward.internal).restrict(forward.internal.hessian(x)));
            context.summary.add_bool("target_equilibrium_stable", stability.positive_definite());
            if (!stability.positive_definite())
              context.fail_check("the target is an unstable equilibrium of the computed rest shape: a "
                                 "fabricated part would not stay in it (a stiffer material or more supports "
                                 "help)");
            x_forward                   = forward.rest_positions;
            AnmSettings settings        = anm;
            settings.residual_tolerance = std::min(anm.residual_tolerance, 1e-10);
            const AnmResult check = AnmSolver(forward.internal, forward.load, settings).solve(x_forward);
            context.summary.add_bool("forward_check_completed", check.completed);
            const double error = (x_forward - x).lpNorm<Eigen::Infinity>() / diagonal;
            context.summary.add_figure("round_trip_error_relative_to_diagonal", error, "1");
            context.summary.add_figure("bounding_box_diagonal", diagonal, "m");
            context.summary.add_figure("max_rest_to_target_distance", (rest - x).lpNorm<Eigen::Infinity>(),
                                       "m");
            context.summary.add_figure("round_trip_tolerance", round_trip_tolerance, "1");
            context.pcout << "forward check: max |x_forward - x_target| / diagonal = " << error
                          << " (tolerance " << round_trip_tolerance << ")" << std::endl;
            // With several targets the rest shape is a compromise: multi_target.csv and
            // multi_target_max_forward_distance measure it, not the distance to the main target.
            if (!check.completed)
              context.fail_check("the forward round trip from the rest shape did not reach the full load (" +
                                 check.stop_reason + ")");
            else if (load_cases.empty() && !(error <= round_trip_tolerance))
              {
                std::ostringstream what;
                what << "the forward round trip misses the target by " << error
                     << " of the bounding-box diagonal (tolerance " << round_trip_tolerance << ")";
                context.fail_check(what.str());
              }
          }
        if (context.is_root())
          {
            TimerOutput::Scope t(context.timer, "output");
            write_vertex_fields_vtu(
                target_mesh, {{"rest_minus_target", rest - x}, {"forward_minus_target", x_forward - x}}, {},
                context.output.file("target.vtu"));
            write_file_atomically(context.output.file("rest_shape.msh"), rest_shape_msh(target_mesh, rest));
          }
      }

    private:
      /// A further target x_t and its loads g_t (paper section 5.2).
      struct LoadCase
      {
        std::string                                    target_mesh;  // file, or empty
        std::string                                    displacement; // u(x), or empty
        double                                         scale = 1;
        std::vector<std::pair<Point<3>, Tensor<1, 3>>> point_loads;
      };

      /// The target mesh of a load case: same vertices and tetrahedra as the main target, supports
      /// in place (the single rest shape holds them where every target has them).
      RawSimplexMesh<3> load_case_target(const LoadCase &c, const RawSimplexMesh<3> &main,
                                         const std::vector<unsigned int> &support_vertices,
                                         const std::string               &name) const
      {
        RawSimplexMesh<3> t = main;
        if (!c.target_mesh.empty())
          {
            MeshOptions options = mesh.options(mesh.element_size);
            options.file        = c.target_mesh;
            t                   = read_simplex_mesh<3>(options, 3);
            AssertThrow(t.vertices.size() == main.vertices.size() && t.cells == main.cells,
                        ExcMessage(name + ": the target mesh <" + c.target_mesh + "> has " +
                                   std::to_string(t.vertices.size()) + " vertices and " +
                                   std::to_string(t.cells.size()) + " tetrahedra, not the main target's " +
                                   std::to_string(main.vertices.size()) + " and " +
                                   std::to_string(main.cells.size()) + " in the same order."));
            t.groups = main.groups, t.boundary_faces = main.boundary_faces,
            t.boundary_face_id = main.boundary_face_id, t.cell_material = main.cell_material;
          }
        else if (!c.displacement.empty())
          {
            const auto u = displacement_function(c.displacement, name);
            for (auto &v : t.vertices)
              {
                Point<3> moved = v;
                for (unsigned int i = 0; i < 3; ++i)
                  moved[i] += u->value(v, i);
                v = moved;
              }
          }
        check_simplex_mesh(t, 3); // an inverted target element is a clear error
        for (const unsigned int v : support_vertices)
          AssertThrow(t.vertices[v].distance(main.vertices[v]) <= 1e-12 * (1 + main.vertices[v].norm()),
                      ExcMessage(name + ": support vertex " + std::to_string(v) +
                                 " is not where the main target has it; one rest shape cannot be "
                                 "clamped in two places."));
        return t;
      }

      /// Section 5.2: one rest shape for the main target and the further load cases.
      Eigen::VectorXd multi_target_rest_shape(RunContext &context, const RawSimplexMesh<3> &target_mesh,
                                              const InverseHyperelasticSystem      &system,
                                              const Eigen::VectorXd                &load,
                                              const Eigen::VectorXd                &rest_for_case_1,
                                              const HyperelasticBoundaryConditions &conditions,
                                              const std::vector<unsigned int>      &support_vertices) const
      {
        TimerOutput::Scope             t(context.timer, "multi-target design");
        std::vector<RawSimplexMesh<3>> targets    = {target_mesh};
        std::vector<Eigen::VectorXd>   case_loads = {load};
        std::vector<AnmSeries> series = {AnmSolver(system, load, anm).series_at(rest_for_case_1, 1.0)};
        for (std::size_t c = 0; c < load_cases.size(); ++c)
          {
            const std::string name = "load case " + std::to_string(c + 2);
            targets.push_back(load_case_target(load_cases[c], target_mesh, support_vertices, name));
            HyperelasticLoads case_loads_spec = loads;
            case_loads_spec.gravity *= load_cases[c].scale;
            for (auto &p : case_loads_spec.point_loads)
              p.second *= load_cases[c].scale;
            for (const auto &p : load_cases[c].point_loads)
              case_loads_spec.point_loads.push_back(p);
            const HyperelasticProblem on_case =
                make_hyperelastic_problem(targets.back(), material, conditions, case_loads_spec);
            case_loads.push_back(on_case.load);
            const InverseHyperelasticSystem case_system(targets.back(), on_case.rest_positions, material,
                                                        support_vertices);
            const AnmSolver                 solver(case_system, on_case.load, anm);
            Eigen::VectorXd                 X      = on_case.rest_positions; // the ANM starts at X = x_t
            const AnmResult                 result = solver.solve(X);
            AssertThrow(result.completed, ExcMessage("Multi-target design: the inverse ANM for " + name +
                                                     " stopped: " + result.stop_reason));
            series.push_back(solver.series_at(X, 1.0));
          }
        const Eigen::VectorXd combined = reduced_basis_rest_shape(series);
        // Second method: the mean of the individual rest shapes (the least squares' minimiser).
        Eigen::VectorXd mean = Eigen::VectorXd::Zero(combined.size());
        for (const auto &s : series)
          mean += s.x.front() / double(series.size());
        context.summary.add_figure("reduced_basis_minus_mean_relative",
                                   (combined - mean).norm() / mean.norm(), "1");

        RawSimplexMesh<3> rest_mesh = target_mesh;
        for (std::size_t v = 0; v < rest_mesh.vertices.size(); ++v)
          rest_mesh.vertices[v] = Point<3>(combined[3 * v], combined[3 * v + 1], combined[3 * v + 2]);
        HyperelasticProblem forward = make_hyperelastic_problem(rest_mesh, material, conditions, {});
        std::ostringstream  csv;
        csv << "load_case,target_distance_to_main_target_m,individual_rest_distance_to_combined_m,"
               "forward_distance_to_target_m,forward_completed\n";
        double worst = 0;
        for (std::size_t c = 0; c < targets.size(); ++c)
          {
            forward.load                   = case_loads[c];
            const Eigen::VectorXd x_t      = target_positions(targets[c]);
            Eigen::VectorXd       y        = forward.rest_positions;
            const AnmResult       r        = AnmSolver(forward.internal, forward.load, anm).solve(y);
            const double          distance = (y - x_t).lpNorm<Eigen::Infinity>();
            worst                          = std::max(worst, distance);
            csv << c + 1 << ","
                << json_number((x_t - target_positions(target_mesh)).lpNorm<Eigen::Infinity>()) << ","
                << json_number((series[c].x.front() - combined).lpNorm<Eigen::Infinity>()) << ","
                << json_number(distance) << "," << r.completed << "\n";
            context.pcout << "multi-target: case " << c + 1 << " forward distance to its target " << distance
                          << " m" << (r.completed ? "" : " (forward solve incomplete)") << std::endl;
            if (!r.completed)
              context.fail_check("multi-target design: the forward solve of load case " +
                                 std::to_string(c + 1) + " from the combined rest shape stopped (" +
                                 r.stop_reason + ")");
          }
        if (context.is_root())
          write_file_atomically(context.output.file("multi_target.csv"), csv.str());
        context.summary.add_number("load_cases", targets.size());
        context.summary.add_figure("multi_target_max_forward_distance", worst, "m");
        context.pcout << "multi-target design: " << targets.size()
                      << " load cases combined by the reduced basis" << std::endl;
        return combined;
      }

      MeshParameters                 mesh;
      HyperelasticMaterialParameters material_parameters;
      HyperelasticMaterial           material;
      std::vector<std::string>       supports;
      HyperelasticLoads              loads;
      std::vector<std::string>       methods;
      AnmSettings                    anm;
      unsigned int                   newton_steps         = 5;
      double                         round_trip_tolerance = 1e-6;
      std::vector<LoadCase>          load_cases;
      static constexpr unsigned int  max_load_cases = 4;
    };
  } // namespace

  NLMECH_REGISTER_SCENE(inverse_design,
                        (SceneInfo{
                            "inverse-design",
                            "Rest shape that deforms into a target shape under its loads (neo-Hookean), by "
                            "the ANM and/or Newton, with the forward round trip checked.",
                            &InverseDesignScene::declare_parameters,
                            [](ParameterHandler &prm) -> std::unique_ptr<Scene> {
                              return std::make_unique<InverseDesignScene>(prm);
                            }}))
} // namespace nlmech
