// Scene "manufactured-solution": linear elasticity on a gmsh unit square or cube with Dirichlet data
// and body force from a known displacement field; reports L2 errors and the fitted convergence order.

#include <deal.II/base/exceptions.h>
#include <deal.II/base/numbers.h>

#include <nlmech/base/run_context.h>
#include <nlmech/base/scene.h>
#include <nlmech/scenes/elastic_statics_study.h>
#include <nlmech/scenes/manufactured_solution.h>

#include <cmath>
#include <filesystem>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    double amplitude(unsigned int d)
    {
      return 0.01 * (1 + 0.5 * d);
    }
    double phase(unsigned int d, unsigned int k)
    {
      return 0.3 * (d + 1) + 0.7 * k;
    }
    double affine_offset(unsigned int d)
    {
      return 0.001 * (d + 1);
    }
    double affine_gradient(unsigned int d, unsigned int k)
    {
      return 0.002 * (1 + d) - 0.003 * k + 0.001 * d * k;
    }
    constexpr double omega = numbers::PI;
  } // namespace

  template <int dim>
  ManufacturedDisplacement<dim>::ManufacturedDisplacement(const bool affine)
      : Function<dim>(dim)
      , affine(affine)
  {
  }

  template <int dim>
  double ManufacturedDisplacement<dim>::value(const Point<dim> &p, const unsigned int d) const
  {
    if (affine)
      {
        double v = affine_offset(d);
        for (unsigned int k = 0; k < dim; ++k)
          v += affine_gradient(d, k) * p[k];
        return v;
      }
    double v = amplitude(d);
    for (unsigned int k = 0; k < dim; ++k)
      v *= std::sin(omega * p[k] + phase(d, k));
    return v;
  }

  template <int dim>
  Tensor<1, dim> ManufacturedDisplacement<dim>::gradient(const Point<dim> &p, const unsigned int d) const
  {
    Tensor<1, dim> g;
    for (unsigned int j = 0; j < dim; ++j)
      {
        if (affine)
          {
            g[j] = affine_gradient(d, j);
            continue;
          }
        double v = amplitude(d);
        for (unsigned int k = 0; k < dim; ++k)
          v *= (k == j ? omega * std::cos(omega * p[k] + phase(d, k)) : std::sin(omega * p[k] + phase(d, k)));
        g[j] = v;
      }
    return g;
  }

  template <int dim>
  SymmetricTensor<2, dim> ManufacturedDisplacement<dim>::hessian(const Point<dim>  &p,
                                                                 const unsigned int d) const
  {
    SymmetricTensor<2, dim> h;
    if (affine)
      return h;
    for (unsigned int i = 0; i < dim; ++i)
      for (unsigned int j = i; j < dim; ++j)
        {
          double v = amplitude(d);
          for (unsigned int k = 0; k < dim; ++k)
            {
              const double s = std::sin(omega * p[k] + phase(d, k)), c = std::cos(omega * p[k] + phase(d, k));
              if (i == j && k == i)
                v *= -omega * omega * s;
              else if (k == i || k == j)
                v *= omega * c;
              else
                v *= s;
            }
          h[i][j] = v;
        }
    return h;
  }

  template <int dim>
  ManufacturedBodyForce<dim>::ManufacturedBodyForce(const ManufacturedDisplacement<dim> &u, double lambda,
                                                    double mu)
      : Function<dim>(dim)
      , u(u)
      , lambda(lambda)
      , mu(mu)
  {
  }

  template <int dim>
  double ManufacturedBodyForce<dim>::value(const Point<dim> &p, const unsigned int i) const
  {
    // f_i = -(lambda + mu) d_i (d_k u_k) - mu d_k d_k u_i
    double grad_div = 0;
    for (unsigned int k = 0; k < dim; ++k)
      grad_div += u.hessian(p, k)[i][k];
    return -(lambda + mu) * grad_div - mu * trace(u.hessian(p, i));
  }

  template class ManufacturedDisplacement<2>;
  template class ManufacturedDisplacement<3>;
  template class ManufacturedBodyForce<2>;
  template class ManufacturedBodyForce<3>;

  namespace
  {
    class ManufacturedScene : public Scene
    {
    public:
      static void declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Dimension", "3", Patterns::Integer(2, 3),
                          "Space dimension: 3 (tetrahedra) or 2 (triangles, plane strain) [-].");
        prm.declare_entry(
            "Manufactured field", "trigonometric", Patterns::Selection("trigonometric|affine"),
            "trigonometric: u_d = A_d prod_k sin(pi x_k + c_dk), for convergence orders; affine: "
            "u = a + B x with no body force, the patch test, reproduced to round-off.");
        MeshParameters::declare_parameters(prm, "", 0.25);
        MeshStudyParameters::declare_parameters(prm, "0.25, 0.125, 0.0625");
        MaterialParameters::declare_parameters(prm, 1e6, 0.3, 0);
        DiscretizationParameters::declare_parameters(prm, 1);
        LinearSolverParameters::declare_parameters(prm);
      }

      explicit ManufacturedScene(ParameterHandler &prm)
      {
        dim    = prm.get_integer("Dimension");
        affine = prm.get("Manufactured field") == "affine";
        mesh.parse_parameters(prm);
        prm.enter_subsection("Mesh");
        if (prm.get("Mesh file").empty())
          mesh.file = std::string(NLMECH_SOURCE_DIR) +
                      (dim == 3 ? "/meshes/unit_cube.geo" : "/meshes/unit_square.geo");
        prm.leave_subsection();
        study.parse_parameters(prm);
        material.parse_parameters(prm);
        discretization.parse_parameters(prm);
        solver.parse_parameters(prm);
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
        s.solver = solver;
        s.title  = std::string("manufactured solution (") + (affine ? "affine" : "trigonometric") + ", " +
                  std::to_string(d) + "D, degree " + std::to_string(discretization.degree) + ")";
        s.error_name    = "l2_error_m";
        s.extra_columns = {"relative_l2_error", "max_vertex_error_m"};
        const ManufacturedDisplacement<d> exact(affine);
        const ManufacturedBodyForce<d>    force(exact, material.material.lame_lambda(),
                                                material.material.shear_modulus());
        s.configure = [&](LinearElasticity<d> &problem, const MeshGroups &groups) {
          AssertThrow(!groups.boundary_ids.empty(),
                      ExcMessage("The mesh <" + mesh.file +
                                 "> has no boundary physical group for the Dirichlet data."));
          for (const auto &g : groups.boundary_ids)
            problem.add_dirichlet(g.second, &exact);
          if (!affine)
            problem.set_body_force(&force);
        };
        s.evaluate = [&](const LinearElasticity<d> &problem, const MeshGroups &) {
          const double error = problem.l2_error(exact);
          // ||u_h - 0||_L2 = ||u_h||_L2, the scale for the relative error.
          const Functions::ZeroFunction<d> zero(d);
          const double                     norm = problem.l2_error(zero);
          return std::make_pair(error, std::vector<double>{error / norm, problem.max_vertex_error(exact)});
        };
        MeshStudyTable table  = s.run(context);
        const auto    &finest = table.rows().back();
        context.summary.add_string("manufactured_field", affine ? "affine" : "trigonometric");
        context.summary.add_figure("l2_error", finest.error, "m");
        context.summary.add_figure("max_vertex_error", finest.extra[1], "m");
        if (table.rows().size() >= 2 && !affine)
          {
            context.summary.add_figure("fitted_l2_order_in_h", table.fitted_order_in_h(), "1");
            context.summary.add_figure("fitted_l2_order_in_dofs", table.fitted_order_in_dofs(d), "1");
            context.pcout << "manufactured solution: fitted L2 order " << table.fitted_order_in_h()
                          << " in h, " << table.fitted_order_in_dofs(d) << " in DOFs^(-1/" << d << ")"
                          << std::endl;
          }
        context.pcout << "manufactured solution: finest L2 error " << finest.error << " m, max vertex error "
                      << finest.extra[1] << " m" << std::endl;
      }

      unsigned int             dim    = 3;
      bool                     affine = false;
      MeshParameters           mesh;
      MeshStudyParameters      study;
      MaterialParameters       material;
      DiscretizationParameters discretization;
      LinearSolverParameters   solver;
    };
  } // namespace

  NLMECH_REGISTER_SCENE(
      manufactured,
      (SceneInfo{"manufactured-solution",
                 "Linear elasticity on a unit square/cube with a manufactured displacement: L2 "
                 "error, convergence order, and the affine patch test.",
                 &ManufacturedScene::declare_parameters, [](ParameterHandler &prm) -> std::unique_ptr<Scene> {
                   return std::make_unique<ManufacturedScene>(prm);
                 }}))
} // namespace nlmech
