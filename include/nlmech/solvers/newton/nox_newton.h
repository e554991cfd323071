#pragma once
// Newton's method with a line search from Trilinos NOX (Epetra back end) for r(q) = lambda g on the
// free unknowns of any EquilibriumSystem, with load stepping. The linear solves go through NOX's
// Amesos linear system (KLU serially, MUMPS on several ranks) on an Epetra matrix whose rows are
// distributed over the communicator's ranks; the residual and tangent are evaluated by the system
// (every rank evaluates the system and keeps its own rows), so `mpirun -np 2` gives the serial
// answer to round-off. NLMECH_NOX_VERBOSE=1 in the environment prints NOX's iterations and line
// searches.

#include <nlmech/models/equilibrium_system.h>

#include <mpi.h>

#include <functional>
#include <string>

namespace nlmech
{
  struct NoxNewtonSettings
  {
    unsigned int load_steps         = 10;
    double       relative_tolerance = 1e-9; // |r - lambda g| <= tol |g| on the free unknowns
    unsigned int max_iterations     = 50;   // per load step
    /// NOX line search when no energy is given (merit 0.5 |R|^2): "Backtrack", "Polynomial",
    /// "More'-Thuente" or "Full Step". With an energy, NOX's "Polynomial" (cubic, Armijo) line search
    /// runs on the energy E(q) - lambda g.q as a user-defined merit function instead: the residual
    /// norm is a poor merit for large deformations (steps are cut to 1/256 and Newton stalls).
    std::string line_search = "Backtrack";
    /// Amesos solver ("Amesos_Klu", "Amesos_Mumps", "Amesos_Lapack"); empty: KLU on one rank,
    /// MUMPS on several.
    std::string direct_solver;
  };

  struct NoxNewtonResult
  {
    unsigned int iterations     = 0; // nonlinear iterations over all load steps
    unsigned int factorizations = 0; // Jacobian evaluations (each is factorised once)
    unsigned int residuals      = 0; // residual evaluations (line-search trials included)
    double       seconds        = 0;
    std::string  direct_solver; // the Amesos solver used
  };

  /// Potential energy of the internal forces at a full-length state (r = dE/dq); +inf where the
  /// state is not admissible.
  using EnergyFunction = std::function<double(const Eigen::VectorXd &)>;

  /// Solves for q (fixed unknowns are set first). Throws a clear error, naming the load factor,
  /// when a load step does not converge. `energy` (optional) makes the line search minimise energy.
  NoxNewtonResult solve_equilibrium_with_nox(const EquilibriumSystem &system, const Eigen::VectorXd &load,
                                             Eigen::VectorXd &q, const NoxNewtonSettings &settings = {},
                                             MPI_Comm              comm   = MPI_COMM_WORLD,
                                             const EnergyFunction &energy = {});
} // namespace nlmech
