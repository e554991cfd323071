#pragma once
// A primal-dual interior-point solver for convex quadratic programs over products of second-order
// cones (the strain-limiting projection of the SOCP paper, eqs. 5 and 12):
//
//   minimise 1/2 x^T P x + q^T x   subject to   s = h - G x,  s in K = Q^{d_1} x ... x Q^{d_m},
//
// with Q^d = {(t, y) in R x R^{d-1} : |y| <= t} and P diagonal, positive semi-definite. The method
// follows Vandenberghe's description of CVXOPT's cone QP solver: Nesterov-Todd scaling W_i per cone
// (W z = W^-1 s = lambda), Mehrotra predictor-corrector steps, the Newton systems reduced to the
// normal equations (P + G^T W^-2 G) dx = r, factorised by CHOLMOD (supernodal) with the symbolic
// analysis kept while the pattern of G does not change (across iterations and calls), one step of
// iterative refinement, and the exact (closed-form) step to the boundary of every cone.
//
// Status: solved (residuals and gap below the tolerances), almost_solved (below the looser
// tolerances when progress stalls or the iteration limit is hit), primal_infeasible (a certificate
// z in K with G^T z ~ 0 and h^T z < 0), iteration_limit (settings.max_iterations reached),
// stalled (the step length collapsed first), numerical_error (a non-finite iterate or a failed
// factorisation), dual_infeasible (the objective is unbounded below: x with P x = 0, -G x in K and
// q^T x < 0; found by the embedding only).
//
// Near-infeasible problems (within about 1e-5 of infeasibility) make the direct method stall: its
// iterates must approach both a solution and a certificate at once. There the solver goes on with
// the homogeneous self-dual embedding of the problem (as ECOS and Clarabel solve every problem):
// the unknowns (x, s, z, tau, kappa) with
//   P x + G^T z + q tau = 0,   s + G x - h tau = 0,   kappa + q^T x + h^T z + x^T P x / tau = 0,
// s, z in K, tau, kappa >= 0, s o z = 0 and tau kappa = 0, which has a strictly feasible central
// path whether or not the problem has a solution: x / tau solves it if tau stays positive, z (or
// x) is a certificate of infeasibility if tau goes to 0 with kappa > 0. Its Newton system is the
// same normal matrix with one more right-hand side (the direction of a unit change of tau), so a
// step costs one factorisation and three solves instead of two.

#include <Eigen/CholmodSupport>
#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <string>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace nlmech
{
  struct ConicQP
  {
    Eigen::VectorXd             P_diagonal; // n, >= 0
    Eigen::VectorXd             q;          // n
    Eigen::SparseMatrix<double> G;          // sum(d_i) x n
    Eigen::VectorXd             h;          // sum(d_i)
    std::vector<unsigned int>   cones;      // d_i >= 2 each, in the row order of G
  };

  enum class ConicStatus
  {
    solved,
    almost_solved,
    primal_infeasible,
    iteration_limit,
    numerical_error,
    /// The step to the cone boundary fell below 1e-10 before any tolerance was met: the iterates
    /// cannot move on (typical of problems within about 1e-5 of infeasibility).
    stalled,
    dual_infeasible
  };
  std::string to_string(ConicStatus status);

  /// The Cholesky factorisation of the normal equations (CHOLMOD, LL^T either way).
  enum class ConicFactorization
  {
    automatic,  // CHOLMOD's rule: supernodal from 40 flops per nonzero of L, simplicial below
    supernodal, // dense kernels on supernodes: large problems
    simplicial  // column by column: small problems, where supernodes are a few columns wide
  };

  /// How the iterates are set up: the direct method (CVXOPT's infeasible-start path), the
  /// homogeneous self-dual embedding, or the direct one followed by the embedding when it stalls or
  /// ends at its iteration limit or a numerical error (the default: the direct method is faster
  /// where it works, about 2/3 of the solves per iteration, and warm-starts).
  enum class ConicMethod
  {
    automatic,
    direct,
    embedded
  };

  struct ConicSettings
  {
    double       feasibility_tolerance   = 1e-9; // relative primal and dual residuals
    double       gap_tolerance           = 1e-9; // relative duality gap
    double       almost_factor           = 1e3;  // almost_solved: tolerances times this
    double       infeasibility_tolerance = 1e-8;
    unsigned int max_iterations          = 100;
    double       step_fraction           = 0.99;
    /// With a starting point x: start_mu > 0 starts from s = h - G x, lifted into every cone to
    /// t - |y| >= start_margin max(|t|, |y|), and the exactly centred z = start_mu s^-1 (s o z =
    /// start_mu e), instead of CVXOPT's start (which also needs a factorisation). Suits problems
    /// whose solution is near a known point, such as projections of nearly feasible candidates.
    double start_mu     = 0;
    double start_margin = 0.1;
    /// With a starting z as well (a warm start from the solution of a nearby problem, such as the
    /// last time step's projection): z is that point lifted into every cone to
    /// z_0 - |z_1| >= warm_margin max_i |z_i0|, plus warm_mu s^-1, and s is lifted by
    /// warm_s_margin instead of start_margin. Chosen on twelve steps of the swinging sheet (60x60,
    /// 1 % limits: 14.8 iterations a step against 19.5 from the centred start; 10 %: 31 against
    /// 40 summed over the screening rounds); warm_mu from 1e-7 to 1e-5 and warm_margin from 1e-4 to
    /// 1e-2 were within 1.5 iterations of it, a smaller warm_s_margin cost more.
    double warm_mu       = 1e-5;
    double warm_margin   = 1e-4;
    double warm_s_margin = 0.1;
    /// At 10x10 cloth projections (n 357, 22 flops per entry of L) a supernodal factorisation took
    /// 0.6 ms, a simplicial one 0.1 ms; from 40x40 on the supernodal one is chosen and faster.
    ConicFactorization factorization = ConicFactorization::automatic;
    ConicMethod        method        = ConicMethod::automatic;

    /// "Projection tolerance" (residuals and gap) and "Projection iterations" in the current
    /// subsection.
    static void declare_parameters(dealii::ParameterHandler &prm);
    void        parse_parameters(const dealii::ParameterHandler &prm);
  };

  struct ConicResult
  {
    ConicStatus     status = ConicStatus::numerical_error;
    Eigen::VectorXd x, s, z;
    unsigned int    iterations      = 0;
    double          primal_residual = 0, dual_residual = 0, gap = 0; // relative
    double          objective = 0;                                   // 1/2 x^T P x + q^T x
    double          seconds = 0, factorization_seconds = 0;
    /// Whether the answer came from the embedding (the iterations count both methods' steps).
    bool embedded = false;
  };

  class ConicQPSolver
  {
  public:
    ConicQPSolver();
    /// Solves from the standard starting point (CVXOPT's: the least-squares point shifted into
    /// the cones); `x_start` (optional) replaces x there, or gives the centred start (start_mu >
    /// 0), warm with `z_start` (the multipliers of a nearby problem's solution, one per row).
    ConicResult solve(const ConicQP &problem, const ConicSettings &settings = {},
                      const Eigen::VectorXd *x_start = nullptr, const Eigen::VectorXd *z_start = nullptr);

    unsigned int n_symbolic_analyses = 0, n_factorizations = 0;
    /// Whether the current symbolic analysis is simplicial (else supernodal).
    bool simplicial() const { return analysed_simplicial; }

  private:
    /// One interior-point run, direct or embedded (the embedding ignores the starting points).
    ConicResult solve_once(const ConicQP &problem, const ConicSettings &settings,
                           const Eigen::VectorXd *x_start, const Eigen::VectorXd *z_start, bool embedded);
    void        analyse(const ConicQP &problem, ConicFactorization factorization);
    /// Normal matrix P + sum_i G_i^T W_i^-2 G_i into `normal` (fixed pattern), with
    /// W_i^-2 = (2 J w w^T J - J) / eta^2 from the scaling (w, eta) of every cone; identity scalings
    /// (the starting point) when `w` is empty.
    void assemble(const ConicQP &problem, const Eigen::VectorXd &w, const std::vector<double> &eta);

    Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Upper> cholesky;
    Eigen::SparseMatrix<double>                                            normal;
    // Consecutive cones on the same columns of G form a group (cones group_begin[g] to
    // group_begin[g + 1]); per group its columns and where the entries of its block of the normal
    // matrix go in normal.valuePtr() (upper triangle); per cone G_i densely on its group's columns.
    std::vector<std::size_t>       group_begin, cone_group;
    std::vector<std::vector<int>>  group_columns;
    std::vector<std::vector<long>> group_slots;
    std::vector<double>            group_values; // the groups' blocks, from group_value_start[g]
    std::vector<std::size_t>       group_value_start;
    std::vector<double>            cone_G;
    std::vector<std::size_t>       cone_G_start;
    std::vector<char>              cone_sparse;       // per cone: every column of G_i has <= 1 entry
    std::vector<int>               cone_column_row;   // then its row and entry per column (0 and 0
    std::vector<double>            cone_column_value; // for an empty column)
    std::vector<std::size_t>       cone_column_start;
    std::vector<Eigen::Index>      offset; // first row of every cone
    std::vector<long>              diagonal_slot;
    long                           pattern_rows = -1, pattern_cols = -1, pattern_nonzeros = -1;
    ConicFactorization             analysed_factorization = ConicFactorization::automatic;
    bool                           analysed_simplicial    = false;
    std::vector<int>               pattern_inner, pattern_outer;
  };
} // namespace nlmech
