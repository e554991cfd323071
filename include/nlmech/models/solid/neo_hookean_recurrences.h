#pragma once
// The compressible neo-Hookean first Piola stress as a Taylor series in the path parameter, by
// auxiliary-variable recurrences (ANM paper, section 4.2.2 and appendix A): with cof F, J = det F,
// I_c = F:F, s = J^(-2/3) and u = s I_c / J as auxiliary series, every coefficient is a Cauchy
// product or a linear recurrence in the lower ones, so that order m costs O(m) once the orders
// below are known. Shared by the forward kernel (F linear in x) and the inverse one (F rational in
// the rest shape X).

#include <cmath>

namespace nlmech
{
  /// Coefficients 0..m of F (9, row-major), cof F (9), J, I_c, s, u, held by the caller.
  struct NeoHookeanSeries
  {
    double *F[9];
    double *C[9];
    double *J, *Ic, *S, *U;

    /// Sum_{i=0}^m x_i y_{m-i}.
    static double cauchy(const double *x, const double *y, const int m)
    {
      double sum = 0;
      for (int i = 0; i <= m; ++i)
        sum += x[i] * y[m - i];
      return sum;
    }

    /// Coefficient m of cof F, J, I_c, s, u from F_0..F_m and their own coefficients below m.
    void advance(const int m) const
    {
      constexpr double p = -2.0 / 3.0;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
          {
            const int a1 = (a + 1) % 3, a2 = (a + 2) % 3, b1 = (b + 1) % 3, b2 = (b + 2) % 3;
            C[3 * a + b][m] =
                cauchy(F[3 * a1 + b1], F[3 * a2 + b2], m) - cauchy(F[3 * a1 + b2], F[3 * a2 + b1], m);
          }
      J[m] = Ic[m] = 0;
      for (int b = 0; b < 3; ++b)
        J[m] += cauchy(F[b], C[b], m); // det F = row 0 of F . row 0 of cof F
      for (int ab = 0; ab < 9; ++ab)
        Ic[m] += cauchy(F[ab], F[ab], m);
      if (m == 0)
        S[0] = std::pow(J[0], p);
      else
        {
          double sum = 0; // s = J^p: s_m = 1/(m J_0) sum_{j=1}^m ((p+1) j - m) J_j s_{m-j}
          for (int j = 1; j <= m; ++j)
            sum += ((p + 1) * j - m) * J[j] * S[m - j];
          S[m] = sum / (m * J[0]);
        }
      double sum = cauchy(S, Ic, m); // u = s I_c / J: u_m = ((s I_c)_m - sum_{j=1}^m J_j u_{m-j}) / J_0
      for (int j = 1; j <= m; ++j)
        sum -= J[j] * U[m - j];
      U[m] = sum / J[0];
    }

    /// Coefficient m of P = mu s F - mu/3 u cof F + kappa (J - 1) cof F.
    void stress(const int m, const double mu, const double kappa, double (&P)[3][3]) const
    {
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
          {
            const int ab = 3 * a + b;
            P[a][b]      = mu * cauchy(S, F[ab], m) - mu / 3 * cauchy(U, C[ab], m) +
                      kappa * (cauchy(J, C[ab], m) - C[ab][m]);
          }
    }
  };
} // namespace nlmech
