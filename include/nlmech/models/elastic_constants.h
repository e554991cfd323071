#pragma once
// The isotropic elastic constants from Young's modulus E and Poisson's ratio nu, once for every
// material of the models (solids, shells, rods, hyperelastic and linear-elastic tetrahedra).

namespace nlmech
{
  /// Lame's first parameter lambda = E nu / ((1 + nu) (1 - 2 nu)).
  inline double lame_lambda(const double E, const double nu)
  {
    return E * nu / ((1 + nu) * (1 - 2 * nu));
  }
  /// The shear modulus mu = E / (2 (1 + nu)).
  inline double shear_modulus(const double E, const double nu)
  {
    return E / (2 * (1 + nu));
  }
  /// The bulk modulus K = E / (3 (1 - 2 nu)).
  inline double bulk_modulus(const double E, const double nu)
  {
    return E / (3 * (1 - 2 * nu));
  }
} // namespace nlmech
