#include <nlmech/base/truncated_series.h>
#include <nlmech/models/solid/inverse_hyperelastic.h>

#include <deal.II/base/exceptions.h>

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

  Eigen::VectorXd InverseHyperelasticSystem::internal_force(const Eigen::VectorXd &X) const
  {
    Eigen::VectorXd r = Eigen::VectorXd::Zero(X.size());
    for (std::size_t e = 0; e < tets.size(); ++e)
      {
        const auto             dofs = element_dofs(tets[e]);
        std::array<double, 12> local, force;
        for (int i = 0; i < 12; ++i)
          local[i] = X[dofs[i]];
        element_force(e, local, force);
        for (int i = 0; i < 12; ++i)
          r[dofs[i]] += force[i];
      }
    return r;
  }

  Eigen::SparseMatrix<double> InverseHyperelasticSystem::tangent(const Eigen::VectorXd &X) const
  {
    using Fad = Sacado::Fad::SFad<double, 12>;
    Triplets triplets;
    triplets.reserve(144 * tets.size());
    for (std::size_t e = 0; e < tets.size(); ++e)
      {
        const auto          dofs = element_dofs(tets[e]);
        std::array<Fad, 12> local, force;
        for (int i = 0; i < 12; ++i)
          local[i] = Fad(12, i, X[dofs[i]]);
        element_force(e, local, force);
        for (int i = 0; i < 12; ++i)
          for (int j = 0; j < 12; ++j)
            triplets.emplace_back(dofs[i], dofs[j], force[i].dx(j));
      }
    Eigen::SparseMatrix<double> K(X.size(), X.size());
    K.setFromTriplets(triplets.begin(), triplets.end());
    return K;
  }

  Eigen::VectorXd
  InverseHyperelasticSystem::internal_force_series_coefficient(const std::vector<Eigen::VectorXd> &path,
                                                               const unsigned int                  k) const
  {
    using Series = TruncatedSeries<32>;
    AssertThrow(k < Series::capacity, dealii::ExcMessage("The ANM order is limited to 31."));
    Eigen::VectorXd out = Eigen::VectorXd::Zero(path[0].size());
    for (std::size_t e = 0; e < tets.size(); ++e)
      {
        const auto             dofs = element_dofs(tets[e]);
        std::array<Series, 12> local, force;
        for (int i = 0; i < 12; ++i)
          {
            local[i] = Series::zero(k);
            for (unsigned int j = 0; j < k && j < path.size(); ++j)
              local[i].coefficient(j) = path[j][dofs[i]];
          }
        element_force(e, local, force);
        for (int i = 0; i < 12; ++i)
          out[dofs[i]] += force[i][k];
      }
    return out;
  }

  bool InverseHyperelasticSystem::is_valid(const Eigen::VectorXd &X) const
  {
    for (const auto &tet : tets)
      {
        const auto dofs = element_dofs(tet);
        double     Dm[3][3];
        for (int d = 0; d < 3; ++d)
          for (int a = 0; a < 3; ++a)
            Dm[d][a] = X[dofs[3 * (a + 1) + d]] - X[dofs[d]];
        if (HyperelasticTetElements::determinant(Dm) <= 0)
          return false;
      }
    return true;
  }

  double InverseHyperelasticSystem::first_invalid_along_series(const std::vector<Eigen::VectorXd> &path,
                                                               const double a_max) const
  {
    using Series    = TruncatedSeries<32>;
    const int n     = std::min<int>(path.size() - 1, Series::capacity - 1);
    double    first = a_max;
    for (const auto &tet : tets)
      {
        const auto dofs = element_dofs(tet);
        Series     Dm[3][3];
        for (int d = 0; d < 3; ++d)
          for (int a = 0; a < 3; ++a)
            {
              Dm[d][a] = Series::zero(n);
              for (int j = 0; j <= n; ++j)
                Dm[d][a].coefficient(j) = path[j][dofs[3 * (a + 1) + d]] - path[j][dofs[d]];
            }
        const Series        det = HyperelasticTetElements::determinant(Dm);
        std::vector<double> c(n + 1);
        for (int j = 0; j <= n; ++j)
          c[j] = det[j];
        first = first_nonpositive_point(c, first); // 6 V(a) of this rest element
      }
    return first;
  }

  template void InverseHyperelasticSystem::element_force(std::size_t, const std::array<double, 12> &,
                                                         std::array<double, 12> &) const;
} // namespace nlmech
