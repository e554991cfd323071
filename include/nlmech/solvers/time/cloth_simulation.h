#pragma once
// Implicit time stepping of a cloth sheet (CST St.Venant-Kirchhoff membrane + hinge bending, the
// thin-shell model of models/dynamics/thin_shell.h) with gravity, pinned vertices, penalty
// collisions with a sphere and a ground plane, and strain limiting by projection (the SOCP paper,
// section 4; thesis ch. 3):
//
// - IE:  implicit Euler, x = argmin 1/(2 h^2) |x - x_n - h v_n|_M^2 + W(x) - f.x (Newton, CHOLMOD);
// - SAP: IE, then the projection; v = (x - x_n) / h;
// - SAR: the step-and-reflect of Algorithm 1 (half step, projection, reflection, half step,
//        projection);
// - BDF2: x = argmin 1/(2 (2h/3)^2) |x - x_hat|_M^2 + W - f.x with
//        x_hat = (4 x_n - x_{n-1}) / 3 + 2h/9 (4 v_n - v_{n-1}); first step IE;
// - BAP: BDF2, then the projection (English and Bridson 2008); BAR: SAR with a BDF2 second half
//        (history (x_n, v_n) and the reflected mid-step) and Algorithm 1's end velocity
//        (x - x_r) / (h/2). The BDF2 end velocity (3 x - 4 x_r + x_n) / h made the swinging sheet
//        (20x20, 1 %, 3 s) gain 0.053 J instead of losing 0.050 J (the thesis reports the same
//        kind of instability for a BDF2 mid-step velocity).
// Total energy = kinetic + elastic + gravity potential + penalty energy, recorded by the caller.

#include <nlmech/models/dynamics/thin_shell.h>
#include <nlmech/solvers/socp/strain_projection.h>

#include <limits>
#include <memory>
#include <string>

namespace dealii
{
  class ParameterHandler;
}

namespace nlmech
{
  enum class ClothScheme
  {
    ie,
    sap,
    sar,
    bdf2,
    bap,
    bar
  };
  ClothScheme parse_cloth_scheme(const std::string &name);
  std::string to_string(ClothScheme scheme);
  bool        uses_projection(ClothScheme scheme);

  struct ClothSettings
  {
    double                time_step = 1.0 / 60; // [s]
    ClothScheme           scheme    = ClothScheme::sar;
    std::array<double, 3> gravity   = {{0, -9.81, 0}};
    // Penalty collisions (stiffness 0: none): E = k/2 depth^2.
    bool                  sphere        = false;
    std::array<double, 3> sphere_center = {{0, 0, 0}};
    double                sphere_radius = 0.1, sphere_stiffness = 0;
    bool                  ground        = false;
    double                ground_height = -1, ground_stiffness = 0;
    double                newton_tolerance = 1e-8; // relative gradient
    /// Also converged when a full Newton step moves no vertex faster than this [m/s] (|dx|_inf / h,
    /// IPC's criterion): wrinkling fine sheets approach their minimum along nearly flat directions
    /// where the gradient falls slowly. 0: gradient only.
    double newton_velocity_tolerance = 1e-4;
    /// Triangles crushed below this fraction of their rest area meet a log barrier (0: none); see
    /// AreaBarrierElements in cloth_simulation.cc. Inactive in ordinary states.
    double area_barrier = 0.1;
    /// Implicit steps' Newton on element Hessians projected to positive semi-definite (true), or on
    /// the exact Hessian with a global diagonal shift where it is indefinite (false).
    bool project_element_hessians = true;

    /// The implicit steps' entries in subsection "Time stepping" ("Time step", "Newton tolerance",
    /// "Newton velocity tolerance", "Area barrier", "Newton Hessian") and the penalty obstacles
    /// in "Collisions"; entered here from the top level.
    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(dealii::ParameterHandler &prm);
  };

  struct ClothStepStatistics
  {
    double       newton_seconds = 0, projection_seconds = 0;
    unsigned int newton_iterations = 0, projections = 0, projection_iterations = 0;
    double       violation = 0; // after the step (relative, <= 0 when every limit holds)
    /// After the step: the largest excess over the limit curve between the sampled directions,
    /// relative to the requested strain (<= the curve tolerance when it holds; NaN without limits).
    double      curve_excess      = std::numeric_limits<double>::quiet_NaN();
    std::size_t cuts              = 0; // cutting planes the step's projections added
    ConicStatus projection_status = ConicStatus::solved;
  };

  struct ClothEnergy
  {
    double kinetic = 0, elastic = 0, gravity = 0, contact = 0;
    double total() const { return kinetic + elastic + gravity + contact; }
  };

  class ClothSimulation
  {
  public:
    /// The limits as projected on: the sampled rows and the cuts added so far.
    const StrainLimits &current_limits() const { return projector ? projector->current_limits() : limits; }
    /// `limits` may be empty (no projection); the schemes with projection need it non-empty.
    /// `pinned` vertices stay at their rest positions moved by `pin_offsets` (one per pinned vertex,
    /// or none): grips that stretch the sheet from the start.
    ClothSimulation(const RawSimplexMesh<3> &mesh, const ShellMaterial &material,
                    const std::vector<unsigned int> &pinned, const StrainLimits &limits,
                    const ClothSettings &settings, ConicSettings cone_settings = {},
                    const std::vector<std::array<double, 3>> &pin_offsets = {});
    ~ClothSimulation();

    /// One time step. Throws a clear error when Newton diverges, the state becomes non-finite or a
    /// projection fails (infeasible limits, iteration limit).
    ClothStepStatistics step();
    ClothEnergy         energy() const;

    const Eigen::VectorXd &positions() const { return x; }
    const Eigen::VectorXd &velocities() const { return v; }
    /// Replaces the state (for benchmarks that split a step into its parts); clears the history.
    void set_state(const Eigen::VectorXd &positions, const Eigen::VectorXd &velocities)
    {
      x = positions, v = velocities, has_history = false;
    }
    const ShellModel &shell() const { return model; }
    double            time() const { return t; }
    /// The projection alone (for benchmarks): x = P(x_hat).
    ProjectionResult project(const Eigen::VectorXd &x_hat, Eigen::VectorXd &x_out);
    /// An implicit Euler step's candidate from (x0, v0) over dt, without changing the state.
    Eigen::VectorXd implicit_euler(const Eigen::VectorXd &x0, const Eigen::VectorXd &v0, double dt,
                                   ClothStepStatistics &stats) const;
    const std::map<std::size_t, double> &fixed() const { return model.model.fixed(); }
    const Eigen::VectorXd               &mass() const { return model.model.lumped_mass(); }

  private:
    Eigen::VectorXd minimise(const Eigen::VectorXd &x_hat, double dt_effective, const Eigen::VectorXd &start,
                             ClothStepStatistics &stats) const;
    Eigen::VectorXd projected(const Eigen::VectorXd &x_hat, ClothStepStatistics &stats);

    ShellModel                            model;
    const StrainLimits                   &limits;
    ClothSettings                         settings;
    std::unique_ptr<StrainLimitProjector> projector;
    Eigen::VectorXd                       x, v, x_previous, v_previous, force;
    bool                                  has_history = false;
    double                                t           = 0;
  };
} // namespace nlmech
