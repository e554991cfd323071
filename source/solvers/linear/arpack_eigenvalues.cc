#include <deal.II/base/exceptions.h>

#include <nlmech/solvers/linear/arpack_eigenvalues.h>

#include <algorithm>
#include <string>

// ARPACK's double-precision nonsymmetric drivers (Fortran 77, trailing underscore; the hidden
// string lengths are all 1 or 2 and not read by ARPACK).
extern "C"
{
  void dnaupd_(int *ido, char *bmat, int *n, char *which, int *nev, double *tol, double *resid, int *ncv,
               double *v, int *ldv, int *iparam, int *ipntr, double *workd, double *workl, int *lworkl,
               int *info);
  void dneupd_(int *rvec, char *howmany, int *select, double *dr, double *di, double *z, int *ldz,
               double *sigmar, double *sigmai, double *workev, char *bmat, int *n, char *which, int *nev,
               double *tol, double *resid, int *ncv, double *v, int *ldv, int *iparam, int *ipntr,
               double *workd, double *workl, int *lworkl, int *info);
}

namespace nlmech
{
  ArpackResult largest_eigenvalues(const std::function<void(const double *x, double *y)> &apply,
                                   const unsigned int dimension, const ArpackSettings &settings)
  {
    int n   = int(dimension);
    int nev = int(settings.n_eigenvalues);
    AssertThrow(nev >= 1 && nev + 2 <= n,
                dealii::ExcMessage("ARPACK: " + std::to_string(nev) +
                                   " eigenvalues of an operator of dimension " + std::to_string(n) +
                                   " (at most the dimension minus 2)."));
    int ncv                 = settings.n_arnoldi > 0 ? int(settings.n_arnoldi) : 2 * nev + 1;
    ncv                     = std::min(n, std::max(ncv, nev + 2));
    int                 ido = 0, info = 0, ldv = n;
    char                bmat[2] = "I", which[3] = "LM";
    double              tol = settings.tolerance;
    std::vector<double> resid(n), v(std::size_t(n) * ncv), workd(3 * std::size_t(n));
    int                 lworkl = 3 * ncv * ncv + 6 * ncv;
    std::vector<double> workl(lworkl);
    std::vector<int>    iparam(11, 0), ipntr(14, 0);
    iparam[0] = 1; // exact shifts
    iparam[2] = int(settings.max_restarts);
    iparam[6] = 1; // regular mode: the operator is the matrix whose eigenvalues are wanted
    ArpackResult result;
    result.n_arnoldi = unsigned(ncv);
    while (true)
      {
        dnaupd_(&ido, bmat, &n, which, &nev, &tol, resid.data(), &ncv, v.data(), &ldv, iparam.data(),
                ipntr.data(), workd.data(), workl.data(), &lworkl, &info);
        if (ido != -1 && ido != 1)
          break;
        apply(&workd[ipntr[0] - 1], &workd[ipntr[1] - 1]);
        ++result.products;
      }
    AssertThrow(info >= 0,
                dealii::ExcMessage("ARPACK dnaupd failed with info = " + std::to_string(info) + "."));
    result.restarts          = unsigned(iparam[2]);
    int                 rvec = 0, ldz = n;
    char                howmany[2] = "A";
    std::vector<int>    select(ncv, 1);
    std::vector<double> dr(nev + 1), di(nev + 1), workev(3 * std::size_t(ncv));
    double              sigmar = 0, sigmai = 0;
    int                 einfo = 0;
    dneupd_(&rvec, howmany, select.data(), dr.data(), di.data(), v.data(), &ldz, &sigmar, &sigmai,
            workev.data(), bmat, &n, which, &nev, &tol, resid.data(), &ncv, v.data(), &ldv, iparam.data(),
            ipntr.data(), workd.data(), workl.data(), &lworkl, &einfo);
    AssertThrow(einfo == 0,
                dealii::ExcMessage("ARPACK dneupd failed with info = " + std::to_string(einfo) + "."));
    result.n_converged = unsigned(std::min(iparam[4], nev + 1));
    for (unsigned int i = 0; i < result.n_converged; ++i)
      result.eigenvalues.emplace_back(dr[i], di[i]);
    std::sort(result.eigenvalues.begin(), result.eigenvalues.end(),
              [](auto a, auto b) { return std::abs(a) > std::abs(b); });
    return result;
  }
} // namespace nlmech
