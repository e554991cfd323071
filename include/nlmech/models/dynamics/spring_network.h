#pragma once
// Point masses joined by springs, in 1, 2 or 3 dimensions: the compliant-mechanism and Duffing
// building block of the dynamics models (thesis appendix 2.A.5). A spring's stretch s is either
// axial, s = (x_b - x_a) . e - L0 along a fixed unit direction e (linear in the positions: a
// Duffing spring), or geometric, s = |x_b - x_a| - L0 (a geometrically nonlinear spring); its
// energy is k/2 s^2 + k3/4 s^4. Positions are unknowns d*v + i of vertex v.

#include <nlmech/models/energy_term.h>
#include <nlmech/models/model.h>

#include <array>
#include <cmath>
#include <vector>

namespace nlmech
{
  template <int dim>
  struct Spring
  {
    unsigned int            a = 0, b = 0;
    double                  rest_length = 0; // L0 [m]
    double                  stiffness   = 0; // k [N/m]
    double                  cubic       = 0; // k3 [N/m^3]
    bool                    axial       = false;
    std::array<double, dim> direction{}; // e, for axial springs
  };

  template <int dim>
  struct SpringElements
  {
    static constexpr std::size_t n_dofs = 2 * dim;
    std::vector<Spring<dim>>     springs;

    std::size_t                     n_elements() const { return springs.size(); }
    std::array<std::size_t, n_dofs> dofs(std::size_t e) const
    {
      std::array<std::size_t, n_dofs> d;
      for (int i = 0; i < dim; ++i)
        d[i] = dim * springs[e].a + i, d[dim + i] = dim * springs[e].b + i;
      return d;
    }
    template <typename S>
    S energy(const std::array<S, n_dofs> &x, std::size_t e) const
    {
      using std::sqrt;
      const Spring<dim> &spring = springs[e];
      S                  s      = 0;
      if (spring.axial)
        {
          for (int i = 0; i < dim; ++i)
            s += (x[dim + i] - x[i]) * spring.direction[i];
          s -= spring.rest_length;
        }
      else
        {
          S length2 = 0;
          for (int i = 0; i < dim; ++i)
            length2 += (x[dim + i] - x[i]) * (x[dim + i] - x[i]);
          s = sqrt(length2) - spring.rest_length;
        }
      const S s2 = s * s;
      return 0.5 * spring.stiffness * s2 + 0.25 * spring.cubic * s2 * s2;
    }
  };

  template <int dim>
  using SpringTerm = ElementEnergyTerm<SpringElements<dim>>;

  /// The Duffing oscillator m x'' + k x + k3 x^3: vertex 0 fixed at 0, vertex 1 (unknown 1) of mass
  /// m on an axial cubic spring (1D).
  Model make_duffing_model(double mass, double stiffness, double cubic);

  /// A mass at the origin between anchors at (-span, 0) and (span, 0), joined by geometric springs
  /// of rest length L0 (2D; the mass's unknowns are 2 and 3).
  Model make_two_spring_mass_model(double mass, double stiffness, double cubic, double span,
                                   double rest_length);

  // Instantiated once, in spring_network.cc (not again in every file that uses the terms).
  extern template class ElementEnergyTerm<SpringElements<1>>;
  extern template class ElementEnergyTerm<SpringElements<2>>;
} // namespace nlmech
