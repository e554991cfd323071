#include <deal.II/base/exceptions.h>
#include <deal.II/base/parallel.h>
#include <deal.II/base/parameter_handler.h>

#include <nlmech/base/threads.h>
#include <nlmech/solvers/socp/conic_qp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <type_traits>

namespace nlmech
{
  void ConicSettings::declare_parameters(dealii::ParameterHandler &prm)
  {
    prm.declare_entry("Projection tolerance", "1e-9", dealii::Patterns::Double(0),
                      "Residuals and gap of the interior-point projection (relative) [-].");
    prm.declare_entry("Projection iterations", "100", dealii::Patterns::Integer(1),
                      "Interior-point iterations per cone problem before the projection (and its "
                      "scheme) is given up [-].");
  }

  void ConicSettings::parse_parameters(const dealii::ParameterHandler &prm)
  {
    feasibility_tolerance = gap_tolerance = prm.get_double("Projection tolerance");
    max_iterations                        = unsigned(prm.get_integer("Projection iterations"));
  }

  namespace
  {
    using Clock = std::chrono::steady_clock;
    double since(Clock::time_point t0)
    {
      return std::chrono::duration<double>(Clock::now() - t0).count();
    }

    /// f(begin, end) over [0, m) in chunks on deal.II's threads (serial for small m).
    template <typename F>
    void for_chunks(const std::size_t m, const F &f)
    {
      if (m < 4096)
        f(std::size_t(0), m);
      else
        dealii::parallel::apply_to_subranges(std::size_t(0), m, f, 2048);
    }

    // The cone kernels take the dimension d as an Eigen::Index or, where every cone has the same
    // small dimension (4 in the strain-limiting problems), as a compile-time constant
    // (std::integral_constant), so that their loops unroll.
    using Four = std::integral_constant<Eigen::Index, 4>;

    /// u^T J u with J = diag(1, -1, ..., -1).
    template <typename Dim>
    inline double jnorm2(const double *u, const Dim d)
    {
      double y = 0;
      for (Eigen::Index k = 1; k < d; ++k)
        y += u[k] * u[k];
      return u[0] * u[0] - y;
    }
    double jnorm2(const Eigen::Ref<const Eigen::VectorXd> &u)
    {
      return jnorm2(u.data(), u.size());
    }
    /// Solves lambda o d = r for d (lambda in the interior), into d.
    template <typename Dim>
    inline void jordan_solve(const double *l, const double *r, const Dim size, double *d)
    {
      double lr = 0, ll = 0;
      for (Eigen::Index k = 1; k < size; ++k)
        lr += l[k] * r[k], ll += l[k] * l[k];
      d[0]               = (l[0] * r[0] - lr) / (l[0] * l[0] - ll);
      const double inv_l = 1 / l[0];
      for (Eigen::Index k = 1; k < size; ++k)
        d[k] = (r[k] - d[0] * l[k]) * inv_l;
    }
    /// Largest alpha >= 0 with u + alpha du in the cone (u inside); infinity if unbounded.
    template <typename Dim>
    inline double step_to_boundary(const double *u, const double *du, const Dim d)
    {
      double aa = 0, bb = 0, cc = 0;
      for (Eigen::Index k = 1; k < d; ++k)
        aa += du[k] * du[k], bb += u[k] * du[k], cc += u[k] * u[k];
      const double a = du[0] * du[0] - aa, b = u[0] * du[0] - bb, c = u[0] * u[0] - cc;
      const double disc = b * b - a * c;
      if ((a >= 0 && b >= 0) || (a > 0 && disc < 0))
        return std::numeric_limits<double>::infinity();
      // The smaller positive root of a t^2 + 2 b t + c, in the cancellation-free form.
      return c / (-b + std::sqrt(std::max(disc, 0.0)));
    }
    /// Whether a run ended without an answer (no solution, no certificate).
    bool failed(const ConicStatus status)
    {
      return status == ConicStatus::iteration_limit || status == ConicStatus::numerical_error ||
             status == ConicStatus::stalled;
    }

    /// Smallest eigenvalue u_0 - |u_1| of u in the cone's Jordan algebra.
    double min_eigenvalue(const Eigen::Ref<const Eigen::VectorXd> &u)
    {
      return u[0] - u.tail(u.size() - 1).norm();
    }

    /// Applies the Nesterov-Todd scaling of one cone, W = eta Wb with the hyperbolic Householder
    /// matrix Wb = [[w_0, w_1^T], [w_1, I + w_1 w_1^T / (1 + w_0)]] (w^T J w = 1), or its inverse
    /// W^-1 = J Wb J / eta, to u (length d) into out (may be u itself). No temporaries.
    template <typename Dim>
    [[gnu::always_inline]] inline void apply_scaling(const double *w, const double eta, const Dim d,
                                                     const double *u, double *out, const bool inverse)
    {
      double dot = 0;
      for (Eigen::Index k = 1; k < d; ++k)
        dot += w[k] * u[k];
      const double u0 = u[0];
      if (!inverse)
        {
          const double c = u0 + dot / (1 + w[0]);
          out[0]         = eta * (w[0] * u0 + dot);
          for (Eigen::Index k = 1; k < d; ++k)
            out[k] = eta * (u[k] + c * w[k]);
        }
      else
        {
          const double c = -u0 + dot / (1 + w[0]), e = 1 / eta;
          out[0] = (w[0] * u0 - dot) * e;
          for (Eigen::Index k = 1; k < d; ++k)
            out[k] = (u[k] + c * w[k]) * e;
        }
    }
  } // namespace

  std::string to_string(const ConicStatus status)
  {
    switch (status)
      {
        case ConicStatus::solved: return "solved";
        case ConicStatus::almost_solved: return "almost solved";
        case ConicStatus::primal_infeasible: return "primal infeasible";
        case ConicStatus::iteration_limit: return "iteration limit";
        case ConicStatus::stalled: return "stalled";
        case ConicStatus::dual_infeasible: return "dual infeasible";
        default: return "numerical error";
      }
  }

  ConicQPSolver::ConicQPSolver()
  {
    serialise_openmp();
    cholesky.setMode(Eigen::CholmodSupernodalLLt);
    cholesky.cholmod().print = 0;
    if (const char *o = std::getenv("NLMECH_SOCP_ORDERING"))
      {
        cholesky.cholmod().nmethods           = 1;
        cholesky.cholmod().method[0].ordering = std::atoi(o);
      }
  }

  void ConicQPSolver::analyse(const ConicQP &problem, const ConicFactorization factorization)
  {
    const Eigen::Index                                 n = problem.G.cols();
    const Eigen::SparseMatrix<double, Eigen::RowMajor> Gr(problem.G);
    // Columns of every cone; consecutive cones on the same columns form a group (the limits of
    // one triangle), whose contributions are summed densely before they go into the matrix.
    group_begin.assign(1, 0);
    group_columns.clear();
    cone_group.assign(problem.cones.size(), 0);
    std::vector<int> cols;
    Eigen::Index     row = 0;
    for (std::size_t i = 0; i < problem.cones.size(); ++i)
      {
        cols.clear();
        for (unsigned int r = 0; r < problem.cones[i]; ++r, ++row)
          for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(Gr, row); it; ++it)
            cols.push_back(int(it.col()));
        std::sort(cols.begin(), cols.end());
        cols.erase(std::unique(cols.begin(), cols.end()), cols.end());
        if (group_columns.empty() || cols != group_columns.back())
          {
            if (!group_columns.empty())
              group_begin.push_back(i);
            group_columns.push_back(cols);
          }
        cone_group[i] = group_columns.size() - 1;
      }
    group_begin.push_back(problem.cones.size());
    std::vector<Eigen::Triplet<double>> t;
    for (const auto &gc : group_columns)
      for (std::size_t a = 0; a < gc.size(); ++a)
        for (std::size_t b = 0; b <= a; ++b)
          t.emplace_back(gc[b], gc[a], 0.0); // upper triangle: CHOLMOD's cheapest input
    for (Eigen::Index j = 0; j < n; ++j)
      t.emplace_back(j, j, 0.0);
    normal.resize(n, n);
    normal.setFromTriplets(t.begin(), t.end());
    normal.makeCompressed();
    auto slot = [&](int r, int c) {
      const int *begin = normal.innerIndexPtr() + normal.outerIndexPtr()[c];
      const int *end   = normal.innerIndexPtr() + normal.outerIndexPtr()[c + 1];
      return long(std::lower_bound(begin, end, r) - normal.innerIndexPtr());
    };
    group_slots.assign(group_columns.size(), {});
    for (std::size_t g = 0; g < group_columns.size(); ++g)
      {
        const auto &gc = group_columns[g];
        for (std::size_t a = 0; a < gc.size(); ++a)
          for (std::size_t b = 0; b <= a; ++b)
            group_slots[g].push_back(slot(gc[b], gc[a]));
      }
    group_value_start.assign(group_columns.size() + 1, 0);
    for (std::size_t g = 0; g < group_columns.size(); ++g)
      group_value_start[g + 1] = group_value_start[g] + group_slots[g].size();
    group_values.resize(group_value_start.back());
    diagonal_slot.resize(std::size_t(n));
    for (Eigen::Index j = 0; j < n; ++j)
      diagonal_slot[std::size_t(j)] = slot(int(j), int(j));
    // Supernodal or simplicial LL^T by CHOLMOD's own rule (CHOLMOD_AUTO: supernodal where the
    // factorisation costs at least 40 flops per nonzero of L), kept as LL^T so that a matrix that is
    // not positive definite is reported. Small problems gain most: at 10x10 (n 357, nnz(L) 6420,
    // 22 flops per entry) a supernodal factorisation took 0.6 ms, a simplicial one 0.1 ms, because
    // the supernodal one pays per supernode for dense kernels on blocks of a few columns.
    // ConicSettings::factorization forces one (for comparisons).
    cholesky.setMode(Eigen::CholmodSupernodalLLt);
    cholesky.analyzePattern(normal);
    const bool simplicial  = factorization == ConicFactorization::automatic
                                 ? cholesky.cholmod().fl < 40 * cholesky.cholmod().lnz
                                 : factorization == ConicFactorization::simplicial;
    analysed_factorization = factorization, analysed_simplicial = simplicial;
    if (simplicial)
      {
        cholesky.setMode(Eigen::CholmodSimplicialLLt);
        cholesky.analyzePattern(normal);
      }
    if (std::getenv("NLMECH_SOCP_DEBUG"))
      std::fprintf(stderr, "socp analysis: n %ld, nnz(A) %ld, nnz(L) %.0f, %.3g flops, %s\n", long(n),
                   long(normal.nonZeros()), cholesky.cholmod().lnz, cholesky.cholmod().fl,
                   simplicial ? "simplicial" : "supernodal");
    ++n_symbolic_analyses;
    pattern_rows = problem.G.rows(), pattern_cols = n, pattern_nonzeros = problem.G.nonZeros();
    pattern_outer.assign(problem.G.outerIndexPtr(), problem.G.outerIndexPtr() + n + 1);
    pattern_inner.assign(problem.G.innerIndexPtr(), problem.G.innerIndexPtr() + problem.G.nonZeros());
  }

  void ConicQPSolver::assemble(const ConicQP &problem, const Eigen::VectorXd &w,
                               const std::vector<double> &eta)
  {
    std::fill(normal.valuePtr(), normal.valuePtr() + normal.nonZeros(), 0.0);
    const double regularisation = 1e-13 * std::max(1.0, problem.P_diagonal.lpNorm<Eigen::Infinity>());
    for (std::size_t j = 0; j < diagonal_slot.size(); ++j)
      normal.valuePtr()[diagonal_slot[j]] += problem.P_diagonal[Eigen::Index(j)] + regularisation;
    // Per group (in parallel): sum over its cones of B^T B with B = W_i^-1 G_i (W_i symmetric,
    // so this is G_i^T W_i^-2 G_i), B = G_i for the identity scaling of the starting point; then
    // the blocks go into the matrix (serially: groups share entries). With W^-1 = J Wb J / eta,
    // B in closed form from v = w_1^T G_1 (G_i = [g_0; G_1] by rows):
    //   B_0 = (w_0 g_0 - v) / eta,   B_1 = (G_1 + w_1 (v / (1 + w_0) - g_0)^T) / eta.
    const std::size_t  n_groups = group_columns.size();
    const unsigned int max_d =
        problem.cones.empty() ? 0u : *std::max_element(problem.cones.begin(), problem.cones.end());
    for_chunks(n_groups, [&](const std::size_t begin, const std::size_t end) {
      std::vector<double> B;
      for (std::size_t g = begin; g < end; ++g)
        {
          const std::size_t c     = group_columns[g].size();
          double           *local = group_values.data() + group_value_start[g];
          std::fill(local, local + c * (c + 1) / 2, 0.0);
          B.resize(std::max(B.size(), std::size_t(max_d) * c));
          for (std::size_t i = group_begin[g]; i < group_begin[g + 1]; ++i)
            {
              const Eigen::Index d  = problem.cones[i];
              const double      *Gi = cone_G.data() + cone_G_start[i]; // d x c, column-major
              if (w.size() > 0 && cone_sparse[i] && d <= 8)
                {
                  // G_i^T W^-2 G_i entry by entry: (p, q) = g_p g_q (W^-2)_{r_p r_q}, with
                  // W^-2 = (2 J w (J w)^T - J) / eta^2 (g = 0 for an empty column).
                  const double *wi = w.data() + offset[i];
                  const double  e2 = 1 / (eta[i] * eta[i]);
                  double        jw[8], W2[64];
                  for (Eigen::Index a = 0; a < d; ++a)
                    jw[a] = a == 0 ? wi[0] : -wi[a];
                  for (Eigen::Index a = 0; a < d; ++a)
                    for (Eigen::Index b = 0; b <= a; ++b)
                      W2[a * d + b] = W2[b * d + a] = e2 * (2 * jw[a] * jw[b] - (a != b   ? 0.0
                                                                                 : a == 0 ? 1.0
                                                                                          : -1.0));
                  const int    *rp = cone_column_row.data() + cone_column_start[i];
                  const double *gv = cone_column_value.data() + cone_column_start[i];
                  std::size_t   k  = 0;
                  for (std::size_t p = 0; p < c; ++p)
                    {
                      const double  gp  = gv[p];
                      const double *row = W2 + rp[p] * d;
                      for (std::size_t q = 0; q <= p; ++q, ++k)
                        local[k] += gp * gv[q] * row[rp[q]];
                    }
                  continue;
                }
              if (w.size() == 0)
                std::copy(Gi, Gi + d * Eigen::Index(c), B.begin());
              else
                {
                  const double *wi = w.data() + offset[i];
                  const double  e = 1 / eta[i], w0 = wi[0], h = 1 / (1 + w0);
                  for (std::size_t p = 0; p < c; ++p)
                    {
                      const double *gp = Gi + Eigen::Index(p) * d;
                      double       *bp = B.data() + p * std::size_t(d);
                      double        vp = 0;
                      for (Eigen::Index r = 1; r < d; ++r)
                        vp += wi[r] * gp[r];
                      bp[0]          = e * (w0 * gp[0] - vp);
                      const double a = vp * h - gp[0];
                      for (Eigen::Index r = 1; r < d; ++r)
                        bp[r] = e * (gp[r] + wi[r] * a);
                    }
                }
              std::size_t k = 0;
              for (std::size_t p = 0; p < c; ++p)
                {
                  const double *bp = B.data() + p * std::size_t(d);
                  for (std::size_t q = 0; q <= p; ++q, ++k)
                    {
                      const double *bq = B.data() + q * std::size_t(d);
                      double        s  = 0;
                      for (Eigen::Index r = 0; r < d; ++r)
                        s += bp[r] * bq[r];
                      local[k] += s;
                    }
                }
            }
        }
    });
    double *values = normal.valuePtr();
    for (std::size_t g = 0; g < n_groups; ++g)
      {
        const double *local = group_values.data() + group_value_start[g];
        const long   *slots = group_slots[g].data();
        for (std::size_t k = 0; k < group_slots[g].size(); ++k)
          values[slots[k]] += local[k];
      }
  }

  ConicResult ConicQPSolver::solve_once(const ConicQP &problem, const ConicSettings &settings,
                                        const Eigen::VectorXd *x_start, const Eigen::VectorXd *z_start,
                                        const bool embedded)
  {
    const auto         started = Clock::now();
    const Eigen::Index n = problem.G.cols(), rows = problem.G.rows();
    const std::size_t  m     = problem.cones.size();
    Eigen::Index       total = 0;
    for (const unsigned int d : problem.cones)
      {
        AssertThrow(d >= 2, dealii::ExcMessage("Conic QP: every second-order cone needs dimension >= 2."));
        total += d;
      }
    AssertThrow(total == rows && problem.h.size() == rows && problem.q.size() == n &&
                    problem.P_diagonal.size() == n && problem.G.isCompressed(),
                dealii::ExcMessage("Conic QP: inconsistent sizes of P, q, G, h and the cones."));
    AssertThrow(problem.P_diagonal.minCoeff() >= 0 && problem.P_diagonal.allFinite() &&
                    problem.q.allFinite() && problem.h.allFinite(),
                dealii::ExcMessage("Conic QP: P must be positive semi-definite and the data finite."));

    const bool same_pattern =
        rows == pattern_rows && n == pattern_cols && problem.G.nonZeros() == pattern_nonzeros &&
        std::equal(pattern_outer.begin(), pattern_outer.end(), problem.G.outerIndexPtr()) &&
        std::equal(pattern_inner.begin(), pattern_inner.end(), problem.G.innerIndexPtr());
    if (!same_pattern || settings.factorization != analysed_factorization)
      analyse(problem, settings.factorization);
    offset.assign(m + 1, 0);
    for (std::size_t i = 0; i < m; ++i)
      offset[i + 1] = offset[i] + problem.cones[i];
    // Dense per-cone blocks of G on the columns of the cone's group (column-major, one array).
    {
      const Eigen::SparseMatrix<double, Eigen::RowMajor> Gr(problem.G);
      cone_G_start.resize(m + 1);
      cone_G_start[0] = 0;
      for (std::size_t i = 0; i < m; ++i)
        cone_G_start[i + 1] = cone_G_start[i] + problem.cones[i] * group_columns[cone_group[i]].size();
      cone_G.assign(cone_G_start[m], 0.0);
      Eigen::Index row = 0;
      for (std::size_t i = 0; i < m; ++i)
        {
          const auto &cols = group_columns[cone_group[i]];
          const auto  d    = Eigen::Index(problem.cones[i]);
          double     *Gi   = cone_G.data() + cone_G_start[i];
          for (Eigen::Index r = 0; r < d; ++r, ++row)
            for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(Gr, row); it; ++it)
              Gi[(std::lower_bound(cols.begin(), cols.end(), int(it.col())) - cols.begin()) * d + r] =
                  it.value();
        }
      // Where every column of a cone's G_i has at most one nonzero (the strain limits: row 0 is
      // zero, each unknown enters one component), its row per column, for the sparse assembly.
      cone_sparse.assign(m, 1);
      cone_column_start.assign(m + 1, 0);
      for (std::size_t i = 0; i < m; ++i)
        cone_column_start[i + 1] = cone_column_start[i] + group_columns[cone_group[i]].size();
      cone_column_row.assign(cone_column_start[m], 0);
      cone_column_value.assign(cone_column_start[m], 0.0);
      for (std::size_t i = 0; i < m; ++i)
        {
          const auto    d  = Eigen::Index(problem.cones[i]);
          const auto    c  = group_columns[cone_group[i]].size();
          const double *Gi = cone_G.data() + cone_G_start[i];
          for (std::size_t p = 0; p < c; ++p)
            {
              int rows_with_entries = 0;
              for (Eigen::Index r = 0; r < d; ++r)
                if (Gi[Eigen::Index(p) * d + r] != 0)
                  {
                    ++rows_with_entries;
                    cone_column_row[cone_column_start[i] + p]   = int(r);
                    cone_column_value[cone_column_start[i] + p] = Gi[Eigen::Index(p) * d + r];
                  }
              if (rows_with_entries > 1)
                cone_sparse[i] = 0;
            }
        }
    }
    auto block  = [&](Eigen::VectorXd &v, std::size_t i) { return v.segment(offset[i], problem.cones[i]); };
    auto cblock = [&](const Eigen::VectorXd &v, std::size_t i) {
      return v.segment(offset[i], problem.cones[i]);
    };

    ConicResult result;
    auto        factorize = [&]() {
      const auto t0 = Clock::now();
      cholesky.factorize(normal);
      ++n_factorizations;
      result.factorization_seconds += since(t0);
      return cholesky.info() == Eigen::Success;
    };
    // Normal-equation solve with one step of iterative refinement where the residual is not
    // already at rounding level (late iterations, when W spans many orders of magnitude).
    double solve_seconds = 0, assemble_seconds = 0; // for NLMECH_SOCP_DEBUG
    auto   normal_solve = [&](const Eigen::VectorXd &rhs) {
      const auto            t0 = Clock::now();
      Eigen::VectorXd       x  = cholesky.solve(rhs);
      const Eigen::VectorXd r  = rhs - normal.selfadjointView<Eigen::Upper>() * x;
      if (r.norm() > 1e-12 * rhs.norm())
        x += cholesky.solve(r);
      solve_seconds += since(t0);
      return x;
    };

    // Starting point: (P + G^T G) x = -q + G^T h, s = h - G x, z = -s, shifted into the cones
    // (CVXOPT's); or the centred start near x_start (no factorisation needed). The embedding
    // starts from CVXOPT's point with tau = kappa = 1.
    Eigen::VectorXd     w(rows);   // NT scaling points w of every cone (w^T J w = 1)
    std::vector<double> eta(m, 1); // and their factors
    const bool          centred_start = !embedded && x_start && settings.start_mu > 0;
    if (!centred_start)
      {
        assemble(problem, Eigen::VectorXd(), eta);
        if (!factorize())
          {
            result.status  = ConicStatus::numerical_error;
            result.seconds = since(started);
            return result;
          }
      }
    Eigen::VectorXd x =
        x_start && !embedded ? *x_start : normal_solve(-problem.q + problem.G.transpose() * problem.h);
    Eigen::VectorXd s = problem.h - problem.G * x, z = -s;
    auto            shift = [&](Eigen::VectorXd &u) {
      double worst = -std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < m; ++i)
        worst = std::max(worst, -min_eigenvalue(cblock(u, i)));
      if (worst >= -1e-8)
        for (std::size_t i = 0; i < m; ++i)
          block(u, i)[0] += 1 + std::max(worst, 0.0);
    };
    if (centred_start)
      {
        // Centred start near a given point: s = h - G x lifted into every cone by at least a
        // margin, z = mu s^-1 (so that s o z = mu e exactly in every cone).
        const bool warm    = z_start && z_start->size() == rows && z_start->allFinite();
        double     z_floor = 0;
        if (warm)
          for (std::size_t i = 0; i < m; ++i)
            z_floor = std::max(z_floor, std::abs((*z_start)[offset[i]]));
        z_floor *= settings.warm_margin;
        const double s_margin = warm ? settings.warm_s_margin : settings.start_margin;
        for (std::size_t i = 0; i < m; ++i)
          {
            auto         si     = block(s, i);
            const double norm_y = si.tail(si.size() - 1).norm();
            const double margin = s_margin * std::max(std::abs(si[0]), norm_y);
            if (si[0] - norm_y < margin)
              si[0] = norm_y + std::max(margin, 1e-12);
            auto         zi        = block(z, i);
            const double j         = jnorm2(si);
            const double mu        = warm ? settings.warm_mu : settings.start_mu;
            zi[0]                  = mu * si[0] / j;
            zi.tail(zi.size() - 1) = -mu / j * si.tail(si.size() - 1);
            if (warm)
              {
                Eigen::VectorXd zw = z_start->segment(offset[i], problem.cones[i]);
                const double    ny = zw.tail(zw.size() - 1).norm();
                if (zw[0] - ny < z_floor)
                  zw[0] = ny + z_floor;
                zi += zw;
              }
          }
      }
    else
      shift(s), shift(z);
    // The embedding's scalars (tau = 1, kappa = 0 fixed without it): x / tau solves the problem
    // when tau stays away from 0; tau -> 0 with kappa > 0 leaves a certificate of infeasibility.
    double tau = 1, kappa = embedded ? 1 : 0;

    const double    h_scale = std::max(1.0, problem.h.norm()), q_scale = std::max(1.0, problem.q.norm());
    Eigen::VectorXd lambda(rows);
    ConicStatus     status = ConicStatus::iteration_limit;
    ConicResult     last;
    double          last_tau = 1;
    last.primal_residual = last.dual_residual = last.gap = std::numeric_limits<double>::infinity();
    // G v and G^T v in parallel (over the rows of a row-major copy, over the columns of G).
    const Eigen::SparseMatrix<double, Eigen::RowMajor> G_rows(problem.G);
    auto G_times = [&](const Eigen::VectorXd &v, Eigen::VectorXd &out) {
      out.resize(rows);
      for_chunks(std::size_t(rows), [&](const std::size_t begin, const std::size_t end) {
        for (std::size_t r = begin; r < end; ++r)
          {
            double sum = 0;
            for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(G_rows, Eigen::Index(r)); it;
                 ++it)
              sum += it.value() * v[it.index()];
            out[Eigen::Index(r)] = sum;
          }
      });
    };
    auto Gt_times = [&](const Eigen::VectorXd &v, Eigen::VectorXd &out) {
      out.resize(n);
      for_chunks(std::size_t(n), [&](const std::size_t begin, const std::size_t end) {
        for (std::size_t c = begin; c < end; ++c)
          {
            double sum = 0;
            for (Eigen::SparseMatrix<double>::InnerIterator it(problem.G, Eigen::Index(c)); it; ++it)
              sum += it.value() * v[it.index()];
            out[Eigen::Index(c)] = sum;
          }
      });
    };
    // Per-cone loops (in parallel), with the dimension fixed at compile time when all are 4.
    const bool all_four  = std::all_of(problem.cones.begin(), problem.cones.end(),
                                       [](const unsigned int d) { return d == Four::value; });
    auto       cone_loop = [&](const auto &body) {
      for_chunks(m, [&](const std::size_t begin, const std::size_t end) {
        if (all_four)
          for (std::size_t i = begin; i < end; ++i)
            body(i, Four());
        else
          for (std::size_t i = begin; i < end; ++i)
            body(i, Eigen::Index(problem.cones[i]));
      });
    };
    /// out = W^-2 u per cone (out may be u).
    auto scale_twice_inverse = [&](const Eigen::VectorXd &u, Eigen::VectorXd &out) {
      out.resize(rows);
      cone_loop([&](const std::size_t i, const auto d) {
        const double *wi = w.data() + offset[i];
        apply_scaling(wi, eta[i], d, u.data() + offset[i], out.data() + offset[i], true);
        apply_scaling(wi, eta[i], d, out.data() + offset[i], out.data() + offset[i], true);
      });
    };
    Eigen::VectorXd     t, Gdx, Gtt, dx, ds, dz, corrector, Gx, Gtz, Px; // work vectors of an iteration
    Eigen::VectorXd     dx_tau, dz_tau, Gdx_tau, c_tau;                  // the embedding's tau direction
    std::vector<double> cone_steps(m);
    const double        degree            = double(m) + (embedded ? 1 : 0); // of the cone, with tau kappa
    double              best_certificate  = std::numeric_limits<double>::infinity();
    unsigned int        stale_certificate = 0;
    for (result.iterations = 0;; ++result.iterations)
      {
        G_times(x, Gx);
        Gt_times(z, Gtz);
        Px                        = problem.P_diagonal.cwiseProduct(x);
        const double          xPx = x.dot(Px);
        const Eigen::VectorXd rx  = Px + tau * problem.q + Gtz;
        const Eigen::VectorXd rz  = s + Gx - tau * problem.h;
        const double          rt  = embedded ? kappa + problem.q.dot(x) + problem.h.dot(z) + xPx / tau : 0.0;
        const double          gap = s.dot(z);
        // Figures of the point x / tau, s / tau, z / tau.
        const double objective = (0.5 * xPx / tau + problem.q.dot(x)) / tau;
        result.primal_residual = rz.norm() / tau / h_scale;
        result.dual_residual   = rx.norm() / tau / q_scale;
        result.gap             = std::abs(gap) / (tau * tau) / std::max(1.0, std::abs(objective));
        result.objective       = objective;
        if (std::getenv("NLMECH_SOCP_DEBUG"))
          std::fprintf(
              stderr,
              "socp%s it %2u pres %.3e dres %.3e gap %.3e obj %.10g tau %.2e kappa %.2e (%.3f s, %.3f s "
              "factorising, %.3f s solving, %.3f s assembling)\n",
              embedded ? " (embedded)" : "", result.iterations, result.primal_residual, result.dual_residual,
              result.gap, objective, tau, kappa, since(started), result.factorization_seconds, solve_seconds,
              assemble_seconds);
        if (!(x.allFinite() && s.allFinite() && z.allFinite()) || !std::isfinite(result.gap) ||
            !std::isfinite(tau * kappa) || tau <= 0)
          {
            // Back to the last finite iterate and its figures (the loose tolerances may hold).
            x = last.x, s = last.s, z = last.z, tau = last_tau;
            result.primal_residual = last.primal_residual, result.dual_residual = last.dual_residual;
            result.gap = last.gap, result.objective = last.objective;
            status = ConicStatus::numerical_error;
            break;
          }
        last.x = x, last.s = s, last.z = z, last_tau = tau, last.primal_residual = result.primal_residual;
        last.dual_residual = result.dual_residual, last.gap = result.gap, last.objective = objective;
        if (result.primal_residual <= settings.feasibility_tolerance &&
            result.dual_residual <= settings.feasibility_tolerance && result.gap <= settings.gap_tolerance)
          {
            status = ConicStatus::solved;
            break;
          }
        const double hz = problem.h.dot(z);
        if (std::getenv("NLMECH_SOCP_DEBUG") && hz < 0)
          std::fprintf(stderr, "socp    certificate |G^T z| / -h^T z = %.3e\n", Gtz.norm() / -hz);
        if (hz < 0 && Gtz.norm() <= settings.infeasibility_tolerance * -hz)
          {
            status = ConicStatus::primal_infeasible;
            break;
          }
        if (embedded && tau < 1e-8)
          {
            // tau on its way to 0: an infeasible problem, whose certificate must now improve. Past
            // a few steps without (its accuracy is bounded by rounding: |G^T z| / |z| near 1e-15
            // for a gap of 1e-7 at the default tolerance), the run has stalled.
            const double ratio = hz < 0 ? Gtz.norm() / -hz : std::numeric_limits<double>::infinity();
            if (ratio < 0.5 * best_certificate)
              best_certificate = ratio, stale_certificate = 0;
            else if (++stale_certificate >= 5)
              {
                status = ConicStatus::stalled;
                break;
              }
          }
        if (embedded)
          {
            // A direction of unbounded descent: P x = 0, -G x in K (s = -G x), q^T x < 0.
            const double qx = problem.q.dot(x);
            if (qx < 0 && Px.norm() <= settings.infeasibility_tolerance * -qx &&
                (Gx + s).norm() <= settings.infeasibility_tolerance * -qx)
              {
                status = ConicStatus::dual_infeasible;
                break;
              }
          }
        if (result.iterations >= settings.max_iterations)
          break;

        // Nesterov-Todd scaling per cone: W z = W^-1 s = lambda.
        cone_loop([&](const std::size_t i, const auto d) {
          const double *si = s.data() + offset[i], *zi = z.data() + offset[i];
          double       *wi = w.data() + offset[i];
          const double  ss = std::sqrt(jnorm2(si, d)), zz = std::sqrt(jnorm2(zi, d));
          const double  is = 1 / ss, iz = 1 / zz;
          double        sz = si[0] * zi[0];
          for (Eigen::Index k = 1; k < d; ++k)
            sz += si[k] * zi[k];
          const double gamma = std::sqrt(0.5 * (1 + sz * is * iz)), ig = 1 / (2 * gamma);
          wi[0] = (si[0] * is + zi[0] * iz) * ig;
          for (Eigen::Index k = 1; k < d; ++k)
            wi[k] = (si[k] * is - zi[k] * iz) * ig;
          eta[i] = std::sqrt(ss * iz);
          apply_scaling(wi, eta[i], d, zi, lambda.data() + offset[i], false);
        });
        {
          const auto t0 = Clock::now();
          assemble(problem, w, eta);
          assemble_seconds += since(t0);
        }
        bool factorised = factorize();
        // With the embedding, a normal matrix that rounding has made indefinite (W^-2 over 30
        // orders of magnitude as tau -> 0) is shifted by 1e-12, 1e-10, 1e-8 of its largest
        // diagonal entry; the iterative refinement on the whole system below removes the shift.
        for (double shift = 1e-12; embedded && !factorised && shift <= 1e-8; shift *= 100)
          {
            double largest = 0;
            for (const long slot : diagonal_slot)
              largest = std::max(largest, normal.valuePtr()[slot]);
            for (const long slot : diagonal_slot)
              normal.valuePtr()[slot] += shift * largest;
            factorised = factorize();
          }
        if (!factorised)
          {
            status = ConicStatus::numerical_error;
            break;
          }
        if (embedded && tau < 1e-8 && hz < 0)
          {
            // Polish the certificate with the factorisation at hand: z' = z - W^-2 G N^-1 G^T z
            // removes G^T z but for P N^-1 G^T z (N = P + G^T W^-2 G, large as tau -> 0), where
            // the iterates' own |G^T z| / |z| stops near 1e-14 from rounding. Taken if z' is still
            // in K with h^T z' < 0 and passes the test.
            const Eigen::VectorXd correction = normal_solve(Gtz);
            G_times(correction, Gdx);
            scale_twice_inverse(Gdx, t);
            const Eigen::VectorXd polished = z - t;
            bool                  inside   = true;
            for (std::size_t i = 0; i < m && inside; ++i)
              inside = min_eigenvalue(cblock(polished, i)) >= 0;
            Gt_times(polished, Gtt);
            const double hp = problem.h.dot(polished);
            if (inside && hp < 0 && Gtt.norm() <= settings.infeasibility_tolerance * -hp)
              {
                z      = polished;
                status = ConicStatus::primal_infeasible;
                break;
              }
          }
        // The embedding: the direction of a unit change of tau, (N dx_tau = G^T W^-2 h - q,
        // dz_tau = W^-2 (G dx_tau - h)), shared by the predictor and the corrector, and the
        // coefficient of d tau in the linearised third row
        // d kappa + (2 P x / tau + q)^T dx + h^T dz - (x^T P x / tau^2) d tau = -r_tau.
        double tau_coefficient = 0;
        if (embedded)
          {
            scale_twice_inverse(problem.h, t);
            Gt_times(t, Gtt);
            dx_tau = normal_solve(Gtt - problem.q);
            G_times(dx_tau, Gdx_tau);
            Gdx_tau -= problem.h;
            scale_twice_inverse(Gdx_tau, dz_tau);
            Gdx_tau += problem.h;
            c_tau           = (2 / tau) * Px + problem.q;
            tau_coefficient = -kappa / tau + c_tau.dot(dx_tau) + problem.h.dot(dz_tau) - xPx / (tau * tau);
          }
        // The linearised system for the residuals (e_x, e_z, e_tau), the right-hand side d of
        // the linearised centrality and (embedding) d_kappa:
        //   P dx + G^T dz + q dtau = -e_x,            G dx + ds - h dtau = -e_z,
        //   dkappa + c^T dx + h^T dz - (x^T P x / tau^2) dtau = -e_tau,
        //   W^-1 ds + W dz = d,                       kappa dtau + tau dkappa = -d_kappa.
        // t = W^-1 (W^-1 e_z + d); dx from the normal equations; dz = W^-2 G dx + t;
        // ds = -e_z - G dx (+ h dtau) (equal to W (d - W dz), exact in the linear equation).
        double dtau = 0, dkappa = 0;
        auto   solve_linear = [&](const Eigen::VectorXd &e_x, const Eigen::VectorXd &e_z, const double e_tau,
                                const Eigen::VectorXd &rhs, const double d_kappa, Eigen::VectorXd &dx,
                                Eigen::VectorXd &ds, Eigen::VectorXd &dz, double &d_tau, double &d_kap) {
          t.resize(rows);
          cone_loop([&](const std::size_t i, const auto d) {
            double       *ti = t.data() + offset[i];
            const double *wi = w.data() + offset[i];
            apply_scaling(wi, eta[i], d, e_z.data() + offset[i], ti, true);
            for (Eigen::Index k = 0; k < d; ++k)
              ti[k] += rhs[offset[i] + k];
            apply_scaling(wi, eta[i], d, ti, ti, true);
          });
          Gt_times(t, Gtt);
          dx = normal_solve(-e_x - Gtt);
          G_times(dx, Gdx);
          dz.resize(rows);
          cone_loop([&](const std::size_t i, const auto d) {
            double       *dzi = dz.data() + offset[i];
            const double *wi  = w.data() + offset[i];
            apply_scaling(wi, eta[i], d, Gdx.data() + offset[i], dzi, true);
            apply_scaling(wi, eta[i], d, dzi, dzi, true);
            for (Eigen::Index k = 0; k < d; ++k)
              dzi[k] += t[offset[i] + k];
          });
          d_tau = d_kap = 0;
          if (embedded)
            {
              d_tau = (-e_tau + d_kappa / tau - c_tau.dot(dx) - problem.h.dot(dz)) / tau_coefficient;
              dx += d_tau * dx_tau, dz += d_tau * dz_tau, Gdx += d_tau * Gdx_tau;
              d_kap = (-d_kappa - kappa * d_tau) / tau;
            }
          ds = -e_z - Gdx + d_tau * problem.h;
        };
        // Newton step: the residuals weighted by f. With the embedding, one step of iterative
        // refinement on the whole linearised system (not only the normal equations): as tau goes
        // to 0 the normal matrix spans many orders of magnitude, and without it the certificate's
        // |G^T z| / -h^T z stopped at 1e-6 to 1e-8 for gaps of 1e-5 to 1e-7.
        Eigen::VectorXd e_x, e_z, e_d, ex2, ez2, es2, Gtdz;
        auto            newton = [&](const Eigen::VectorXd &rhs, const double f, const double d_kappa,
                          Eigen::VectorXd &dx, Eigen::VectorXd &ds, Eigen::VectorXd &dz) {
          e_x = f * rx, e_z = f * rz;
          solve_linear(e_x, e_z, f * rt, rhs, d_kappa, dx, ds, dz, dtau, dkappa);
          if (!embedded)
            return;
          Gt_times(dz, Gtdz);
          G_times(dx, Gdx);
          ex2              = problem.P_diagonal.cwiseProduct(dx) + Gtdz + dtau * problem.q + e_x;
          ez2              = Gdx + ds - dtau * problem.h + e_z;
          const double et2 = dkappa + c_tau.dot(dx) + problem.h.dot(dz) - xPx / (tau * tau) * dtau + f * rt;
          const double ek2 = kappa * dtau + tau * dkappa + d_kappa;
          e_d.resize(rows);
          cone_loop([&](const std::size_t i, const auto d) {
            // -(W^-1 ds + W dz - d)
            double        u[64], v[64];
            const double *wi = w.data() + offset[i];
            double       *ei = e_d.data() + offset[i];
            if (d > 64)
              {
                Eigen::VectorXd U{Eigen::Index(d)}, V{Eigen::Index(d)};
                apply_scaling(wi, eta[i], d, ds.data() + offset[i], U.data(), true);
                apply_scaling(wi, eta[i], d, dz.data() + offset[i], V.data(), false);
                for (Eigen::Index k = 0; k < d; ++k)
                  ei[k] = rhs[offset[i] + k] - U[k] - V[k];
                return;
              }
            apply_scaling(wi, eta[i], d, ds.data() + offset[i], u, true);
            apply_scaling(wi, eta[i], d, dz.data() + offset[i], v, false);
            for (Eigen::Index k = 0; k < d; ++k)
              ei[k] = rhs[offset[i] + k] - u[k] - v[k];
          });
          Eigen::VectorXd cx, cs, cz;
          double          ct = 0, ck = 0;
          solve_linear(ex2, ez2, et2, e_d, ek2, cx, cs, cz, ct, ck);
          dx += cx, ds += cs, dz += cz, dtau += ct, dkappa += ck;
        };
        auto max_step = [&](const Eigen::VectorXd &ds, const Eigen::VectorXd &dz) {
          cone_loop([&](const std::size_t i, const auto d) {
            const Eigen::Index o = offset[i];
            cone_steps[i]        = std::min(step_to_boundary(s.data() + o, ds.data() + o, d),
                                            step_to_boundary(z.data() + o, dz.data() + o, d));
          });
          double step = *std::min_element(cone_steps.begin(), cone_steps.end());
          if (dtau < 0)
            step = std::min(step, -tau / dtau);
          if (dkappa < 0)
            step = std::min(step, -kappa / dkappa);
          return step;
        };
        // Predictor (affine scaling): lambda o d = -lambda o lambda, i.e. d = -lambda.
        newton(-lambda, 1, tau * kappa, dx, ds, dz);
        const double alpha_a = std::min(1.0, max_step(ds, dz));
        const double mu      = (gap + tau * kappa) / degree;
        const double mu_a =
            ((s + alpha_a * ds).dot(z + alpha_a * dz) + (tau + alpha_a * dtau) * (kappa + alpha_a * dkappa)) /
            degree;
        const double sigma = std::clamp(std::pow(std::max(mu_a, 0.0) / mu, 3), 0.0, 1.0);
        // Corrector: lambda o d = sigma mu e - lambda o lambda - (W^-1 ds_a) o (W dz_a).
        corrector.resize(rows);
        cone_loop([&](const std::size_t i, const auto dim) {
          constexpr bool                   fixed = std::is_same_v<std::decay_t<decltype(dim)>, Four>;
          thread_local std::vector<double> scratch;
          double                           stack[3 * Four::value];
          double                          *u = stack;
          if constexpr (!fixed)
            {
              scratch.resize(3 * std::size_t(dim));
              u = scratch.data();
            }
          double       *v = u + dim, *r = v + dim;
          const double *li = lambda.data() + offset[i], *wi = w.data() + offset[i];
          apply_scaling(wi, eta[i], dim, ds.data() + offset[i], u, true);
          apply_scaling(wi, eta[i], dim, dz.data() + offset[i], v, false);
          // r = sigma mu e - lambda o lambda - u o v
          double l2 = 0, uv = 0;
          for (Eigen::Index k = 0; k < dim; ++k)
            l2 += li[k] * li[k], uv += u[k] * v[k];
          r[0] = sigma * mu - l2 - uv;
          for (Eigen::Index k = 1; k < dim; ++k)
            r[k] = -2 * li[0] * li[k] - (u[0] * v[k] + v[0] * u[k]);
          jordan_solve(li, r, dim, corrector.data() + offset[i]);
        });
        // Without the embedding the corrector removes the whole residual (CVXOPT's); with it,
        // the residuals shrink with the complementarity, by 1 - sigma (as ECOS and Clarabel).
        const double d_kappa = tau * kappa + dtau * dkappa - sigma * mu;
        newton(corrector, embedded ? 1 - sigma : 1.0, d_kappa, dx, ds, dz);
        const double alpha = std::min(1.0, settings.step_fraction * max_step(ds, dz));
        x += alpha * dx, s += alpha * ds, z += alpha * dz;
        tau += alpha * dtau, kappa += alpha * dkappa;
        if (std::getenv("NLMECH_SOCP_DEBUG"))
          std::fprintf(stderr, "socp    affine step %.3f sigma %.2e step %.3f\n", alpha_a, sigma, alpha);
        if (alpha < 1e-10)
          {
            status = ConicStatus::stalled;
            break;
          }
      }
    if (failed(status))
      {
        const double loose = settings.almost_factor;
        if (result.primal_residual <= loose * settings.feasibility_tolerance &&
            result.dual_residual <= loose * settings.feasibility_tolerance &&
            result.gap <= loose * settings.gap_tolerance)
          status = ConicStatus::almost_solved;
      }
    result.status   = status;
    result.embedded = embedded;
    if (status == ConicStatus::primal_infeasible)
      {
        // The certificate, scaled to h^T z = -1 (CVXOPT's convention).
        const double hz = -problem.h.dot(z);
        result.x = x / tau, result.s = s / hz, result.z = z / hz;
      }
    else if (status == ConicStatus::dual_infeasible)
      {
        // The direction, scaled to q^T x = -1.
        const double qx = -problem.q.dot(x);
        result.x = x / qx, result.s = s / qx, result.z = z / tau;
      }
    else
      result.x = x / tau, result.s = s / tau, result.z = z / tau;
    result.seconds = since(started);
    return result;
  }

  ConicResult ConicQPSolver::solve(const ConicQP &problem, const ConicSettings &settings,
                                   const Eigen::VectorXd *x_start, const Eigen::VectorXd *z_start)
  {
    const auto  started = Clock::now();
    const bool  embed   = settings.method == ConicMethod::embedded;
    ConicResult result  = solve_once(problem, settings, x_start, z_start, embed);
    auto        again   = [&](const ConicSettings &s, const bool embedded) {
      ConicResult next = solve_once(problem, s, nullptr, nullptr, embedded);
      next.iterations += result.iterations;
      next.factorization_seconds += result.factorization_seconds;
      return next;
    };
    if (!embed && failed(result.status) && x_start && settings.start_mu > 0)
      {
        // The centred start can be poor far from the solution (mu too small for the residuals):
        // start again from CVXOPT's point.
        ConicSettings standard = settings;
        standard.start_mu      = 0;
        result                 = again(standard, false);
      }
    if (settings.method == ConicMethod::automatic && failed(result.status))
      {
        // A stall or an iteration limit of the direct method, typical within about 1e-5 of
        // infeasibility: the embedding certifies either way (or fails too; then the direct
        // method's figures are kept, with both methods' iterations).
        ConicResult embedded = again(settings, true);
        if (!failed(embedded.status))
          result = embedded;
        else
          result.iterations = embedded.iterations;
      }
    result.seconds = since(started);
    return result;
  }
} // namespace nlmech
