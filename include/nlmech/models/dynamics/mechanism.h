#pragma once
// Planar compliant mechanisms (thesis appendix 2.A.5): joints are point masses (2 unknowns each),
// rigid links keep their length and rigid joints their angle by stiff penalties, and compliant
// elements are linear springs whose end points are given in the local frame of a link, so they
// follow the link as it turns. Gravity acts on the joint masses.
//
// Link a->b frame: origin x_a, axes e = x_b - x_a and n = (-e_y, e_x) (not normalised: local
// coordinates (u, w) scale with the link, which is rigid); the attachment is p = x_a + u e + w n.
// Rigid link: k_l / 2 (|x_b - x_a| - L)^2. Rigid joint at b between links (a, b) and (b, c):
// k_t / 2 (phi - phi_0)^2 with phi the signed angle from x_a - x_b to x_c - x_b.
// Spring: k / 2 (|p - q| - L0)^2.

#include <nlmech/models/energy_term.h>
#include <nlmech/models/model.h>

#include <array>
#include <cmath>
#include <vector>

namespace nlmech
{
  struct MechanismSpring
  {
    unsigned int link_a = 0, link_b = 0; // links the two ends are attached to
    double       u_a = 0, w_a = 0, u_b = 0, w_b = 0;
    double       stiffness   = 0; // [N/m]
    double       rest_length = 0; // [m]; negative: the initial distance
  };

  struct MechanismDescription
  {
    std::vector<std::array<double, 2>>       joints;       // [m]
    std::vector<double>                      masses;       // per joint [kg]
    std::vector<std::array<unsigned int, 2>> links;        // joint pairs, rigid
    std::vector<std::array<unsigned int, 3>> rigid_angles; // (a, b, c): angle at b kept
    std::vector<MechanismSpring>             springs;
    double                                   link_stiffness  = 1e5;  // k_l [N/m]
    double                                   angle_stiffness = 1e3;  // k_t [N m/rad^2]
    double                                   gravity         = 9.81; // along -y [m/s^2]
  };

  struct AttachedSpringElements
  {
    static constexpr std::size_t             n_dofs = 8;
    std::vector<std::array<unsigned int, 4>> ends;  // link a (j0, j1), link b (j2, j3)
    std::vector<std::array<double, 4>>       local; // u_a, w_a, u_b, w_b
    std::vector<double>                      stiffness, rest_length;

    std::size_t                n_elements() const { return ends.size(); }
    std::array<std::size_t, 8> dofs(std::size_t e) const
    {
      std::array<std::size_t, 8> d;
      for (int v = 0; v < 4; ++v)
        for (int i = 0; i < 2; ++i)
          d[2 * v + i] = 2 * ends[e][v] + i;
      return d;
    }
    /// Attachment point of end `side` (0, 1).
    template <typename S>
    static void attachment(const std::array<S, 8> &x, int side, double u, double w, S (&p)[2])
    {
      const int o  = 4 * side;
      const S   ex = x[o + 2] - x[o], ey = x[o + 3] - x[o + 1];
      p[0] = x[o] + u * ex - w * ey;
      p[1] = x[o + 1] + u * ey + w * ex;
    }
    /// The energy with the spring's data (u_a, w_a, u_b, w_b, L0, k) of any scalar type: design
    /// parameters differentiate it in them by nested forward AD.
    template <typename S, typename P>
    static S energy_of(const std::array<S, 8> &x, const std::array<P, 6> &data)
    {
      using std::sqrt;
      const S ax = x[2] - x[0], ay = x[3] - x[1], bx = x[6] - x[4], by = x[7] - x[5];
      const S dx = x[4] + data[2] * bx - data[3] * by - (x[0] + data[0] * ax - data[1] * ay);
      const S dy = x[5] + data[2] * by + data[3] * bx - (x[1] + data[0] * ay + data[1] * ax);
      const S s  = sqrt(dx * dx + dy * dy) - data[4];
      return 0.5 * data[5] * s * s;
    }
    template <typename S>
    S energy(const std::array<S, 8> &x, std::size_t e) const
    {
      return energy_of(x, data(e));
    }
    std::array<double, 6> data(std::size_t e) const
    {
      return {{local[e][0], local[e][1], local[e][2], local[e][3], rest_length[e], stiffness[e]}};
    }
  };

  struct JointAngleElements
  {
    static constexpr std::size_t             n_dofs = 6;
    std::vector<std::array<unsigned int, 3>> joints;
    std::vector<double>                      rest_angle;
    double                                   stiffness = 0;

    std::size_t                n_elements() const { return joints.size(); }
    std::array<std::size_t, 6> dofs(std::size_t e) const
    {
      std::array<std::size_t, 6> d;
      for (int v = 0; v < 3; ++v)
        for (int i = 0; i < 2; ++i)
          d[2 * v + i] = 2 * joints[e][v] + i;
      return d;
    }
    template <typename S>
    static S angle(const std::array<S, 6> &x)
    {
      using std::atan;
      using std::sqrt;
      const S ax = x[0] - x[2], ay = x[1] - x[3], cx = x[4] - x[2], cy = x[5] - x[3];
      const S cross = ax * cy - ay * cx, dot = ax * cx + ay * cy;
      const S norms = sqrt((ax * ax + ay * ay) * (cx * cx + cy * cy));
      return 2.0 * atan(cross / (norms + dot)); // atan2(cross, dot), smooth away from -pi
    }
    template <typename S>
    S energy(const std::array<S, 6> &x, std::size_t e) const
    {
      const S d = angle(x) - rest_angle[e];
      return 0.5 * stiffness * d * d;
    }
  };

  struct MechanismModel
  {
    Model           model{0};
    Eigen::VectorXd rest_positions;
  };

  /// The Model of a mechanism; throws clear errors for links of zero length, indices out of range or
  /// non-positive masses.
  MechanismModel make_mechanism_model(const MechanismDescription &description);

  /// Largest relative change of a link's length and largest change of a rigid angle [rad] at x
  /// (the constraint violations of thesis Fig. 2.14).
  std::array<double, 2> mechanism_constraint_violation(const MechanismDescription &description,
                                                       const Eigen::VectorXd      &x);

  // Instantiated once, in mechanism.cc (not again in every file that uses the terms).
  extern template class ElementEnergyTerm<JointAngleElements>;
  extern template class ElementEnergyTerm<AttachedSpringElements>;
} // namespace nlmech
