#include <deal.II/base/exceptions.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/base/json.h>
#include <nlmech/base/parse.h>
#include <nlmech/base/run_context.h>
#include <nlmech/scenes/inverse/multi_target.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <sstream>

namespace nlmech
{
  using namespace dealii;

  void LoadCase::declare_parameters(ParameterHandler &prm)
  {
    for (unsigned int c = 2; c <= LoadCase::max_cases; ++c)
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
  }

  std::vector<LoadCase> LoadCase::parse_parameters(ParameterHandler &prm)
  {
    std::vector<LoadCase> load_cases;
    for (unsigned int c = 2; c <= LoadCase::max_cases; ++c)
      {
        prm.enter_subsection("Load case " + std::to_string(c));
        LoadCase load_case;
        if (!prm.get("Target mesh").empty())
          load_case.target_mesh = resolve_input_path(prm.get("Target mesh"), current_parameter_directory());
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
    return load_cases;
  }

  Eigen::VectorXd target_positions(const RawSimplexMesh<3> &mesh)
  {
    Eigen::VectorXd x(3 * mesh.vertices.size());
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
      for (int i = 0; i < 3; ++i)
        x[3 * v + i] = mesh.vertices[v][i];
    return x;
  }

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

  /// The target mesh of a load case: same vertices and tetrahedra as the main target, supports
  /// in place (the single rest shape holds them where every target has them).
  RawSimplexMesh<3> load_case_target(const LoadCase &c, const RawSimplexMesh<3> &main,
                                     const MeshParameters            &mesh,
                                     const std::vector<unsigned int> &support_vertices,
                                     const std::string               &name)
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
  Eigen::VectorXd multi_target_rest_shape(RunContext &context, const MultiTargetProblem &p,
                                          const RawSimplexMesh<3>         &target_mesh,
                                          const InverseHyperelasticSystem &system,
                                          const Eigen::VectorXd &load, const Eigen::VectorXd &rest_for_case_1,
                                          const HyperelasticBoundaryConditions &conditions,
                                          const std::vector<unsigned int>      &support_vertices,
                                          Eigen::VectorXd                      *forward_of_case_1)
  {
    TimerOutput::Scope t(context.timer, "multi-target design");
    auto inverse_solves = std::make_unique<TimerOutput::Scope>(context.timer, "multi-target: inverse solves");
    const auto                    &load_cases = p.load_cases;
    const auto                    &anm        = p.anm;
    const auto                    &loads      = p.loads;
    const auto                    &material   = p.material;
    std::vector<RawSimplexMesh<3>> targets    = {target_mesh};
    std::vector<Eigen::VectorXd>   case_loads = {load};
    std::vector<AnmSeries>         series = {AnmSolver(system, load, anm).series_at(rest_for_case_1, 1.0)};
    for (std::size_t c = 0; c < load_cases.size(); ++c)
      {
        const std::string name = "load case " + std::to_string(c + 2);
        targets.push_back(load_case_target(load_cases[c], target_mesh, p.mesh, support_vertices, name));
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
    inverse_solves.reset();
    TimerOutput::Scope forward_checks(context.timer, "multi-target: forward checks");
    // Second method: the mean of the individual rest shapes (the least squares' minimiser).
    Eigen::VectorXd mean = Eigen::VectorXd::Zero(combined.size());
    for (const auto &s : series)
      mean += s.x.front() / double(series.size());
    context.summary.add_figure("reduced_basis_minus_mean_relative", (combined - mean).norm() / mean.norm(),
                               "1");

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
        if (c == 0 && forward_of_case_1 && r.completed)
          *forward_of_case_1 = y;
        csv << c + 1 << "," << json_number((x_t - target_positions(target_mesh)).lpNorm<Eigen::Infinity>())
            << "," << json_number((series[c].x.front() - combined).lpNorm<Eigen::Infinity>()) << ","
            << json_number(distance) << "," << r.completed << "\n";
        context.pcout << "multi-target: case " << c + 1 << " forward distance to its target " << distance
                      << " m" << (r.completed ? "" : " (forward solve incomplete)") << std::endl;
        if (!r.completed)
          context.fail_check("multi-target design: the forward solve of load case " + std::to_string(c + 1) +
                             " from the combined rest shape stopped (" + r.stop_reason + ")");
      }
    if (context.is_root())
      write_file_atomically(context.output.file("multi_target.csv"), csv.str());
    context.summary.add_number("load_cases", targets.size());
    context.summary.add_figure("multi_target_max_forward_distance", worst, "m");
    context.pcout << "multi-target design: " << targets.size() << " load cases combined by the reduced basis"
                  << std::endl;
    return combined;
  }
} // namespace nlmech
