#pragma once
// Manufactured displacement fields for linear elasticity and the body force that produces them:
// f = -div sigma(u) = -(lambda + mu) grad(div u) - mu laplace(u).

#include <deal.II/base/function.h>
#include <deal.II/base/symmetric_tensor.h>

namespace nlmech
{
  template <int dim>
  class ManufacturedDisplacement : public dealii::Function<dim>
  {
  public:
    /// affine: u = a + B x (reproduced exactly by any conforming element: the patch test);
    /// trigonometric: u_d = A_d prod_k sin(pi x_k + c_dk).
    explicit ManufacturedDisplacement(bool affine);

    double                 value(const dealii::Point<dim> &p, unsigned int component) const override;
    dealii::Tensor<1, dim> gradient(const dealii::Point<dim> &p, unsigned int component) const override;
    dealii::SymmetricTensor<2, dim> hessian(const dealii::Point<dim> &p,
                                            unsigned int              component) const override;

  private:
    bool affine;
  };

  template <int dim>
  class ManufacturedBodyForce : public dealii::Function<dim>
  {
  public:
    ManufacturedBodyForce(const ManufacturedDisplacement<dim> &u, double lambda, double mu);
    double value(const dealii::Point<dim> &p, unsigned int component) const override;

  private:
    const ManufacturedDisplacement<dim> &u;
    double                               lambda, mu;
  };
} // namespace nlmech
