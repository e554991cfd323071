#pragma once
// Discrete elastic rods (Bergou et al. 2008) and rod networks with rigid junctions (after Zehnder
// et al. 2016), for dynamics (thesis Fig. 2.11, appendix 2.A.5).
//
// Unknowns: 3 positions per vertex, then one material-frame angle theta_e per edge, then a
// rotation (Gibbs/Cayley vector q, R = I + 2 ([q]x + [q]x^2) / (1 + q.q), smooth at q = 0) per
// junction. Reference frames are transported in space from the rest state: the reference
// director of edge e is u_e = P(t_e_rest -> t_e) u_e_rest (parallel transport along the rotation
// that takes the rest tangent to the current one), so every state has its frame without a time
// history, as harmonic balance needs; the material frame is u, v = t x u turned by theta_e.
//   Stretching: k_s / 2 (|e| / |e_rest| - 1)^2 |e_rest|, k_s = E A.
//   Bending at a vertex between edges e, f: kb = 2 t_e x t_f / (1 + t_e . t_f), material
//     curvatures w_j = (kb . m2_j, -kb . m1_j) for j = e, f;
//     W = 1 / l * sum_j 1/2 (w_j - w_j_rest)^T B (w_j - w_j_rest), l = |e_rest| + |f_rest|, B = E I.
//   Twist: W = G J (m - m_rest)^2 / l, m = theta_f - theta_e + reference twist (the angle from the
//     transported u_e to u_f about t_f).
// A junction is a rigid body at a vertex where rod ends meet: each rod end couples to an arm of the
// junction (direction and frame fixed in the junction's rotating frame) by the same bending and
// twist energies, with the arm in place of the neighbouring edge and the edge's length as l (two
// arms in series across a junction are then exactly as stiff as one interior vertex).

#include <nlmech/models/energy_term.h>
#include <nlmech/models/model.h>

#include <array>
#include <cmath>
#include <vector>

namespace nlmech
{
  struct RodMaterial
  {
    double radius         = 0.55e-3; // m
    double youngs_modulus = 69e9;    // Pa
    double poissons_ratio = 0.33;    // -
    double density        = 2700;    // kg/m^3
  };

  namespace rod_geometry
  {
    template <typename S>
    using Vec = std::array<S, 3>;

    template <typename S>
    S dot(const Vec<S> &a, const Vec<S> &b)
    {
      return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    }
    template <typename S>
    Vec<S> cross(const Vec<S> &a, const Vec<S> &b)
    {
      return Vec<S>{{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
    }
    /// A constant vector in the scalar type S.
    template <typename S>
    Vec<S> lift(const Vec<double> &a)
    {
      return Vec<S>{{S(a[0]), S(a[1]), S(a[2])}};
    }
    /// Parallel transport of v along the rotation taking unit a to unit b.
    template <typename S>
    Vec<S> transport(const Vec<S> &a, const Vec<S> &b, const Vec<S> &v)
    {
      const Vec<S> c   = cross(a, b);
      const S      cab = dot(a, b);
      const Vec<S> cv  = cross(c, v);
      const S      s   = dot(c, v) / (1.0 + cab);
      return Vec<S>{
          {v[0] * cab + cv[0] + c[0] * s, v[1] * cab + cv[1] + c[1] * s, v[2] * cab + cv[2] + c[2] * s}};
    }
    /// Signed angle from unit a to unit b about unit axis n (both normal to n), by the half-angle
    /// formula (smooth away from pi).
    template <typename S>
    S signed_angle(const Vec<S> &a, const Vec<S> &b, const Vec<S> &n)
    {
      using std::atan;
      const S sine = dot(cross(a, b), n), cosine = dot(a, b);
      using std::sqrt;
      const S norm = sqrt(sine * sine + cosine * cosine);
      return 2.0 * atan(sine / (norm + cosine));
    }
    /// Unit vector and length.
    template <typename S>
    Vec<S> unit(const Vec<S> &a, S &length)
    {
      using std::sqrt;
      length = sqrt(dot(a, a));
      return Vec<S>{{a[0] / length, a[1] / length, a[2] / length}};
    }
    /// Material frame (m1, m2) of an edge with unit tangent t, reference director u, angle theta.
    template <typename S>
    void material_frame(const Vec<S> &t, const Vec<S> &u, const S &theta, Vec<S> &m1, Vec<S> &m2)
    {
      using std::cos;
      using std::sin;
      const Vec<S> v = cross(t, u);
      const S      c = cos(theta), s = sin(theta);
      for (int i = 0; i < 3; ++i)
        m1[i] = c * u[i] + s * v[i], m2[i] = -s * u[i] + c * v[i];
    }
    /// Rotation by the Gibbs vector q applied to v.
    template <typename S>
    Vec<S> rotate(const Vec<S> &q, const Vec<double> &v_in)
    {
      const Vec<S> v   = lift<S>(v_in);
      const Vec<S> qv  = cross(q, v);
      const Vec<S> qqv = cross(q, qv);
      const S      f   = 2.0 / (1.0 + dot(q, q));
      return Vec<S>{{v[0] + f * (qv[0] + qqv[0]), v[1] + f * (qv[1] + qqv[1]), v[2] + f * (qv[2] + qqv[2])}};
    }
  } // namespace rod_geometry

  struct RodStretchElements
  {
    static constexpr std::size_t             n_dofs = 6;
    std::vector<std::array<unsigned int, 2>> edges;
    std::vector<double>                      rest_length;
    double                                   stiffness = 0; // E A

    std::size_t                n_elements() const { return edges.size(); }
    std::array<std::size_t, 6> dofs(std::size_t e) const
    {
      return {{3 * edges[e][0], 3 * edges[e][0] + 1, 3 * edges[e][0] + 2, 3 * edges[e][1],
               3 * edges[e][1] + 1, 3 * edges[e][1] + 2}};
    }
    template <typename S>
    S energy(const std::array<S, 6> &x, std::size_t e) const
    {
      using std::sqrt;
      const S dx = x[3] - x[0], dy = x[4] - x[1], dz = x[5] - x[2];
      const S s = sqrt(dx * dx + dy * dy + dz * dz) / rest_length[e] - 1.0;
      return 0.5 * stiffness * s * s * rest_length[e];
    }
  };

  /// Bending and twist between two frames: edge "a" and edge "b" meeting at a vertex. Shared by
  /// interior rod vertices and junction arms.
  struct RodHingeRest
  {
    std::array<double, 4> curvature{}; // w_a (2), w_b (2) at rest
    double                twist  = 0;  // m at rest
    double                length = 0;  // l = |e_a| + |e_b| at rest
  };

  template <typename S>
  S rod_hinge_energy(const rod_geometry::Vec<S> &ta, const rod_geometry::Vec<S> &m1a,
                     const rod_geometry::Vec<S> &m2a, const rod_geometry::Vec<S> &ua, const S &theta_a,
                     const rod_geometry::Vec<S> &tb, const rod_geometry::Vec<S> &m1b,
                     const rod_geometry::Vec<S> &m2b, const rod_geometry::Vec<S> &ub, const S &theta_b,
                     const RodHingeRest &rest, double bending, double twisting, bool with_rest,
                     std::array<S, 5> *measures = nullptr)
  {
    using namespace rod_geometry;
    const Vec<S> c    = cross(ta, tb);
    const S      d    = 1.0 + dot(ta, tb);
    const Vec<S> kb   = {{2.0 * c[0] / d, 2.0 * c[1] / d, 2.0 * c[2] / d}};
    const S      w[4] = {dot(kb, m2a), -dot(kb, m1a), dot(kb, m2b), -dot(kb, m1b)};
    // reference twist: u_a transported to t_b against u_b, about t_b
    const Vec<S> ua_b = transport(ta, tb, ua);
    const S      m    = theta_b - theta_a + signed_angle(ua_b, ub, tb);
    if (measures)
      *measures = {{w[0], w[1], w[2], w[3], m}};
    S bend = 0.0;
    for (int i = 0; i < 4; ++i)
      {
        const S delta = w[i] - (with_rest ? rest.curvature[i] : 0.0);
        bend += 0.5 * bending * delta * delta;
      }
    const S dm = m - (with_rest ? rest.twist : 0.0);
    return bend / rest.length + twisting * dm * dm / rest.length;
  }

  struct RodBendTwistElements
  {
    static constexpr std::size_t             n_dofs = 11; // x_prev, x, x_next, theta_a, theta_b
    std::vector<std::array<unsigned int, 3>> vertices;
    std::vector<std::array<unsigned int, 2>> edges; // edge indices a, b
    std::vector<std::array<double, 3>>       rest_tangent_a, rest_tangent_b, rest_director_a, rest_director_b;
    std::vector<RodHingeRest>                rest;
    std::size_t                              theta_offset = 0; // unknown of theta of edge 0
    double                                   bending = 0, twisting = 0;

    std::size_t                 n_elements() const { return vertices.size(); }
    std::array<std::size_t, 11> dofs(std::size_t e) const
    {
      std::array<std::size_t, 11> d;
      for (int v = 0; v < 3; ++v)
        for (int i = 0; i < 3; ++i)
          d[3 * v + i] = 3 * vertices[e][v] + i;
      d[9] = theta_offset + edges[e][0], d[10] = theta_offset + edges[e][1];
      return d;
    }
    template <typename S>
    S evaluate(const std::array<S, 11> &x, std::size_t e, bool with_rest, std::array<S, 5> *measures) const
    {
      using namespace rod_geometry;
      S            la, lb;
      const Vec<S> ta = unit(Vec<S>{{x[3] - x[0], x[4] - x[1], x[5] - x[2]}}, la);
      const Vec<S> tb = unit(Vec<S>{{x[6] - x[3], x[7] - x[4], x[8] - x[5]}}, lb);
      const Vec<S> ua = transport(lift<S>(rest_tangent_a[e]), ta, lift<S>(rest_director_a[e]));
      const Vec<S> ub = transport(lift<S>(rest_tangent_b[e]), tb, lift<S>(rest_director_b[e]));
      Vec<S>       m1a, m2a, m1b, m2b;
      material_frame(ta, ua, x[9], m1a, m2a);
      material_frame(tb, ub, x[10], m1b, m2b);
      return rod_hinge_energy(ta, m1a, m2a, ua, x[9], tb, m1b, m2b, ub, x[10], rest[e], bending, twisting,
                              with_rest, measures);
    }
    template <typename S>
    S energy(const std::array<S, 11> &x, std::size_t e) const
    {
      return evaluate<S>(x, e, true, nullptr);
    }
  };

  /// A rod end at a junction: the junction's arm (rest direction and director turned by the
  /// junction's rotation) against the rod's first edge. Orientation: the arm points into the
  /// junction, the edge away from it, so the pair reads like two consecutive edges.
  struct RodJunctionElements
  {
    static constexpr std::size_t             n_dofs = 10; // x_junction, q_junction, x_neighbour, theta
    std::vector<std::array<unsigned int, 2>> vertices;    // junction vertex, neighbour vertex
    std::vector<unsigned int>                junction, edge;
    std::vector<std::array<double, 3>>       rest_tangent, rest_director; // of the edge = of the arm at rest
    std::vector<RodHingeRest>                rest;
    std::size_t                              theta_offset = 0, rotation_offset = 0;
    double                                   bending = 0, twisting = 0;

    std::size_t                 n_elements() const { return vertices.size(); }
    std::array<std::size_t, 10> dofs(std::size_t e) const
    {
      std::array<std::size_t, 10> d;
      for (int i = 0; i < 3; ++i)
        d[i] = 3 * vertices[e][0] + i, d[3 + i] = rotation_offset + 3 * junction[e] + i,
        d[6 + i] = 3 * vertices[e][1] + i;
      d[9] = theta_offset + edge[e];
      return d;
    }
    template <typename S>
    S evaluate(const std::array<S, 10> &x, std::size_t e, bool with_rest, std::array<S, 5> *measures) const
    {
      using namespace rod_geometry;
      const Vec<S> q  = {{x[3], x[4], x[5]}};
      const Vec<S> ta = rotate(q, rest_tangent[e]); // the arm, fixed in the junction
      const Vec<S> ua = rotate(q, rest_director[e]);
      S            lb;
      const Vec<S> tb = unit(Vec<S>{{x[6] - x[0], x[7] - x[1], x[8] - x[2]}}, lb);
      const Vec<S> ub = transport(lift<S>(rest_tangent[e]), tb, lift<S>(rest_director[e]));
      Vec<S>       m1a, m2a, m1b, m2b;
      const S      zero = 0.0;
      material_frame(ta, ua, zero, m1a, m2a);
      material_frame(tb, ub, x[9], m1b, m2b);
      return rod_hinge_energy(ta, m1a, m2a, ua, zero, tb, m1b, m2b, ub, x[9], rest[e], bending, twisting,
                              with_rest, measures);
    }
    template <typename S>
    S energy(const std::array<S, 10> &x, std::size_t e) const
    {
      return evaluate<S>(x, e, true, nullptr);
    }
  };

  struct RodNetworkDescription
  {
    std::vector<std::array<double, 3>>     vertices;
    std::vector<std::vector<unsigned int>> rods; // vertex sequences; first == last: a closed loop
    RodMaterial                            material;
  };

  struct RodNetwork
  {
    Model                                    model{0};
    Eigen::VectorXd                          rest_positions;
    std::vector<std::array<unsigned int, 2>> edges;
    std::vector<unsigned int>                junction_vertices;
    std::size_t                              theta_offset = 0, rotation_offset = 0;
  };

  /// The rod network's Model with lumped masses (rho A per length at vertices, rho J per length on
  /// the edge angles, the junction's share of rotational inertia on its rotation). Throws for
  /// zero-length edges, rods of fewer than one edge, or vertices out of range.
  RodNetwork make_rod_network(const RodNetworkDescription &description);

  /// Rods from polylines: each polyline (points, closed if first == last) is resampled to
  /// `segments` equal-length edges; rod ends closer than `tolerance` share a vertex (a junction).
  RodNetworkDescription rods_from_polylines(const std::vector<std::vector<std::array<double, 3>>> &polylines,
                                            unsigned int segments, double tolerance);

  // Instantiated once, in rod_network.cc (not again in every file that uses the terms).
  extern template class ElementEnergyTerm<RodStretchElements>;
  extern template class ElementEnergyTerm<RodBendTwistElements>;
  extern template class ElementEnergyTerm<RodJunctionElements>;
} // namespace nlmech
