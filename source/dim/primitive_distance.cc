#include <nlmech/dim/primitive_distance.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <limits>

namespace nlmech::dim
{
  namespace
  {
    /// Distance type of point p (local number ip) against segment (a, b) (local numbers ia, ib).
    ClosestType point_segment(const Eigen::Vector3d &p, const Eigen::Vector3d &a, const Eigen::Vector3d &b,
                              const unsigned ip, const unsigned ia, const unsigned ib)
    {
      const Eigen::Vector3d e  = b - a;
      const double          ee = e.squaredNorm();
      const double          t  = ee > 0 ? (p - a).dot(e) / ee : 0;
      ClosestType           c;
      if (t <= 0)
        c.type = DistanceType::point_point, c.points = {{ip, ia, 0, 0}},
        c.squared_distance = (p - a).squaredNorm();
      else if (t >= 1)
        c.type = DistanceType::point_point, c.points = {{ip, ib, 0, 0}},
        c.squared_distance = (p - b).squaredNorm();
      else
        c.type = DistanceType::point_line, c.points = {{ip, ia, ib, 0}},
        c.squared_distance = (p - a).cross(e).squaredNorm() / ee;
      return c;
    }
  } // namespace

  ClosestType segment_segment_type(const Eigen::Vector3d &a0, const Eigen::Vector3d &a1,
                                   const Eigen::Vector3d &b0, const Eigen::Vector3d &b1)
  {
    const Eigen::Vector3d ea = a1 - a0, eb = b1 - b0, r = a0 - b0;
    const double a = ea.squaredNorm(), e = eb.squaredNorm(), b = ea.dot(eb), c = ea.dot(r), f = eb.dot(r);
    const double denom = a * e - b * b; // |ea x eb|^2
    if (denom > 1e-12 * a * e)
      {
        // Closest points of the infinite lines, clamped in turn (Ericson, Real-Time Collision
        // Detection 5.1.9).
        double s = std::clamp((b * f - c * e) / denom, 0.0, 1.0);
        double t = (b * s + f) / e;
        if (t < 0)
          t = 0, s = std::clamp(-c / a, 0.0, 1.0);
        else if (t > 1)
          t = 1, s = std::clamp((b - c) / a, 0.0, 1.0);
        const bool s_inside = s > 0 && s<1, t_inside = t> 0 && t < 1;
        if (s_inside && t_inside)
          {
            ClosestType ll;
            ll.type             = DistanceType::line_line;
            ll.points           = {{0, 1, 2, 3}};
            const double h      = (b0 - a0).dot(ea.cross(eb));
            ll.squared_distance = h * h / denom;
            return ll;
          }
        if (t_inside)
          return point_segment(s <= 0 ? a0 : a1, b0, b1, s <= 0 ? 0 : 1, 2, 3);
        if (s_inside)
          return point_segment(t <= 0 ? b0 : b1, a0, a1, t <= 0 ? 2 : 3, 0, 1);
        ClosestType pp;
        pp.type             = DistanceType::point_point;
        pp.points           = {{s <= 0 ? 0u : 1u, t <= 0 ? 2u : 3u, 0, 0}};
        pp.squared_distance = ((s <= 0 ? a0 : a1) - (t <= 0 ? b0 : b1)).squaredNorm();
        return pp;
      }
    // (Nearly) parallel: the nearest of the four endpoint-segment pairs.
    std::array<ClosestType, 4> candidates = {
        {point_segment(a0, b0, b1, 0, 2, 3), point_segment(a1, b0, b1, 1, 2, 3),
         point_segment(b0, a0, a1, 2, 0, 1), point_segment(b1, a0, a1, 3, 0, 1)}};
    return *std::min_element(candidates.begin(), candidates.end(), [](const auto &x, const auto &y) {
      return x.squared_distance < y.squared_distance;
    });
  }

  ClosestType point_triangle_type(const Eigen::Vector3d &p, const Eigen::Vector3d &t0,
                                  const Eigen::Vector3d &t1, const Eigen::Vector3d &t2)
  {
    // Voronoi regions of the triangle (Ericson 5.1.5).
    const Eigen::Vector3d ab = t1 - t0, ac = t2 - t0, ap = p - t0;
    const double          d1 = ab.dot(ap), d2 = ac.dot(ap);
    auto                  vertex = [&](const unsigned k, const Eigen::Vector3d &v) {
      ClosestType c;
      c.type = DistanceType::point_point, c.points = {{0, k, 0, 0}},
      c.squared_distance = (p - v).squaredNorm();
      return c;
    };
    if (d1 <= 0 && d2 <= 0)
      return vertex(1, t0);
    const Eigen::Vector3d bp = p - t1;
    const double          d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3)
      return vertex(2, t1);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0)
      return point_segment(p, t0, t1, 0, 1, 2);
    const Eigen::Vector3d cp = p - t2;
    const double          d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6)
      return vertex(3, t2);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0)
      return point_segment(p, t0, t2, 0, 1, 3);
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
      return point_segment(p, t1, t2, 0, 2, 3);
    ClosestType c;
    c.type                  = DistanceType::point_plane;
    c.points                = {{0, 1, 2, 3}};
    const Eigen::Vector3d n = ab.cross(ac);
    const double          h = ap.dot(n);
    c.squared_distance      = h * h / n.squaredNorm();
    return c;
  }

  double segment_triangle_distance(const Eigen::Vector3d &a0, const Eigen::Vector3d &a1,
                                   const Eigen::Vector3d &t0, const Eigen::Vector3d &t1,
                                   const Eigen::Vector3d &t2)
  {
    // Crossing: the segment's endpoints on opposite sides of the plane, the crossing point inside.
    const Eigen::Vector3d n  = (t1 - t0).cross(t2 - t0);
    const double          h0 = (a0 - t0).dot(n), h1 = (a1 - t0).dot(n);
    if ((h0 <= 0 && h1 >= 0) || (h0 >= 0 && h1 <= 0))
      {
        const double          w  = h0 == h1 ? 0 : h0 / (h0 - h1);
        const Eigen::Vector3d x  = a0 + w * (a1 - a0);
        const double          e0 = (t1 - t0).cross(x - t0).dot(n), e1 = (t2 - t1).cross(x - t1).dot(n),
                     e2 = (t0 - t2).cross(x - t2).dot(n);
        if ((e0 >= 0 && e1 >= 0 && e2 >= 0) || (e0 <= 0 && e1 <= 0 && e2 <= 0))
          return 0;
      }
    double d2 = std::min(point_triangle_type(a0, t0, t1, t2).squared_distance,
                         point_triangle_type(a1, t0, t1, t2).squared_distance);
    d2        = std::min({d2, segment_segment_type(a0, a1, t0, t1).squared_distance,
                          segment_segment_type(a0, a1, t1, t2).squared_distance,
                          segment_segment_type(a0, a1, t2, t0).squared_distance});
    return std::sqrt(d2);
  }
} // namespace nlmech::dim
