#pragma once
// Distances between the centreline primitives of swept-sphere elements, in the form barrier contact
// needs (IPC, Li et al. 2020): the closest-point *type* of a segment-segment or point-triangle pair
// is found once in double precision, then the squared distance of that type is a smooth closed-form
// function of the primitives' points, templated so that forward AD differentiates it exactly:
//   point-point |p - q|^2, point-line |(p - a) x (b - a)|^2 / |b - a|^2,
//   line-line ((b0 - a0) . n)^2 / |n|^2 with n = (a1 - a0) x (b1 - b0),
//   point-plane ((p - t0) . n)^2 / |n|^2 with n = (t1 - t0) x (t2 - t0).
// Nearly parallel segments (|n|^2 below 1e-12 |ea|^2 |eb|^2) use the nearest endpoint-segment type,
// which gives the same distance.

#include <Eigen/Core>

#include <array>
#include <cmath>

namespace nlmech::dim
{
  enum class DistanceType
  {
    point_point,
    point_line,
    line_line,
    point_plane
  };

  /// A primitive pair reduced to its distance type: `points` index the four (or fewer) points of the
  /// pair in the order the type's formula takes them (p, q | p, a, b | a0, a1, b0, b1 | p, t0, t1, t2).
  struct ClosestType
  {
    DistanceType            type = DistanceType::point_point;
    std::array<unsigned, 4> points{};
    double                  squared_distance = 0;
  };

  /// Segment (a0, a1) against segment (b0, b1); local point numbers 0, 1 (a) and 2, 3 (b).
  ClosestType segment_segment_type(const Eigen::Vector3d &a0, const Eigen::Vector3d &a1,
                                   const Eigen::Vector3d &b0, const Eigen::Vector3d &b1);
  /// Point p against triangle (t0, t1, t2); local point numbers 0 (p) and 1, 2, 3 (triangle).
  ClosestType point_triangle_type(const Eigen::Vector3d &p, const Eigen::Vector3d &t0,
                                  const Eigen::Vector3d &t1, const Eigen::Vector3d &t2);
  /// Exact distance between segment (a0, a1) and triangle (t0, t1, t2), 0 where they cross.
  double segment_triangle_distance(const Eigen::Vector3d &a0, const Eigen::Vector3d &a1,
                                   const Eigen::Vector3d &t0, const Eigen::Vector3d &t1,
                                   const Eigen::Vector3d &t2);

  template <typename S>
  using Point = std::array<S, 3>;

  template <typename S>
  Point<S> difference(const Point<S> &a, const Point<S> &b)
  {
    return {{a[0] - b[0], a[1] - b[1], a[2] - b[2]}};
  }
  template <typename S>
  Point<S> cross(const Point<S> &a, const Point<S> &b)
  {
    return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
  }
  template <typename S>
  S dot(const Point<S> &a, const Point<S> &b)
  {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  }

  /// The squared distance of a given type from its points (in the order of ClosestType::points).
  template <typename S>
  S squared_distance(const DistanceType type, const std::array<Point<S>, 4> &x)
  {
    switch (type)
      {
        case DistanceType::point_point:
          {
            const Point<S> d = difference(x[0], x[1]);
            return dot(d, d);
          }
        case DistanceType::point_line:
          {
            const Point<S> e = difference(x[2], x[1]), c = cross(difference(x[0], x[1]), e);
            return dot(c, c) / dot(e, e);
          }
        case DistanceType::line_line:
          {
            const Point<S> n = cross(difference(x[1], x[0]), difference(x[3], x[2]));
            const S        h = dot(difference(x[2], x[0]), n);
            return h * h / dot(n, n);
          }
        default:
          {
            const Point<S> n = cross(difference(x[2], x[1]), difference(x[3], x[1]));
            const S        h = dot(difference(x[0], x[1]), n);
            return h * h / dot(n, n);
          }
      }
  }

  /// The IPC barrier b(d) = -kappa (d - dhat)^2 ln(d / dhat) for 0 < d < dhat, 0 beyond (C2 at dhat).
  template <typename S>
  S barrier(const S &d, const double dhat, const double kappa)
  {
    using std::log;
    if (!(d < dhat))
      return S(0);
    return -kappa * (d - dhat) * (d - dhat) * log(d / dhat);
  }
} // namespace nlmech::dim
