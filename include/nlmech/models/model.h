#pragma once
// A Model: a layout of n unknowns, a lumped mass, fixed (Dirichlet) unknowns, and a sum of energy
// terms. Solvers see only this class, never the physics behind the terms.

#include <nlmech/models/energy_term.h>
#include <nlmech/models/triplet_assembly.h>

#include <Eigen/Sparse>

#include <map>
#include <memory>
#include <vector>

namespace nlmech
{
  class Model
  {
  public:
    explicit Model(std::size_t n_unknowns);

    std::size_t                                           n_unknowns() const { return n; }
    void                                                  add_term(std::shared_ptr<const EnergyTerm> term);
    const std::vector<std::shared_ptr<const EnergyTerm>> &terms() const { return energy_terms; }

    /// Lumped (diagonal) mass per unknown [kg].
    Eigen::VectorXd       &lumped_mass() { return mass; }
    const Eigen::VectorXd &lumped_mass() const { return mass; }

    /// Holds unknown i at a value.
    void                                 fix(std::size_t i, double value);
    const std::map<std::size_t, double> &fixed() const { return fixed_values; }
    bool                                 is_fixed(std::size_t i) const { return fixed_values.count(i) > 0; }

    double                      energy(const Eigen::VectorXd &x) const;
    Eigen::VectorXd             gradient(const Eigen::VectorXd &x) const;
    Eigen::SparseMatrix<double> hessian(const Eigen::VectorXd &x, bool projected = false) const;
    /// The Hessian with each term's element blocks projected to positive semi-definite
    /// (EnergyTerm::add_projected_hessian).
    Eigen::SparseMatrix<double> projected_hessian(const Eigen::VectorXd &x) const;
    /// H(x) v, and d(H(x) v)/dx (third derivatives along v), for stiffness-proportional damping.
    Eigen::VectorXd hessian_vector_product(const Eigen::VectorXd &x, const Eigen::VectorXd &v) const;
    Eigen::SparseMatrix<double> directional_hessian(const Eigen::VectorXd &x, const Eigen::VectorXd &v) const;
    /// Coefficient k of the gradient's Taylor series along sum_{j<k} a^j path[j] (for the ANM).
    Eigen::VectorXd gradient_series_coefficient(const std::vector<Eigen::VectorXd> &path,
                                                unsigned int                        k) const;
    bool            has_series() const;
    bool            is_valid(const Eigen::VectorXd &x) const;
    double          max_safe_step(const Eigen::VectorXd &x, const Eigen::VectorXd &dx) const;
    /// The smallest of the terms' first_invalid_along_series (the ANM's step bound).
    double first_invalid_along_series(const std::vector<Eigen::VectorXd> &path, double a_max) const;

  private:
    std::size_t                                    n;
    std::vector<std::shared_ptr<const EnergyTerm>> energy_terms;
    Eigen::VectorXd                                mass;
    std::map<std::size_t, double>                  fixed_values;
    /// Hessian assemblies with their patterns kept, one per concurrent caller (shared by copies).
    std::shared_ptr<TripletAssemblyPool> hessian_assemblies = std::make_shared<TripletAssemblyPool>();
  };

  /// The unknowns that are not fixed: restriction of vectors and matrices to them and back.
  class FreeDofMap
  {
  public:
    explicit FreeDofMap(const Model &model);
    FreeDofMap(std::size_t n_unknowns, const std::map<std::size_t, double> &fixed);
    std::size_t n_free() const { return free.size(); }
    Eigen::VectorXd restrict(const Eigen::VectorXd &full) const;
    /// Free values into a full-length vector with zeros at the fixed unknowns.
    Eigen::VectorXd expand(const Eigen::VectorXd &free_values) const;
    Eigen::SparseMatrix<double> restrict(const Eigen::SparseMatrix<double> &full) const;

  private:
    std::size_t              n;
    std::vector<std::size_t> free;
    std::vector<long>        index; // position among the free unknowns, -1 if fixed
  };

  /// Largest relative differences between analytic and central finite-difference derivatives.
  struct DerivativeCheck
  {
    double gradient_error = 0; // max |g - g_fd| / max(1, |g|_inf)
    double hessian_error  = 0; // max |H - H_fd| / max(1, |H|_inf)
  };

  /// Checks an energy term's gradient against differences of its value and its Hessian against
  /// differences of its gradient, with step `h` scaled by max(1, |x|_inf).
  DerivativeCheck check_derivatives(const EnergyTerm &term, const Eigen::VectorXd &x, double h = 1e-6);
} // namespace nlmech
