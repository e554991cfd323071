#include <deal.II/base/exceptions.h>

#include <nlmech/dim/element_shape.h>

#include <Eigen/Geometry>

#include <cmath>
#include <numeric>

namespace nlmech::dim
{
  namespace
  {
    void add_closed_polyline(ElementShape &shape, const std::vector<Eigen::Vector3d> &points, const double r)
    {
      const unsigned int first = shape.points.size();
      for (const auto &p : points)
        shape.points.push_back(p);
      for (unsigned int i = 0; i < points.size(); ++i)
        {
          shape.segments.push_back({{first + i, first + (i + 1) % unsigned(points.size())}});
          shape.segment_radius.push_back(r);
        }
    }
    std::vector<Eigen::Vector3d> circle(const double R, const unsigned int N, const double z = 0)
    {
      std::vector<Eigen::Vector3d> points;
      for (unsigned int i = 0; i < N; ++i)
        {
          const double t = 2 * M_PI * i / N;
          points.emplace_back(R * std::cos(t), R * std::sin(t), z);
        }
      return points;
    }
  } // namespace

  double ElementShape::bounding_radius() const
  {
    double rho = 0;
    for (std::size_t s = 0; s < segments.size(); ++s)
      for (const unsigned int i : segments[s])
        rho = std::max(rho, points[i].norm() + segment_radius[s]);
    for (std::size_t t = 0; t < triangles.size(); ++t)
      for (const unsigned int i : triangles[t])
        rho = std::max(rho, points[i].norm() + triangle_radius[t]);
    return rho;
  }

  double ElementShape::volume() const
  {
    double v = 0;
    for (std::size_t s = 0; s < segments.size(); ++s)
      v += M_PI * segment_radius[s] * segment_radius[s] * (points[segments[s][1]] - points[segments[s][0]]).norm();
    for (std::size_t t = 0; t < triangles.size(); ++t)
      {
        const auto &[a, b, c] = triangles[t];
        v += 2 * triangle_radius[t] * 0.5 * (points[b] - points[a]).cross(points[c] - points[a]).norm();
      }
    return v;
  }

  Eigen::Vector3d ElementShape::centroid() const
  {
    Eigen::Vector3d m = Eigen::Vector3d::Zero();
    double          v = 0;
    for (std::size_t s = 0; s < segments.size(); ++s)
      {
        const double vs = M_PI * segment_radius[s] * segment_radius[s] *
                          (points[segments[s][1]] - points[segments[s][0]]).norm();
        m += vs * 0.5 * (points[segments[s][0]] + points[segments[s][1]]);
        v += vs;
      }
    for (std::size_t t = 0; t < triangles.size(); ++t)
      {
        const auto &[a, b, c] = triangles[t];
        const double vt       = triangle_radius[t] * (points[b] - points[a]).cross(points[c] - points[a]).norm();
        m += vt * (points[a] + points[b] + points[c]) / 3;
        v += vt;
      }
    return v > 0 ? Eigen::Vector3d(m / v) : m;
  }

  Eigen::Vector3d centre_shape(ElementShape &shape)
  {
    const Eigen::Vector3d c = shape.centroid();
    for (auto &p : shape.points)
      p -= c;
    return c;
  }

  ElementShape torus_ring(const double R, const double r, const unsigned int N, const double density)
  {
    AssertThrow(R > 0 && r > 0 && r < R, dealii::ExcMessage("Torus ring: needs 0 < tube radius r < major radius R."));
    AssertThrow(N >= 8, dealii::ExcMessage("Torus ring: needs at least 8 centreline segments."));
    ElementShape shape;
    shape.name = "torus ring";
    add_closed_polyline(shape, circle(R, N), r);
    shape.centreline_error = R * (1 - std::cos(M_PI / N));
    shape.mass             = density * shape.volume();
    return shape;
  }

  ElementShape torus_knot(const unsigned int p, const unsigned int q, const double R, const double a, const double r,
                          const unsigned int N, const double density)
  {
    AssertThrow(p >= 1 && q >= 1 && std::gcd(p, q) == 1,
                dealii::ExcMessage("Torus knot: p and q must be positive and coprime."));
    AssertThrow(R > 0 && a > 0 && a < R && r > 0, dealii::ExcMessage("Torus knot: needs 0 < a < R and r > 0."));
    AssertThrow(N >= 8 * (p + q), dealii::ExcMessage("Torus knot: needs at least 8 (p + q) centreline segments."));
    std::vector<Eigen::Vector3d> points;
    double                       worst_chord = 0;
    auto curve = [&](const double t) {
      return Eigen::Vector3d((R + a * std::cos(q * t)) * std::cos(p * t), (R + a * std::cos(q * t)) * std::sin(p * t),
                             -a * std::sin(q * t));
    };
    for (unsigned int i = 0; i < N; ++i)
      {
        const double t0 = 2 * M_PI * i / N, t1 = 2 * M_PI * (i + 1) / N;
        points.push_back(curve(t0));
        // Sagitta of the chord, measured at the curve's midpoint.
        const Eigen::Vector3d mid = curve(0.5 * (t0 + t1)), chord_mid = 0.5 * (curve(t0) + curve(t1));
        worst_chord               = std::max(worst_chord, (mid - chord_mid).norm());
      }
    ElementShape shape;
    shape.name = "(" + std::to_string(p) + "," + std::to_string(q) + ") torus knot";
    add_closed_polyline(shape, points, r);
    shape.centreline_error = worst_chord;
    shape.mass             = density * shape.volume();
    centre_shape(shape);
    return shape;
  }

  ElementShape scale_mail_element(const double R, const double r, const unsigned int N, const double plate_radius,
                                  const double plate_thickness, const double plate_height, const double density)
  {
    AssertThrow(R > 0 && r > 0 && r < R, dealii::ExcMessage("Scale mail: needs 0 < tube radius r < ring radius R."));
    AssertThrow(plate_radius > 0 && plate_thickness > 0,
                dealii::ExcMessage("Scale mail: the plate needs a positive radius and thickness."));
    AssertThrow(plate_height > r + 0.5 * plate_thickness,
                dealii::ExcMessage("Scale mail: the plate must sit above the ring (plate height > r + thickness/2)."));
    ElementShape shape;
    shape.name = "scale mail";
    add_closed_polyline(shape, circle(R, N), r);
    // Hexagonal plate: a fan of six triangles around its centre, swept by half the thickness.
    const unsigned int centre = shape.points.size();
    shape.points.emplace_back(0, 0, plate_height);
    for (unsigned int k = 0; k < 6; ++k)
      {
        const double t = M_PI / 3 * k + M_PI / 6;
        shape.points.emplace_back(plate_radius * std::cos(t), plate_radius * std::sin(t), plate_height);
      }
    for (unsigned int k = 0; k < 6; ++k)
      {
        shape.triangles.push_back({{centre, centre + 1 + k, centre + 1 + (k + 1) % 6}});
        shape.triangle_radius.push_back(0.5 * plate_thickness);
      }
    // Three struts from the ring up to the plate's underside.
    for (unsigned int k = 0; k < 3; ++k)
      {
        const unsigned int ring_point = (k * N) / 3;
        const unsigned int top        = shape.points.size();
        const double       t          = 2 * M_PI * ring_point / N;
        shape.points.emplace_back(0.5 * R * std::cos(t), 0.5 * R * std::sin(t), plate_height);
        shape.segments.push_back({{ring_point, top}});
        shape.segment_radius.push_back(r);
      }
    shape.centreline_error = R * (1 - std::cos(M_PI / N));
    shape.mass             = density * shape.volume();
    centre_shape(shape);
    return shape;
  }
} // namespace nlmech::dim
