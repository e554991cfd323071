#include <nlmech/models/solid/hyperelastic_tet_energy.h>
#include <nlmech/models/solid/neo_hookean_recurrences.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/tensor.h>

#include <algorithm>

namespace nlmech
{
  template class ElementEnergyTerm<HyperelasticTetElements>;

  void HyperelasticMaterial::check() const
  {
    AssertThrow(youngs_modulus > 0, dealii::ExcMessage("Young's modulus must be positive; it is " +
                                                       std::to_string(youngs_modulus) + " Pa."));
    AssertThrow(poissons_ratio < 0.5 && poissons_ratio > -1,
                dealii::ExcMessage("Poisson's ratio must lie in (-1, 0.5); it is " +
                                   std::to_string(poissons_ratio) + "."));
    AssertThrow(density >= 0, dealii::ExcMessage("The density must not be negative."));
  }

  HyperelasticTetElements::HyperelasticTetElements(const std::vector<dealii::Point<3>>          &rest,
                                                   const std::vector<std::vector<unsigned int>> &cells,
                                                   const HyperelasticMaterial                   &material)
      : law(material.law)
      , mu(material.shear_modulus())
      , kappa(material.bulk_modulus())
      , lambda(material.lame_lambda())
  {
    material.check();
    for (const auto &c : cells)
      {
        AssertThrow(c.size() == 4, dealii::ExcMessage("Hyperelastic tetrahedra need 4 vertices per cell."));
        dealii::Tensor<2, 3> Dm;
        for (int a = 0; a < 3; ++a)
          for (int d = 0; d < 3; ++d)
            Dm[d][a] = rest[c[a + 1]][d] - rest[c[0]][d];
        const double det = dealii::determinant(Dm);
        AssertThrow(det > 0, dealii::ExcMessage("An element of the rest shape is inverted or degenerate."));
        const dealii::Tensor<2, 3>           inverse = dealii::invert(Dm);
        std::array<std::array<double, 3>, 3> Dinv;
        for (int a = 0; a < 3; ++a)
          for (int j = 0; j < 3; ++j)
            Dinv[a][j] = inverse[a][j];
        tets.push_back({{c[0], c[1], c[2], c[3]}});
        rest_shape_inverse.push_back(Dinv);
        volume.push_back(det / 6);
      }
  }

  std::array<std::size_t, 12> HyperelasticTetElements::dofs(const std::size_t e) const
  {
    std::array<std::size_t, 12> d;
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i)
        d[3 * a + i] = 3 * std::size_t(tets[e][a]) + i;
    return d;
  }

  void HyperelasticTetElements::add_nodal_forces(const double (&P)[3][3], const std::size_t e,
                                                 std::array<double, 12> &out) const
  {
    // dE/dx_{a,i} = V sum_l P_il Dinv[a-1][l] for a = 1..3; vertex 0 balances the others.
    const auto &Dinv = rest_shape_inverse[e];
    for (int i = 0; i < 3; ++i)
      {
        double balance = 0;
        for (int a = 1; a < 4; ++a)
          {
            double f = 0;
            for (int l = 0; l < 3; ++l)
              f += P[i][l] * Dinv[a - 1][l];
            out[3 * a + i] += volume[e] * f;
            balance += volume[e] * f;
          }
        out[i] -= balance;
      }
  }

  void HyperelasticTetElements::prepare_series(const unsigned int k) const
  {
    if (law == HyperelasticLaw::neo_hookean && use_recurrences)
      cache.prepare(tets.size(), cached_series, k);
  }

  void
  HyperelasticTetElements::add_neo_hookean_series_by_recurrences(const std::vector<Eigen::VectorXd> &path,
                                                                 const unsigned int k, const std::size_t e,
                                                                 std::array<double, 12> &out) const
  {
    AssertThrow(k < cache.capacity(),
                dealii::ExcMessage("prepare_series(k) must be called before the recurrence kernel."));
    NeoHookeanSeries series;
    for (int ab = 0; ab < 9; ++ab)
      {
        series.F[ab] = cache.quantity(e, ab);
        series.C[ab] = cache.quantity(e, 9 + ab);
      }
    series.J        = cache.quantity(e, 18);
    series.Ic       = cache.quantity(e, 19);
    series.S        = cache.quantity(e, 20);
    series.U        = cache.quantity(e, 21);
    const auto dofs = this->dofs(e);

    // Orders below k-1 are exact and cached if this is the next order on the same path; order k-1
    // was computed with F_{k-1} left out and is redone now that it is known. F_m comes from
    // path[m] when it is part of the path, else it is 0 (the newest coefficient is left out).
    for (int m = cache.first_order(e, k, path[0].data()); m <= int(k); ++m)
      {
        double Fm[3][3] = {};
        if (m < int(k) && m < int(path.size()))
          {
            std::array<double, 12> local;
            for (int i = 0; i < 12; ++i)
              local[i] = path[m][dofs[i]];
            deformation_gradient(local, e, Fm);
          }
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b)
            series.F[3 * a + b][m] = Fm[a][b];
        series.advance(m);
      }
    double P[3][3];
    series.stress(int(k), mu, kappa, P);
    add_nodal_forces(P, e, out);
  }

  void HyperelasticTetElements::add_gradient_series_coefficient(const std::vector<Eigen::VectorXd> &path,
                                                                const unsigned int k, const std::size_t e,
                                                                std::array<double, 12> &out) const
  {
    if (law == HyperelasticLaw::neo_hookean && use_recurrences)
      {
        add_neo_hookean_series_by_recurrences(path, k, e, out);
        return;
      }
    using Series = TruncatedSeries<32>;
    using Dual   = ForwardGradient<Series, 9>;
    AssertThrow(k < Series::capacity, dealii::ExcMessage("The ANM order is limited to 31."));
    const auto dofs = this->dofs(e);
    Dual       F[3][3];
    for (int i = 0; i < 3; ++i)
      for (int l = 0; l < 3; ++l)
        F[i][l] = Dual(Series::zero(k), 3 * i + l);
    // F is linear in x: its coefficient j is F(path[j]) (coefficient k of x is left out).
    for (unsigned int j = 0; j < k && j < path.size(); ++j)
      {
        std::array<double, 12> local;
        for (int i = 0; i < 12; ++i)
          local[i] = path[j][dofs[i]];
        double Fj[3][3];
        deformation_gradient(local, e, Fj);
        for (int i = 0; i < 3; ++i)
          for (int l = 0; l < 3; ++l)
            F[i][l].v.coefficient(j) = Fj[i][l];
      }
    const Dual W = energy_density(F);
    double     P[3][3]; // coefficient k of the first Piola stress dW/dF
    for (int i = 0; i < 3; ++i)
      for (int l = 0; l < 3; ++l)
        P[i][l] = W.dx[3 * i + l][k];
    add_nodal_forces(P, e, out);
  }

  namespace
  {
    /// Levi-Civita symbol of (i, j, k) in {0, 1, 2}.
    int permutation_sign(const int i, const int j, const int k)
    {
      return (i - j) * (j - k) * (k - i) / 2;
    }
  } // namespace

  void HyperelasticTetElements::stress_and_tangent(const double (&F)[3][3], double (&P)[9],
                                                   double (&C)[9][9]) const
  {
    if (law != HyperelasticLaw::neo_hookean)
      {
        using Inner = Sacado::Fad::SFad<double, 9>;
        using Outer = Sacado::Fad::SFad<Inner, 9>;
        Outer G[3][3];
        for (int ab = 0; ab < 9; ++ab)
          G[ab / 3][ab % 3] = Outer(9, ab, Inner(9, ab, F[ab / 3][ab % 3]));
        const Outer W = energy_density(G);
        for (int ab = 0; ab < 9; ++ab)
          {
            P[ab] = W.dx(ab).val();
            for (int cd = 0; cd < 9; ++cd)
              C[ab][cd] = W.dx(ab).dx(cd);
          }
        return;
      }
    // W = mu/2 (s I_c - 3) + kappa/2 (J - 1)^2, s = J^(-2/3), u = s I_c / J, dJ/dF = cof F:
    // P = mu s F - mu/3 u cof F + kappa (J - 1) cof F,
    // ds/dF = -2/3 s/J cof F, du/dF = 2 s/J F - 5/3 u/J cof F, dcof_ij/dF_kl = e_ikm e_jln F_mn.
    double cof[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        {
          const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
          cof[i][j] = F[i1][j1] * F[i2][j2] - F[i1][j2] * F[i2][j1];
        }
    const double J  = F[0][0] * cof[0][0] + F[0][1] * cof[0][1] + F[0][2] * cof[0][2];
    double       Ic = 0;
    for (int ab = 0; ab < 9; ++ab)
      Ic += F[ab / 3][ab % 3] * F[ab / 3][ab % 3];
    const double s = std::pow(J, -2.0 / 3.0), u = s * Ic / J, c = kappa * (J - 1) - mu / 3 * u;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        {
          const int ij = 3 * i + j;
          P[ij]        = mu * s * F[i][j] + c * cof[i][j];
          for (int k = 0; k < 3; ++k)
            for (int l = 0; l < 3; ++l)
              {
                const double ds   = -2.0 / 3.0 * s / J * cof[k][l];
                const double du   = 2 * s / J * F[k][l] - 5.0 / 3.0 * u / J * cof[k][l];
                double       dcof = 0;
                if (i != k && j != l)
                  {
                    const int m = 3 - i - k, n = 3 - j - l;
                    dcof = permutation_sign(i, k, m) * permutation_sign(j, l, n) * F[m][n];
                  }
                C[ij][3 * k + l] = (i == k && j == l ? mu * s : 0.0) + mu * F[i][j] * ds -
                                   mu / 3 * du * cof[i][j] + kappa * cof[k][l] * cof[i][j] + c * dcof;
              }
        }
  }

  bool HyperelasticTetElements::element_hessian(const std::array<double, 12> &x, const std::size_t e,
                                                Eigen::Matrix<double, 12, 12> &H) const
  {
    if (!use_stress_tangent)
      return false;
    double F[3][3], P[9], C[9][9];
    deformation_gradient(x, e, F);
    stress_and_tangent(F, P, C);
    // dF_ij/dx_{b,k} = delta_ik G[b][j], G[b] = Dinv[b-1] (b = 1..3), G[0] = -sum of the others.
    const auto &Dinv = rest_shape_inverse[e];
    double      G[4][3];
    for (int j = 0; j < 3; ++j)
      {
        G[0][j] = 0;
        for (int b = 1; b < 4; ++b)
          {
            G[b][j] = Dinv[b - 1][j];
            G[0][j] -= G[b][j];
          }
      }
    // H_{(b,k),(c,l)} = V sum_{j,m} C[kj][lm] G[b][j] G[c][m]: first CG[kj][c,l] = sum_m C[kj][lm] G[c][m].
    double CG[9][12];
    for (int kj = 0; kj < 9; ++kj)
      for (int c = 0; c < 4; ++c)
        for (int l = 0; l < 3; ++l)
          CG[kj][3 * c + l] =
              C[kj][3 * l] * G[c][0] + C[kj][3 * l + 1] * G[c][1] + C[kj][3 * l + 2] * G[c][2];
    for (int b = 0; b < 4; ++b)
      for (int k = 0; k < 3; ++k)
        for (int q = 0; q < 12; ++q)
          H(3 * b + k, q) =
              volume[e] * (CG[3 * k][q] * G[b][0] + CG[3 * k + 1][q] * G[b][1] + CG[3 * k + 2][q] * G[b][2]);
    return true;
  }

  HyperelasticTetTerm::HyperelasticTetTerm(const std::vector<dealii::Point<3>>          &rest,
                                           const std::vector<std::vector<unsigned int>> &tets,
                                           const HyperelasticMaterial                   &material)
      : ElementEnergyTerm<HyperelasticTetElements>(material.law == HyperelasticLaw::neo_hookean
                                                       ? "neo-Hookean tetrahedra"
                                                       : "St.Venant-Kirchhoff tetrahedra",
                                                   HyperelasticTetElements(rest, tets, material))
  {
  }

  double HyperelasticTetTerm::min_jacobian(const Eigen::VectorXd &x) const
  {
    const auto         &el = elements();
    std::vector<double> least_per_block((el.n_elements() + block_size - 1) / block_size,
                                        std::numeric_limits<double>::max());
    for_each_block(el.n_elements(), block_size, [&](const std::size_t begin, const std::size_t end) {
      double least = std::numeric_limits<double>::max();
      for (std::size_t e = begin; e < end; ++e)
        {
          const auto             dofs = el.dofs(e);
          std::array<double, 12> local;
          for (int i = 0; i < 12; ++i)
            local[i] = x[dofs[i]];
          double F[3][3];
          el.deformation_gradient(local, e, F);
          least = std::min(least, HyperelasticTetElements::determinant(F));
        }
      least_per_block[begin / block_size] = least;
    });
    double least = std::numeric_limits<double>::max();
    for (const double l : least_per_block)
      least = std::min(least, l);
    return least;
  }

  bool HyperelasticTetTerm::is_valid(const Eigen::VectorXd &x) const
  {
    // St.Venant-Kirchhoff is defined for inverted elements too, but an inverted state is never a
    // physical answer; both laws treat det F <= 0 as invalid.
    return min_jacobian(x) > 0;
  }

  double first_nonpositive_point(const std::vector<double> &c, const double t_max, const int samples)
  {
    // Sample, then bisect the first sign change: robust for the tiny or vanishing leading terms
    // that make closed-form roots unstable.
    auto p = [&](double t) {
      double v = 0;
      for (int k = int(c.size()) - 1; k >= 0; --k)
        v = c[k] + t * v;
      return v;
    };
    double t0 = 0;
    for (int s = 1; s <= samples; ++s)
      {
        const double t1 = t_max * s / samples;
        if (p(t1) <= 0)
          {
            double lo = t0, hi = t1;
            for (int it = 0; it < 60; ++it)
              {
                const double mid       = 0.5 * (lo + hi);
                (p(mid) > 0 ? lo : hi) = mid;
              }
            return lo;
          }
        t0 = t1;
      }
    return t_max;
  }

  double first_positive_root_of_cubic(const std::array<double, 4> &c, const double t_max)
  {
    return first_nonpositive_point({c[0], c[1], c[2], c[3]}, t_max, 64);
  }

  double HyperelasticTetTerm::first_inversion_along_series(const std::vector<Eigen::VectorXd> &path,
                                                           const double                        a_max) const
  {
    using Series   = TruncatedSeries<32>;
    const auto &el = elements();
    const int   n  = std::min<int>(path.size() - 1, Series::capacity - 1);
    // Each block searches up to the bound found so far in its own elements; the blocks do not
    // depend on the thread count, nor does the answer.
    std::vector<double> first_per_block((el.n_elements() + block_size - 1) / block_size, a_max);
    for_each_block(el.n_elements(), block_size, [&](const std::size_t begin, const std::size_t end) {
      double              first = a_max;
      std::vector<double> c(n + 1);
      for (std::size_t e = begin; e < end; ++e)
        {
          const auto             dofs = el.dofs(e);
          std::array<Series, 12> local;
          for (int i = 0; i < 12; ++i)
            {
              local[i] = Series::zero(n);
              for (int k = 0; k <= n; ++k)
                local[i].coefficient(k) = path[k][dofs[i]];
            }
          Series F[3][3];
          el.deformation_gradient(local, e, F);
          const Series J = HyperelasticTetElements::determinant(F);
          for (int k = 0; k <= n; ++k)
            c[k] = J[k];
          first = first_nonpositive_point(c, first); // det F(a) of this element, up to the bound so far
        }
      first_per_block[begin / block_size] = first;
    });
    double first = a_max;
    for (const double f : first_per_block)
      first = std::min(first, f);
    return first;
  }

  double HyperelasticTetTerm::max_safe_step(const Eigen::VectorXd &x, const Eigen::VectorXd &dx) const
  {
    // det F(t) = det(F + t dF) is a cubic in t per element: c0 = det F, c3 = det dF, and c1, c2
    // from the mixed terms (evaluated exactly by sampling the cubic at t = -1, 1, 2).
    const auto         &el = elements();
    std::vector<double> step_per_block((el.n_elements() + block_size - 1) / block_size, 1.0);
    for_each_block(el.n_elements(), block_size, [&](const std::size_t begin, const std::size_t end) {
      double step = 1.0;
      for (std::size_t e = begin; e < end; ++e)
        {
          const auto             dofs = el.dofs(e);
          std::array<double, 12> local, delta;
          for (int i = 0; i < 12; ++i)
            local[i] = x[dofs[i]], delta[i] = dx[dofs[i]];
          double F[3][3], dF[3][3];
          el.deformation_gradient(local, e, F);
          el.deformation_gradient(delta, e, dF);
          auto det_at = [&](double t) {
            double G[3][3];
            for (int i = 0; i < 3; ++i)
              for (int j = 0; j < 3; ++j)
                G[i][j] = F[i][j] + t * dF[i][j];
            return HyperelasticTetElements::determinant(G);
          };
          const double p0 = det_at(0), pp = det_at(1), pm = det_at(-1), p2 = det_at(2);
          const double c2 = 0.5 * (pp + pm) - p0;
          const double c3 = (p2 - 3 * pp + 3 * p0 - pm) / 6.0; // third difference = 3! c3
          const double c1 = pp - p0 - c2 - c3;
          step            = std::min(step, first_positive_root_of_cubic({{p0, c1, c2, c3}}, step));
        }
      step_per_block[begin / block_size] = step;
    });
    double step = 1.0;
    for (const double s : step_per_block)
      step = std::min(step, s);
    return step;
  }
} // namespace nlmech
