#include <deal.II/base/exceptions.h>

#include <nlmech/models/scaled_energy.h>

namespace nlmech
{
  ScaledEnergyTerm::ScaledEnergyTerm(std::shared_ptr<const EnergyTerm> inner_in,
                                     std::shared_ptr<double>           factor_in)
      : inner(std::move(inner_in))
      , factor(std::move(factor_in))
  {
    AssertThrow(inner && factor, dealii::ExcMessage("ScaledEnergyTerm needs a term and a factor."));
  }

  namespace
  {
    void scale_from(Triplets &h, const std::size_t first, const double s)
    {
      for (std::size_t i = first; i < h.size(); ++i)
        h[i] = Eigen::Triplet<double>(h[i].row(), h[i].col(), s * h[i].value());
    }
  } // namespace

  double ScaledEnergyTerm::value(const Eigen::VectorXd &x) const
  {
    return *factor * inner->value(x);
  }

  void ScaledEnergyTerm::add_gradient(const Eigen::VectorXd &x, Eigen::VectorXd &g) const
  {
    Eigen::VectorXd own = Eigen::VectorXd::Zero(g.size());
    inner->add_gradient(x, own);
    g += *factor * own;
  }

  void ScaledEnergyTerm::add_hessian(const Eigen::VectorXd &x, Triplets &h) const
  {
    const std::size_t first = h.size();
    inner->add_hessian(x, h);
    scale_from(h, first, *factor);
  }

  void ScaledEnergyTerm::add_projected_hessian(const Eigen::VectorXd &x, Triplets &h) const
  {
    const std::size_t first = h.size();
    inner->add_projected_hessian(x, h);
    scale_from(h, first, std::max(*factor, 0.0));
  }

  void ScaledEnergyTerm::add_hessian_vector_product(const Eigen::VectorXd &x, const Eigen::VectorXd &v,
                                                    Eigen::VectorXd &out) const
  {
    Eigen::VectorXd own = Eigen::VectorXd::Zero(out.size());
    inner->add_hessian_vector_product(x, v, own);
    out += *factor * own;
  }

  void ScaledEnergyTerm::add_directional_hessian(const Eigen::VectorXd &x, const Eigen::VectorXd &v,
                                                 Triplets &h) const
  {
    const std::size_t first = h.size();
    inner->add_directional_hessian(x, v, h);
    scale_from(h, first, *factor);
  }
} // namespace nlmech
