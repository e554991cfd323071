// Scene "elastic-statics": linear-elastic statics on any gmsh mesh, with clamped faces, surface
// tractions and gravity addressed by physical-group name.

#include <deal.II/base/exceptions.h>

#include <nlmech/base/gravity_parameter.h>
#include <nlmech/base/run_context.h>
#include <nlmech/base/scene.h>
#include <nlmech/scenes/elastic_statics_study.h>

#include <filesystem>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    class ElasticStaticsScene : public Scene
    {
    public:
      static void declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Dimension", "3", Patterns::Integer(2, 3),
                          "Space dimension of the mesh: 3 (tetrahedra) or 2 (triangles, plane strain) [-].");
        MeshParameters::declare_parameters(prm, NLMECH_SOURCE_DIR "/meshes/cantilever.geo", 0.05);
        MeshStudyParameters::declare_parameters(prm, "");
        MaterialParameters::declare_parameters(prm, 2e11, 0.3, 7800);
        DiscretizationParameters::declare_parameters(prm, 1);
        LinearSolverParameters::declare_parameters(prm);
        prm.enter_subsection("Boundary conditions");
        prm.declare_entry("Clamped groups", "clamped", Patterns::Anything(),
                          "Comma-separated physical groups (faces) where the displacement is zero.");
        prm.leave_subsection();
        prm.enter_subsection("Loads");
        GravityParameter::declare_parameters(prm, 0);
        prm.declare_entry("Tractions", "", Patterns::Anything(),
                          "Surface tractions as `group: t_x, t_y[, t_z]; group: ...` [Pa].");
        prm.leave_subsection();
      }

      explicit ElasticStaticsScene(ParameterHandler &prm)
      {
        dim = prm.get_integer("Dimension");
        mesh.parse_parameters(prm);
        study.parse_parameters(prm);
        material.parse_parameters(prm);
        discretization.parse_parameters(prm);
        solver.parse_parameters(prm);
        prm.enter_subsection("Boundary conditions");
        for (const auto &g : Utilities::split_string_list(prm.get("Clamped groups"), ','))
          if (!g.empty())
            clamped.push_back(g);
        prm.leave_subsection();
        prm.enter_subsection("Loads");
        gravity = GravityParameter::parse_parameters(prm, dim);
        for (const auto &item : Utilities::split_string_list(prm.get("Tractions"), ';'))
          {
            if (item.empty())
              continue;
            const auto parts = Utilities::split_string_list(item, ':');
            AssertThrow(
                parts.size() == 2 && !parts[0].empty(),
                ExcMessage("Tractions must read `group: t_x, t_y, t_z; ...`; <" + item + "> does not."));
            const auto t = parse_number_list(parts[1], "Tractions");
            AssertThrow(t.size() == dim, ExcMessage("The traction on <" + parts[0] + "> needs " +
                                                    std::to_string(dim) + " components."));
            tractions.emplace_back(parts[0], t);
          }
        prm.leave_subsection();
        AssertThrow(!clamped.empty(),
                    ExcMessage("At least one clamped group is needed to prevent rigid-body motion."));
      }

      void validate() const override { mesh.check_exists(); }

      void run(RunContext &context) override
      {
        if (dim == 2)
          run_in<2>(context);
        else
          run_in<3>(context);
      }

    private:
      template <int d>
      void run_in(RunContext &context) const
      {
        ElasticStaticsStudy<d> s;
        s.mesh = mesh, s.study = study, s.material = material, s.discretization = discretization,
        s.solver     = solver;
        s.title      = "elastic statics (" + std::filesystem::path(mesh.file).filename().string() + ")";
        s.error_name = "max_displacement_m"; // no reference: the plot shows the quantity's convergence
        for (const auto &t : tractions)
          s.extra_columns.push_back("mean_displacement_magnitude_on_" + t.first + "_m");
        s.configure = [&](LinearElasticity<d> &problem, const MeshGroups &groups) {
          for (const auto &g : clamped)
            problem.add_dirichlet(groups.boundary_id(g));
          Tensor<1, d> g;
          for (unsigned int i = 0; i < d; ++i)
            g[i] = gravity[i];
          problem.set_gravity(g);
          for (const auto &t : tractions)
            {
              Tensor<1, d> traction;
              for (unsigned int i = 0; i < d; ++i)
                traction[i] = t.second[i];
              problem.add_traction(groups.boundary_id(t.first), traction);
            }
        };
        s.evaluate = [&](const LinearElasticity<d> &problem, const MeshGroups &groups) {
          std::vector<double> extra;
          for (const auto &t : tractions)
            {
              double norm2 = 0;
              for (unsigned int i = 0; i < d; ++i)
                norm2 += std::pow(problem.boundary_mean_displacement(groups.boundary_id(t.first), i), 2);
              extra.push_back(std::sqrt(norm2));
            }
          return std::make_pair(problem.max_displacement(), extra);
        };
        const MeshStudyTable table = s.run(context);
        context.summary.add_figure("max_displacement", table.rows().back().error, "m");
        context.pcout << "elastic statics: max displacement " << table.rows().back().error << " m"
                      << std::endl;
      }

      unsigned int                                             dim = 3;
      MeshParameters                                           mesh;
      MeshStudyParameters                                      study;
      MaterialParameters                                       material;
      DiscretizationParameters                                 discretization;
      LinearSolverParameters                                   solver;
      std::vector<std::string>                                 clamped;
      std::vector<double>                                      gravity;
      std::vector<std::pair<std::string, std::vector<double>>> tractions;
    };
  } // namespace

  NLMECH_REGISTER_SCENE(elastic_statics,
                        (SceneInfo{
                            "elastic-statics",
                            "Linear-elastic statics on any gmsh mesh: clamped groups, surface tractions "
                            "and gravity by physical-group name.",
                            &ElasticStaticsScene::declare_parameters,
                            [](ParameterHandler &prm) -> std::unique_ptr<Scene> {
                              return std::make_unique<ElasticStaticsScene>(prm);
                            }}))
} // namespace nlmech
