#include <nlmech/base/rank_sharing.h>
#include <nlmech/base/threads.h>
#include <nlmech/base/truncated_series.h>
#include <nlmech/models/solid/inverse_hyperelastic.h>
#include <nlmech/models/solid/neo_hookean_recurrences.h>

#include <deal.II/base/exceptions.h>

#include <algorithm>

namespace nlmech
{
  namespace
  {
    std::array<std::size_t, 12> element_dofs(const std::array<unsigned int, 4> &tet)
    {
      std::array<std::size_t, 12> d;
      for (int a = 0; a < 4; ++a)
        for (int i = 0; i < 3; ++i)
          d[3 * a + i] = 3 * std::size_t(tet[a]) + i;
      return d;
    }
  } // namespace

  InverseHyperelasticSystem::InverseHyperelasticSystem(const RawSimplexMesh<3>         &mesh,
                                                       const Eigen::VectorXd           &target,
                                                       const HyperelasticMaterial      &material,
                                                       const std::vector<unsigned int> &fixed_vertices)
      : target(target)
      , density(mesh.vertices, mesh.cells, material) // checks the target (= mesh) elements
  {
    AssertThrow(std::size_t(target.size()) == 3 * mesh.vertices.size(),
                dealii::ExcMessage("The target shape needs 3 coordinates per mesh vertex."));
    tets = density.tets;
    for (unsigned int v : fixed_vertices)
      for (int i = 0; i < 3; ++i)
        fixed_values[3 * std::size_t(v) + i] = target[3 * std::size_t(v) + i];
    AssertThrow(!fixed_values.empty(), dealii::ExcMessage("Inverse design needs supports (fixed vertices)."));
  }

  template <typename S>
  void InverseHyperelasticSystem::element_force(const std::size_t e, const std::array<S, 12> &X,
                                                std::array<S, 12> &force) const
  {
    const auto dofs = element_dofs(tets[e]);
    // D_m(X) and its inverse by the adjugate; rest volume V = det D_m / 6.
    S Dm[3][3];
    for (int d = 0; d < 3; ++d)
      for (int a = 0; a < 3; ++a)
        Dm[d][a] = X[3 * (a + 1) + d] - X[d];
    const S det = HyperelasticTetElements::determinant(Dm);
    S       inverse[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        {
          const int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
          inverse[i][j] = (Dm[i1][j1] * Dm[i2][j2] - Dm[i1][j2] * Dm[i2][j1]) / det;
        }
    // F = D_s(x) D_m^-1, x the (fixed) target.
    using Dual = ForwardGradient<S, 9>;
    Dual F[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        {
          S value = 0.0;
          for (int a = 0; a < 3; ++a)
            value += (target[dofs[3 * (a + 1) + i]] - target[dofs[i]]) * inverse[a][j];
          F[i][j] = Dual(value, 3 * i + j);
        }
    const Dual W = density.energy_density(F);
    const S    V = det * (1.0 / 6.0);
    // dE/dx_{a,i} = V sum_j P_ij (D_m^-1)_{a-1, j}; vertex 0 balances the others.
    for (int i = 0; i < 3; ++i)
      {
        S balance = 0.0;
        for (int a = 1; a < 4; ++a)
          {
            S f = 0.0;
            for (int j = 0; j < 3; ++j)
              f += W.dx[3 * i + j] * inverse[a - 1][j];
            force[3 * a + i] = V * f;
            balance += force[3 * a + i];
          }
        force[i] = balance * (-1.0);
      }
  }

  std::array<std::size_t, 12> InverseHyperelasticSystem::dofs(const std::size_t e) const
  {
    return element_dofs(tets[e]);
  }

  Eigen::VectorXd InverseHyperelasticSystem::internal_force(const Eigen::VectorXd &X) const
  {
    // This rank's elements (all without rank sharing), summed over the sharing ranks.
    Eigen::VectorXd r     = Eigen::VectorXd::Zero(X.size());
    const auto      owned = owned_elements(tets.size());
    add_element_vectors<12>(
        owned.first, owned.second, block_size, [&](const std::size_t e) { return dofs(e); },
        [&](const std::size_t e, std::array<double, 12> &force) {
          const auto             d = dofs(e);
          std::array<double, 12> local;
          for (int i = 0; i < 12; ++i)
            local[i] = X[d[i]];
          element_force(e, local, force);
        },
        r);
    sum_over_sharing_ranks(r.data(), r.size());
    return r;
  }

  void InverseHyperelasticSystem::element_tangent(const std::size_t e, const std::array<double, 12> &X,
                                                  Eigen::Matrix<double, 12, 12> &K) const
  {
    using Fad = Sacado::Fad::SFad<double, 12>;
    std::array<Fad, 12> local;
    for (int i = 0; i < 12; ++i)
      local[i] = Fad(12, i, X[i]);
    if (!use_stress_tangent)
      {
        std::array<Fad, 12> force;
        element_force(e, local, force);
        for (int i = 0; i < 12; ++i)
          for (int j = 0; j < 12; ++j)
            K(i, j) = force[i].dx(j);
        return;
      }
    // r_{a,i} = sum_j P_ij(F) A_{a-1,j} / 6 with A = adj D_m(X), F = D_s A / det D_m: A and F with
    // their first derivatives in X (Fad over 12, polynomial and rational, cheap), P and dP/dF at F.
    const auto d = dofs(e);
    Fad        Dm[3][3], A[3][3];
    for (int i = 0; i < 3; ++i)
      for (int a = 0; a < 3; ++a)
        Dm[i][a] = local[3 * (a + 1) + i] - local[i];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        {
          const int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
          A[i][j] = Dm[i1][j1] * Dm[i2][j2] - Dm[i1][j2] * Dm[i2][j1];
        }
    const Fad det = Dm[0][0] * A[0][0] + Dm[0][1] * A[1][0] + Dm[0][2] * A[2][0];
    Fad       F[3][3];
    double    Fv[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        {
          Fad value = 0.0;
          for (int a = 0; a < 3; ++a)
            value += (target[d[3 * (a + 1) + i]] - target[d[i]]) * A[a][j];
          F[i][j]  = value / det;
          Fv[i][j] = F[i][j].val();
        }
    double P[9], C[9][9];
    density.stress_and_tangent(Fv, P, C);
    // dP_ij/dX_q = sum_kl C[ij][kl] dF_kl/dX_q
    double dP[9][12];
    for (int ij = 0; ij < 9; ++ij)
      for (int q = 0; q < 12; ++q)
        {
          double sum = 0;
          for (int kl = 0; kl < 9; ++kl)
            sum += C[ij][kl] * F[kl / 3][kl % 3].fastAccessDx(q);
          dP[ij][q] = sum;
        }
    for (int i = 0; i < 3; ++i)
      for (int q = 0; q < 12; ++q)
        {
          double balance = 0;
          for (int a = 1; a < 4; ++a)
            {
              double f = 0;
              for (int j = 0; j < 3; ++j)
                f += dP[3 * i + j][q] * A[a - 1][j].val() + P[3 * i + j] * A[a - 1][j].fastAccessDx(q);
              K(3 * a + i, q) = f / 6.0;
              balance += f / 6.0;
            }
          K(i, q) = -balance;
        }
  }

  Eigen::SparseMatrix<double> InverseHyperelasticSystem::tangent(const Eigen::VectorXd &X) const
  {
    // Other ranks' elements give their pattern with zeros: the same matrix structure on every
    // rank, whose values are then summed over the sharing ranks.
    Triplets   triplets(144 * tets.size());
    const auto owned = owned_elements(tets.size());
    for_each_block(tets.size(), block_size / 2, [&](const std::size_t begin, const std::size_t end) {
      for (std::size_t e = begin; e < end; ++e)
        {
          const auto                    d = dofs(e);
          Eigen::Matrix<double, 12, 12> K = Eigen::Matrix<double, 12, 12>::Zero();
          if (e >= owned.first && e < owned.second)
            {
              std::array<double, 12> local;
              for (int i = 0; i < 12; ++i)
                local[i] = X[d[i]];
              element_tangent(e, local, K);
            }
          for (int i = 0; i < 12; ++i)
            for (int j = 0; j < 12; ++j)
              triplets[144 * e + 12 * i + j] = Eigen::Triplet<double>(int(d[i]), int(d[j]), K(i, j));
        }
    });
    Eigen::SparseMatrix<double> K(X.size(), X.size());
    K.setFromTriplets(triplets.begin(), triplets.end());
    sum_over_sharing_ranks(K.valuePtr(), K.nonZeros());
    return K;
  }

  void InverseHyperelasticSystem::prepare_series(const unsigned int k) const
  {
    if (density.law == HyperelasticLaw::neo_hookean && use_recurrences)
      cache.prepare(tets.size(), cached_series, k);
  }

  void
  InverseHyperelasticSystem::add_force_series_by_truncated_series(const std::vector<Eigen::VectorXd> &path,
                                                                  const unsigned int k, const std::size_t e,
                                                                  std::array<double, 12> &force) const
  {
    using Series = TruncatedSeries<32>;
    AssertThrow(k < Series::capacity, dealii::ExcMessage("The ANM order is limited to 31."));
    const auto             d = dofs(e);
    std::array<Series, 12> local, series_force;
    for (int i = 0; i < 12; ++i)
      {
        local[i] = Series::zero(k);
        for (unsigned int j = 0; j < k && j < path.size(); ++j)
          local[i].coefficient(j) = path[j][d[i]];
      }
    element_force(e, local, series_force);
    for (int i = 0; i < 12; ++i)
      force[i] += series_force[i][k];
  }

  void InverseHyperelasticSystem::add_force_series_by_recurrences(const std::vector<Eigen::VectorXd> &path,
                                                                  const unsigned int k, const std::size_t e,
                                                                  std::array<double, 12> &force) const
  {
    AssertThrow(k < cache.capacity(),
                dealii::ExcMessage("prepare_series(k) must be called before the recurrence kernel."));
    double *D[9], *A[9], *P[9];
    for (int ab = 0; ab < 9; ++ab)
      {
        D[ab] = cache.quantity(e, ab);
        A[ab] = cache.quantity(e, 9 + ab);
        P[ab] = cache.quantity(e, 41 + ab);
      }
    double          *det = cache.quantity(e, 18);
    NeoHookeanSeries series;
    for (int ab = 0; ab < 9; ++ab)
      {
        series.F[ab] = cache.quantity(e, 19 + ab);
        series.C[ab] = cache.quantity(e, 28 + ab);
      }
    series.J     = cache.quantity(e, 37);
    series.Ic    = cache.quantity(e, 38);
    series.S     = cache.quantity(e, 39);
    series.U     = cache.quantity(e, 40);
    const auto d = dofs(e);
    double     Ds[3][3]; // D_s of the (fixed) target
    for (int i = 0; i < 3; ++i)
      for (int a = 0; a < 3; ++a)
        Ds[i][a] = target[d[3 * (a + 1) + i]] - target[d[i]];
    using Cauchy = NeoHookeanSeries;

    // Orders below k-1 are cached and exact when this is the next order on the same path; order
    // k-1 was computed with X_{k-1} left out and is redone; X_k is left out (taken as zero).
    for (int m = cache.first_order(e, k, path[0].data()); m <= int(k); ++m)
      {
        const bool known = m < int(k) && m < int(path.size());
        for (int i = 0; i < 3; ++i)
          for (int a = 0; a < 3; ++a)
            D[3 * i + a][m] = known ? path[m][d[3 * (a + 1) + i]] - path[m][d[i]] : 0.0;
        // A = adj D_m (quadratic in X), det D_m = row 0 of D_m . column 0 of A (cubic in X).
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            {
              const int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
              A[3 * i + j][m] = Cauchy::cauchy(D[3 * i1 + j1], D[3 * i2 + j2], m) -
                                Cauchy::cauchy(D[3 * i1 + j2], D[3 * i2 + j1], m);
            }
        det[m] = 0;
        for (int b = 0; b < 3; ++b)
          det[m] += Cauchy::cauchy(D[b], A[3 * b], m);
        // F = D_s A / det: F_m = ((D_s A)_m - sum_{j=1}^m det_j F_{m-j}) / det_0.
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            {
              double value = 0;
              for (int a = 0; a < 3; ++a)
                value += Ds[i][a] * A[3 * a + j][m];
              for (int l = 1; l <= m; ++l)
                value -= det[l] * series.F[3 * i + j][m - l];
              series.F[3 * i + j][m] = value / det[0];
            }
        series.advance(m);
        double Pm[3][3];
        series.stress(m, density.mu, density.kappa, Pm);
        for (int ab = 0; ab < 9; ++ab)
          P[ab][m] = Pm[ab / 3][ab % 3];
      }
    // dE/dx_{a,i} = V sum_j P_ij (D_m^-1)_{a-1,j} = sum_j P_ij A_{a-1,j} / 6; vertex 0 balances.
    for (int i = 0; i < 3; ++i)
      {
        double balance = 0;
        for (int a = 1; a < 4; ++a)
          {
            double f = 0;
            for (int j = 0; j < 3; ++j)
              f += Cauchy::cauchy(P[3 * i + j], A[3 * (a - 1) + j], int(k));
            force[3 * a + i] += f / 6.0;
            balance += f / 6.0;
          }
        force[i] -= balance;
      }
  }

  Eigen::VectorXd
  InverseHyperelasticSystem::internal_force_series_coefficient(const std::vector<Eigen::VectorXd> &path,
                                                               const unsigned int                  k) const
  {
    const bool recurrences = density.law == HyperelasticLaw::neo_hookean && use_recurrences;
    prepare_series(k);
    Eigen::VectorXd out   = Eigen::VectorXd::Zero(path[0].size());
    const auto      owned = owned_elements(tets.size());
    add_element_vectors<12>(
        owned.first, owned.second, block_size, [&](const std::size_t e) { return dofs(e); },
        [&](const std::size_t e, std::array<double, 12> &force) {
          if (recurrences)
            add_force_series_by_recurrences(path, k, e, force);
          else
            add_force_series_by_truncated_series(path, k, e, force);
        },
        out);
    sum_over_sharing_ranks(out.data(), out.size());
    return out;
  }

  bool InverseHyperelasticSystem::is_valid(const Eigen::VectorXd &X) const
  {
    const std::size_t n_blocks = (tets.size() + block_size - 1) / block_size;
    std::vector<char> valid(n_blocks, 1);
    for_each_block(tets.size(), block_size, [&](const std::size_t begin, const std::size_t end) {
      for (std::size_t e = begin; e < end; ++e)
        {
          const auto d = dofs(e);
          double     Dm[3][3];
          for (int i = 0; i < 3; ++i)
            for (int a = 0; a < 3; ++a)
              Dm[i][a] = X[d[3 * (a + 1) + i]] - X[d[i]];
          if (HyperelasticTetElements::determinant(Dm) <= 0)
            {
              valid[begin / block_size] = 0;
              return;
            }
        }
    });
    return std::all_of(valid.begin(), valid.end(), [](const char v) { return v != 0; });
  }

  double InverseHyperelasticSystem::first_invalid_along_series(const std::vector<Eigen::VectorXd> &path,
                                                               const double a_max) const
  {
    using Series = TruncatedSeries<32>;
    const int n  = std::min<int>(path.size() - 1, Series::capacity - 1);
    // Per block, up to the bound found so far in its own elements: the same for every thread count.
    std::vector<double> first_per_block((tets.size() + block_size - 1) / block_size, a_max);
    for_each_block(tets.size(), block_size, [&](const std::size_t begin, const std::size_t end) {
      double              first = a_max;
      std::vector<double> c(n + 1);
      for (std::size_t e = begin; e < end; ++e)
        {
          const auto d = dofs(e);
          Series     Dm[3][3];
          for (int i = 0; i < 3; ++i)
            for (int a = 0; a < 3; ++a)
              {
                Dm[i][a] = Series::zero(n);
                for (int j = 0; j <= n; ++j)
                  Dm[i][a].coefficient(j) = path[j][d[3 * (a + 1) + i]] - path[j][d[i]];
              }
          const Series det = HyperelasticTetElements::determinant(Dm);
          for (int j = 0; j <= n; ++j)
            c[j] = det[j];
          first = first_nonpositive_point(c, first); // 6 V(a) of this rest element
        }
      first_per_block[begin / block_size] = first;
    });
    return *std::min_element(first_per_block.begin(), first_per_block.end());
  }

  template void InverseHyperelasticSystem::element_force(std::size_t, const std::array<double, 12> &,
                                                         std::array<double, 12> &) const;
} // namespace nlmech
