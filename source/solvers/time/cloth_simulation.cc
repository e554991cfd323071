#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>

#include <nlmech/base/parse.h>

#include <nlmech/solvers/newton/newton_solver.h>
#include <nlmech/solvers/time/cloth_simulation.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace nlmech
{
  void ClothSettings::declare_parameters(dealii::ParameterHandler &prm)
  {
    using namespace dealii;
    prm.enter_subsection("Time stepping");
    prm.declare_entry("Time step", "0.0166666666667", Patterns::Double(0), "[s]");
    prm.declare_entry("Newton tolerance", "1e-8", Patterns::Double(0),
                      "Relative gradient norm of the implicit steps [-].");
    prm.declare_entry("Newton velocity tolerance", "1e-4", Patterns::Double(0),
                      "Also converged when a full Newton step moves no vertex faster than this "
                      "(|dx|_inf / time step); 0: the gradient criterion only [m/s].");
    prm.declare_entry("Area barrier", "0.1", Patterns::Double(0, 0.99),
                      "Triangles crushed below this fraction of their rest area meet a log "
                      "barrier (St.Venant-Kirchhoff alone lets a soft sheet collapse triangles, "
                      "which stalls Newton); 0: none [-].");
    prm.declare_entry("Newton Hessian", "projected", Patterns::Selection("projected|exact"),
                      "projected: every element's Hessian block is projected to positive "
                      "semi-definite (robust when the sheet wrinkles under compression); exact: "
                      "the true Hessian, shifted by a multiple of the identity where indefinite.");
    prm.leave_subsection();
    prm.enter_subsection("Collisions");
    prm.declare_entry("Sphere stiffness", "0", Patterns::Double(0),
                      "Penalty k/2 depth^2 per vertex against the sphere; 0: no sphere [N/m].");
    prm.declare_entry("Sphere center", "0.25, -0.2, 0.25", Patterns::Anything(), "[m]");
    prm.declare_entry("Sphere radius", "0.12", Patterns::Double(0), "[m]");
    prm.declare_entry("Ground stiffness", "0", Patterns::Double(0), "0: no ground [N/m].");
    prm.declare_entry("Ground height", "-1", Patterns::Double(), "[m]");
    prm.leave_subsection();
  }

  void ClothSettings::parse_parameters(dealii::ParameterHandler &prm)
  {
    prm.enter_subsection("Time stepping");
    time_step                 = prm.get_double("Time step");
    newton_tolerance          = prm.get_double("Newton tolerance");
    project_element_hessians  = prm.get("Newton Hessian") == "projected";
    newton_velocity_tolerance = prm.get_double("Newton velocity tolerance");
    area_barrier              = prm.get_double("Area barrier");
    prm.leave_subsection();
    prm.enter_subsection("Collisions");
    sphere_stiffness = prm.get_double("Sphere stiffness");
    sphere           = sphere_stiffness > 0;
    const auto c     = parse_number_list(prm.get("Sphere center"), "Sphere center");
    AssertThrow(c.size() == 3, dealii::ExcMessage("Sphere center needs three coordinates."));
    sphere_center    = {{c[0], c[1], c[2]}};
    sphere_radius    = prm.get_double("Sphere radius");
    ground_stiffness = prm.get_double("Ground stiffness");
    ground           = ground_stiffness > 0;
    ground_height    = prm.get_double("Ground height");
    prm.leave_subsection();
  }

  namespace
  {
    double since(std::chrono::steady_clock::time_point t0)
    {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }

    /// A guard against crushed triangles, inactive for ordinary states: per triangle with area
    /// ratio J = area / rest area below J^ it adds w b(J), b(J) = -(J - J^)^2 ln(J / J^) (IPC's
    /// clamped log barrier, C2 at J^), w = mu t A. St.Venant-Kirchhoff alone charges only a finite
    /// energy for collapsing a triangle; a fine, soft sheet collapses some, and at zero area the
    /// hinges' normals (and so the bending energy) lose their derivatives and Newton stalls.
    struct AreaBarrierElements : MembraneElements // its triangles, rest areas and dofs
    {
      std::vector<double> weight;
      double              threshold = 0.1;

      template <typename S>
      S energy(const std::array<S, 9> &x, std::size_t e) const
      {
        using std::log;
        using std::sqrt;
        S u[3], w[3];
        for (int i = 0; i < 3; ++i)
          u[i] = x[3 + i] - x[i], w[i] = x[6 + i] - x[i];
        const S n0 = u[1] * w[2] - u[2] * w[1], n1 = u[2] * w[0] - u[0] * w[2],
                n2 = u[0] * w[1] - u[1] * w[0];
        const S J  = 0.5 * sqrt(n0 * n0 + n1 * n1 + n2 * n2) / area[e];
        if (!(Sacado::ScalarValue<S>::eval(J) < threshold))
          return S(0.0);
        const S d = J - threshold;
        return -weight[e] * d * d * log(J / threshold);
      }
    };

    /// 1/(2 dt^2) |x - x_hat|_M^2 - f.x: inertia of an implicit step and the external forces.
    class InertiaTerm : public EnergyTerm
    {
    public:
      InertiaTerm(const Eigen::VectorXd &mass, Eigen::VectorXd x_hat, double dt, Eigen::VectorXd force)
          : mass(mass)
          , x_hat(std::move(x_hat))
          , weight(1 / (dt * dt))
          , force(std::move(force))
      {
      }
      std::string name() const override { return "inertia"; }
      double      value(const Eigen::VectorXd &x) const override
      {
        return 0.5 * weight * (x - x_hat).cwiseAbs2().dot(mass) - force.dot(x);
      }
      void add_gradient(const Eigen::VectorXd &x, Eigen::VectorXd &g) const override
      {
        g += weight * mass.cwiseProduct(x - x_hat) - force;
      }
      void add_hessian(const Eigen::VectorXd &, Triplets &h) const override
      {
        for (Eigen::Index i = 0; i < mass.size(); ++i)
          h.emplace_back(i, i, weight * mass[i]);
      }

    private:
      const Eigen::VectorXd &mass;
      Eigen::VectorXd        x_hat;
      double                 weight;
      Eigen::VectorXd        force;
    };

    /// Penalty contact with a sphere and a ground plane y >= h: k/2 depth^2 per vertex.
    class ContactTerm : public EnergyTerm
    {
    public:
      explicit ContactTerm(const ClothSettings &s)
          : s(s)
      {
      }
      std::string name() const override { return "contact"; }
      double      value(const Eigen::VectorXd &x) const override
      {
        double e = 0;
        for (Eigen::Index v = 0; v < x.size() / 3; ++v)
          {
            const Eigen::Vector3d p = x.segment<3>(3 * v);
            if (s.sphere)
              e += 0.5 * s.sphere_stiffness *
                   std::pow(std::max(0.0, s.sphere_radius - (p - center()).norm()), 2);
            if (s.ground)
              e += 0.5 * s.ground_stiffness * std::pow(std::max(0.0, s.ground_height - p[1]), 2);
          }
        return e;
      }
      void add_gradient(const Eigen::VectorXd &x, Eigen::VectorXd &g) const override
      {
        for (Eigen::Index v = 0; v < x.size() / 3; ++v)
          {
            const Eigen::Vector3d p = x.segment<3>(3 * v);
            if (s.sphere)
              {
                const Eigen::Vector3d r = p - center();
                const double          d = r.norm(), depth = s.sphere_radius - d;
                if (depth > 0 && d > 0)
                  g.segment<3>(3 * v) -= s.sphere_stiffness * depth * r / d;
              }
            if (s.ground && p[1] < s.ground_height)
              g[3 * v + 1] -= s.ground_stiffness * (s.ground_height - p[1]);
          }
      }
      void add_hessian(const Eigen::VectorXd &x, Triplets &h) const override
      {
        for (Eigen::Index v = 0; v < x.size() / 3; ++v)
          {
            const Eigen::Vector3d p = x.segment<3>(3 * v);
            if (s.sphere)
              {
                const Eigen::Vector3d r = p - center();
                const double          d = r.norm(), depth = s.sphere_radius - d;
                if (depth > 0 && d > 0)
                  {
                    // k (n n^T - depth / d (I - n n^T)), with n = r / d.
                    const Eigen::Vector3d n = r / d;
                    const Eigen::Matrix3d H =
                        s.sphere_stiffness *
                        (n * n.transpose() - depth / d * (Eigen::Matrix3d::Identity() - n * n.transpose()));
                    for (int a = 0; a < 3; ++a)
                      for (int b = 0; b < 3; ++b)
                        h.emplace_back(3 * v + a, 3 * v + b, H(a, b));
                  }
              }
            if (s.ground && p[1] < s.ground_height)
              h.emplace_back(3 * v + 1, 3 * v + 1, s.ground_stiffness);
          }
      }

    private:
      Eigen::Vector3d center() const
      {
        return Eigen::Vector3d(s.sphere_center[0], s.sphere_center[1], s.sphere_center[2]);
      }
      ClothSettings s;
    };
  } // namespace

  ClothScheme parse_cloth_scheme(const std::string &name)
  {
    for (const ClothScheme s : {ClothScheme::ie, ClothScheme::sap, ClothScheme::sar, ClothScheme::bdf2,
                                ClothScheme::bap, ClothScheme::bar})
      if (to_string(s) == name)
        return s;
    AssertThrow(false, dealii::ExcMessage("Unknown time-stepping scheme '" + name +
                                          "' (IE, SAP, SAR, BDF2, BAP or BAR)."));
    return ClothScheme::ie;
  }
  std::string to_string(const ClothScheme scheme)
  {
    switch (scheme)
      {
        case ClothScheme::ie: return "IE";
        case ClothScheme::sap: return "SAP";
        case ClothScheme::sar: return "SAR";
        case ClothScheme::bdf2: return "BDF2";
        case ClothScheme::bap: return "BAP";
        default: return "BAR";
      }
  }
  bool uses_projection(const ClothScheme scheme)
  {
    return scheme == ClothScheme::sap || scheme == ClothScheme::sar || scheme == ClothScheme::bap ||
           scheme == ClothScheme::bar;
  }

  ClothSimulation::ClothSimulation(const RawSimplexMesh<3> &mesh, const ShellMaterial &material,
                                   const std::vector<unsigned int> &pinned, const StrainLimits &limits,
                                   const ClothSettings &settings, ConicSettings cone_settings,
                                   const std::vector<std::array<double, 3>> &pin_offsets)
      : model(make_shell_model(mesh, material))
      , limits(limits)
      , settings(settings)
  {
    AssertThrow(settings.time_step > 0 && std::isfinite(settings.time_step),
                dealii::ExcMessage("Cloth: the time step must be positive."));
    AssertThrow(pin_offsets.empty() || pin_offsets.size() == pinned.size(),
                dealii::ExcMessage("Cloth: give one offset per pinned vertex, or none."));
    x = model.rest_positions;
    for (std::size_t k = 0; k < pinned.size(); ++k)
      {
        const unsigned int p = pinned[k];
        AssertThrow(p < mesh.vertices.size(), dealii::ExcMessage("Cloth: a pinned vertex does not exist."));
        for (unsigned int d = 0; d < 3; ++d)
          {
            x[3 * p + d] += pin_offsets.empty() ? 0.0 : pin_offsets[k][d];
            model.model.fix(3 * p + d, x[3 * p + d]);
          }
      }
    if (settings.sphere || settings.ground)
      model.model.add_term(std::make_shared<ContactTerm>(settings));
    if (settings.area_barrier > 0)
      {
        AssertThrow(settings.area_barrier < 1,
                    dealii::ExcMessage("Cloth: the area barrier is a fraction of the rest area, below 1."));
        const auto         &membrane = model.membrane->elements();
        AreaBarrierElements guard;
        static_cast<MembraneElements &>(guard) = membrane;
        guard.threshold                        = settings.area_barrier;
        for (const double a : membrane.area)
          guard.weight.push_back(membrane.mu * membrane.thickness * a);
        model.model.add_term(
            std::make_shared<ElementEnergyTerm<AreaBarrierElements>>("area barrier", std::move(guard)));
      }
    v = Eigen::VectorXd::Zero(x.size());
    force.resize(x.size());
    for (Eigen::Index i = 0; i < x.size(); ++i)
      force[i] = model.model.lumped_mass()[i] * settings.gravity[std::size_t(i % 3)];
    if (uses_projection(settings.scheme))
      {
        AssertThrow(limits.size() > 0, dealii::ExcMessage("Cloth: scheme " + to_string(settings.scheme) +
                                                          " needs strain limits."));
        projector = std::make_unique<StrainLimitProjector>(limits, model.model.lumped_mass(),
                                                           model.model.fixed(), cone_settings);
      }
  }

  ClothSimulation::~ClothSimulation() = default;

  Eigen::VectorXd ClothSimulation::minimise(const Eigen::VectorXd &x_hat, const double dt_effective,
                                            const Eigen::VectorXd &start, ClothStepStatistics &stats) const
  {
    const auto started = std::chrono::steady_clock::now();
    Model      step(model.model.n_unknowns());
    for (const auto &term : model.model.terms())
      step.add_term(term);
    step.lumped_mass() = model.model.lumped_mass();
    for (const auto &f : model.model.fixed())
      step.fix(f.first, f.second);
    step.add_term(std::make_shared<InertiaTerm>(model.model.lumped_mass(), x_hat, dt_effective, force));
    Eigen::VectorXd y = start;
    NewtonSettings  ns;
    ns.relative_tolerance = settings.newton_tolerance;
    ns.max_iterations     = 100;
    ns.step_tolerance     = settings.newton_velocity_tolerance * dt_effective;
    NewtonSolver newton(
        ns, settings.project_element_hessians
                ? std::shared_ptr<HessianRegularization>(std::make_shared<ProjectedElementHessians>())
                : std::make_shared<DiagonalShift>());
    NewtonResult r;
    try
      {
        r = newton.minimize(step, y);
      }
    catch (const dealii::ExceptionBase &e)
      {
        // Say where the sheet was when Newton gave up: the sharpest fold (a hinge near 180 degrees
        // is a sheet folded onto itself) and the most compressed triangle.
        double      sharpest = 0;
        const auto &hinges   = model.bending->elements();
        for (std::size_t h = 0; h < hinges.n_elements(); ++h)
          {
            std::array<double, 12> local;
            const auto             dofs = hinges.dofs(h);
            for (std::size_t i = 0; i < 12; ++i)
              local[i] = y[dofs[i]];
            sharpest = std::max(sharpest, std::abs(HingeElements::dihedral_angle(local)));
          }
        double      smallest = std::numeric_limits<double>::infinity();
        const auto &membrane = model.membrane->elements();
        for (std::size_t k = 0; k < membrane.n_elements(); ++k)
          {
            const auto           &v = membrane.triangles[k];
            const Eigen::Vector3d a = y.segment<3>(3 * v[0]), b = y.segment<3>(3 * v[1]),
                                  c = y.segment<3>(3 * v[2]);
            smallest = std::min(smallest, 0.5 * (b - a).cross(c - a).norm() / membrane.area[k]);
          }
        std::ostringstream info;
        e.print_info(info);
        char where[200];
        std::snprintf(where, sizeof where,
                      " At the last accepted state the sharpest fold is %.1f degrees and the most "
                      "compressed triangle keeps %.3f of its rest area.",
                      sharpest * 180 / M_PI, smallest);
        AssertThrow(false, dealii::ExcMessage("Cloth: the implicit step from t = " + std::to_string(t) +
                                              " s did not converge. " + info.str() + where));
      }
    stats.newton_iterations += r.iterations;
    stats.newton_seconds += since(started);
    AssertThrow(y.allFinite(), dealii::ExcMessage("Cloth: the implicit step produced non-finite positions."));
    return y;
  }

  Eigen::VectorXd ClothSimulation::implicit_euler(const Eigen::VectorXd &x0, const Eigen::VectorXd &v0,
                                                  const double dt, ClothStepStatistics &stats) const
  {
    return minimise(x0 + dt * v0, dt, x0 + dt * v0, stats);
  }

  ProjectionResult ClothSimulation::project(const Eigen::VectorXd &x_hat, Eigen::VectorXd &x_out)
  {
    AssertThrow(projector, dealii::ExcMessage("Cloth: no strain limits to project on."));
    return projector->project(x_hat, x_out);
  }

  Eigen::VectorXd ClothSimulation::projected(const Eigen::VectorXd &x_hat, ClothStepStatistics &stats)
  {
    Eigen::VectorXd        out = x_hat;
    const ProjectionResult r   = projector->project(x_hat, out);
    stats.projection_seconds += r.seconds;
    stats.projection_iterations += r.iterations;
    ++stats.projections;
    stats.projection_status = r.status;
    stats.cuts += r.cuts_added;
    AssertThrow(
        r.status != ConicStatus::primal_infeasible,
        dealii::ExcMessage("Strain limiting: the limits cannot be met together with the pinned vertices "
                           "(the projection is primal infeasible: the pins are farther apart than "
                           "the limits allow)."));
    AssertThrow(r.status == ConicStatus::solved || r.status == ConicStatus::almost_solved,
                dealii::ExcMessage("Strain limiting: the projection failed (" + to_string(r.status) +
                                   " after " + std::to_string(r.iterations) + " iterations)."));
    return out;
  }

  ClothStepStatistics ClothSimulation::step()
  {
    ClothStepStatistics   stats;
    const double          h  = settings.time_step;
    const Eigen::VectorXd x0 = x, v0 = v;
    auto bdf2_target = [&](const Eigen::VectorXd &xn, const Eigen::VectorXd &vn, const Eigen::VectorXd &xp,
                           const Eigen::VectorXd &vp, double dt) {
      return Eigen::VectorXd((4 * xn - xp) / 3 + 2 * dt / 9 * (4 * vn - vp));
    };
    switch (settings.scheme)
      {
        case ClothScheme::ie:
        case ClothScheme::sap:
          {
            Eigen::VectorXd y = implicit_euler(x0, v0, h, stats);
            if (settings.scheme == ClothScheme::sap)
              y = projected(y, stats);
            x = y, v = (y - x0) / h;
            break;
          }
        case ClothScheme::bdf2:
        case ClothScheme::bap:
          {
            Eigen::VectorXd y;
            if (!has_history)
              y = implicit_euler(x0, v0, h, stats);
            else
              {
                const Eigen::VectorXd target = bdf2_target(x0, v0, x_previous, v_previous, h);
                y                            = minimise(target, 2 * h / 3, x0 + h * v0, stats);
              }
            if (settings.scheme == ClothScheme::bap)
              y = projected(y, stats);
            x = y;
            v = has_history ? Eigen::VectorXd((3 * y - 4 * x0 + x_previous) / (2 * h))
                            : Eigen::VectorXd((y - x0) / h);
            break;
          }
        case ClothScheme::sar:
        case ClothScheme::bar:
          {
            // Algorithm 1: half step, project, reflect, half step, project.
            const Eigen::VectorXd xh_hat = implicit_euler(x0, v0, h / 2, stats);
            const Eigen::VectorXd xh     = projected(xh_hat, stats);
            const Eigen::VectorXd vh     = (xh - x0) / (h / 2);
            const Eigen::VectorXd xr     = 2 * xh - xh_hat;
            Eigen::VectorXd       x1;
            if (settings.scheme == ClothScheme::sar)
              x1 = implicit_euler(xr, vh, h / 2, stats);
            else // BDF2 over the two half steps (x0, v0) -> (xr, vh)
              x1 = minimise(bdf2_target(xr, vh, x0, v0, h / 2), h / 3, xr + h / 2 * vh, stats);
            x1 = projected(x1, stats);
            x = x1, v = (x1 - xr) / (h / 2);
            break;
          }
      }
    AssertThrow(x.allFinite() && v.allFinite(),
                dealii::ExcMessage("Cloth: the state became non-finite (time step too large?)."));
    x_previous = x0, v_previous = v0, has_history = true;
    t += h;
    const StrainLimits &held = current_limits();
    stats.violation          = held.size() > 0 ? max_violation(held, x) : 0.0;
    if (held.size() > 0 && held.curve)
      stats.curve_excess = max_curve_excess(held, x);
    return stats;
  }

  ClothEnergy ClothSimulation::energy() const
  {
    ClothEnergy e;
    e.kinetic = 0.5 * v.cwiseAbs2().dot(model.model.lumped_mass());
    e.gravity = -force.dot(x);
    for (const auto &term : model.model.terms())
      (term->name() == "contact" ? e.contact : e.elastic) += term->value(x);
    return e;
  }
} // namespace nlmech
