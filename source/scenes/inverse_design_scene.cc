// Scene "inverse-design": the rest shape X of a neo-Hookean (or St.Venant-Kirchhoff) object that
// deforms into the given target shape x under its loads (ANM paper, section 4), by the ANM and/or
// Newton, with the forward check built in: the forward solve from X under the same loads and the
// largest distance to the target relative to the bounding-box diagonal.

#include <deal.II/base/exceptions.h>
#include <deal.II/base/function_parser.h>
#include <deal.II/base/utilities.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/base/gravity_parameter.h>
#include <nlmech/base/rank_sharing.h>
#include <nlmech/base/run_context.h>
#include <nlmech/base/scene.h>
#include <nlmech/mesh/msh_output.h>
#include <nlmech/mesh/vertex_field_output.h>
#include <nlmech/models/solid/hyperelastic_model.h>
#include <nlmech/models/solid/inverse_hyperelastic.h>
#include <nlmech/scenes/elastic_statics_parameters.h>
#include <nlmech/scenes/inverse/baselines.h>
#include <nlmech/scenes/inverse/multi_target.h>
#include <nlmech/solvers/anm/anm_solver.h>
#include <nlmech/solvers/linear/sparse_factorization.h>

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
        GravityParameter::declare_parameters(prm, 3, "the weight is that of the target shape");
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
            "stepped adaptively), levenberg-marquardt (the paper's baseline, from its two initial guesses).");
        AnmSettings::declare_parameters(prm);
        InverseBaselineSettings::declare_parameters(prm);
        prm.declare_entry("Round trip tolerance", "1e-6", Patterns::Double(0),
                          "The forward solve from the rest shape under the same loads must land within this "
                          "distance of the target, relative to the target's bounding-box diagonal [-]; above "
                          "it (or when the target is an unstable equilibrium of the rest shape) the run "
                          "keeps its results, says \"status\": \"check_failed\" and exits with 1.");
        prm.leave_subsection();
        LoadCase::declare_parameters(prm);
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
        const std::vector<double> g = GravityParameter::parse_parameters(prm, 3);
        loads.gravity               = Tensor<1, 3>({g[0], g[1], g[2]});
        loads.point_loads           = parse_point_vectors(prm.get("Point loads"), "Point loads");
        prm.leave_subsection();
        prm.enter_subsection("Solver");
        methods = Utilities::split_string_list(prm.get("Methods"), ',');
        anm.parse_parameters(prm);
        baselines.parse_parameters(prm);
        AssertThrow(std::find(methods.begin(), methods.end(), "levenberg-marquardt") == methods.end() ||
                        !baselines.lm_initial_guesses.empty(),
                    ExcMessage("Levenberg-Marquardt is among the methods but \"Levenberg-Marquardt initial "
                               "guesses\" is empty: give target and/or reversed-load."));
        round_trip_tolerance    = prm.get_double("Round trip tolerance");
        const bool multi_target = prm.get_bool("Multi-target design");
        prm.leave_subsection();
        if (multi_target)
          load_cases = LoadCase::parse_parameters(prm);
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
        // Under mpirun every rank evaluates its block of the elements; the solvers see the sums.
        const ShareElementsOverRanks sharing(context.comm);
        context.summary.add_number("element_sharing_ranks", element_sharing_ranks());
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

        Eigen::VectorXd rest = x;
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
        const InverseBaselineProblem baseline{
            system, on_target.load, x, anm.residual_tolerance, on_target.internal, anm};
        if (uses("newton") && context.partial_reason.empty())
          {
            TimerOutput::Scope    t(context.timer, "inverse Newton");
            const Eigen::VectorXd rest_newton =
                inverse_newton_baseline(context, baselines, baseline, methods.size() == 1);
            if (methods.front() == "newton")
              rest = rest_newton;
            else if (rest_newton.size() && uses("anm"))
              context.summary.add_figure("anm_newton_difference",
                                         (rest - rest_newton).lpNorm<Eigen::Infinity>(), "m");
          }
        if (uses("levenberg-marquardt") && context.partial_reason.empty())
          {
            TimerOutput::Scope    t(context.timer, "inverse Levenberg-Marquardt");
            const bool            primary = methods.front() == "levenberg-marquardt";
            const Eigen::VectorXd rest_lm =
                inverse_levenberg_marquardt_baseline(context, baselines, baseline, primary);
            if (primary)
              rest = rest_lm;
          }

        Eigen::VectorXd forward_of_case_1; // the multi-target design's own forward solve of case 1
        if (!load_cases.empty() && uses("anm") && context.partial_reason.empty())
          rest =
              multi_target_rest_shape(context, {load_cases, mesh, loads, material, anm}, target_mesh, system,
                                      on_target.load, rest, conditions, support_vertices, &forward_of_case_1);

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
            x_forward                   = forward.rest_positions;
            AnmResult check;
            if (forward_of_case_1.size() > 0)
              x_forward = forward_of_case_1, check.completed = true;
            else
              check = AnmSolver(forward.internal, forward.load, anm).solve(x_forward); // same tolerance
            // Stability of the equilibrium the fabricated part reaches (the target itself with one
            // target; with several, the main case's forward solution from the compromise): a
            // positive definite Hessian there. An unstable one cannot be realised by the part.
            SparseFactorization stability;
            stability.factorize(FreeDofMap(forward.internal)
                                    .restrict(forward.internal.hessian(load_cases.empty() ? x : x_forward)));
            context.summary.add_bool("target_equilibrium_stable", stability.positive_definite());
            if (!stability.positive_definite())
              context.fail_check("the target is an unstable equilibrium of the computed rest shape: a "
                                 "fabricated part would not stay in it (a stiffer material or more supports "
                                 "help)");
            context.summary.add_bool("forward_check_completed", check.completed);
            context.summary.add_number("forward_check_anm_steps", check.steps.size());
            context.summary.add_number("forward_check_factorizations", check.factorizations);
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
            write_file_atomically(context.output.file("rest_shape.msh"), simplex_mesh_msh(target_mesh, rest));
          }
      }

    private:
      MeshParameters                 mesh;
      HyperelasticMaterialParameters material_parameters;
      HyperelasticMaterial           material;
      std::vector<std::string>       supports;
      HyperelasticLoads              loads;
      std::vector<std::string>       methods;
      AnmSettings                    anm;
      InverseBaselineSettings        baselines;
      double                         round_trip_tolerance = 1e-6;
      std::vector<LoadCase>          load_cases;
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
