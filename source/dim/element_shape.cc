#include <deal.II/base/exceptions.h>

#include <nlmech/dim/element_shape.h>
#include <nlmech/mesh/gmsh_mesh.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <numeric>

namespace nlmech::dim
{
  namespace
  {
    void add_closed_polyline(ElementShape &shape, const std::vector<Eigen::Vector3d> &points, const double r)
    {
      const unsigned int first = shape.points.size();
      for (const auto &p : points)
        {
          if (shape.loop.size() < points.size() && first == 0)
            shape.loop.push_back(shape.points.size());
          shape.points.push_back(p);
        }
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
    /// A closed tube around the curve c(t), t in [0, 2 pi), sampled at N points, with its chord
    /// sagitta (measured at the curve's midpoints) as the centreline error, centred at its centre of
    /// mass.
    template <typename Curve>
    ElementShape closed_curve_tube(const Curve &curve, const unsigned int N, const double r,
                                   const double density, std::string name)
    {
      std::vector<Eigen::Vector3d> points;
      double                       worst_chord = 0;
      for (unsigned int i = 0; i < N; ++i)
        {
          const double t0 = 2 * M_PI * i / N, t1 = 2 * M_PI * (i + 1) / N;
          points.push_back(curve(t0));
          worst_chord =
              std::max(worst_chord, (curve(0.5 * (t0 + t1)) - 0.5 * (curve(t0) + curve(t1))).norm());
        }
      // A rigid element must not intersect itself: centreline points farther apart along the
      // curve than a half turn of radius r (pi r, the tightest bend a tube of radius r allows)
      // must stay more than 2 r apart. Checked on a fourfold finer sampling of the curve.
      {
        const unsigned int           M = 4 * N;
        std::vector<Eigen::Vector3d> fine(M);
        std::vector<double>          arc(M + 1, 0.0);
        for (unsigned int i = 0; i < M; ++i)
          fine[i] = curve(2 * M_PI * i / M);
        for (unsigned int i = 0; i < M; ++i)
          arc[i + 1] = arc[i] + (fine[(i + 1) % M] - fine[i]).norm();
        double closest = std::numeric_limits<double>::infinity(), along = 0;
        for (unsigned int i = 0; i < M; ++i)
          for (unsigned int j = i + 1; j < M; ++j)
            {
              const double s = std::min(arc[j] - arc[i], arc[M] - (arc[j] - arc[i]));
              if (s <= M_PI * r)
                continue;
              const double d = (fine[i] - fine[j]).norm();
              if (d < closest)
                closest = d, along = s;
            }
        AssertThrow(closest > 2 * r,
                    dealii::ExcMessage(name + ": the tube of radius " + std::to_string(r) +
                                       " mm intersects itself (centreline points " + std::to_string(along) +
                                       " mm apart along the curve are " + std::to_string(closest) +
                                       " mm apart in space, less than 2 r); use a thinner tube or a "
                                       "larger winding."));
      }
      ElementShape shape;
      shape.name = std::move(name);
      add_closed_polyline(shape, points, r);
      shape.centreline_error = worst_chord;
      shape.mass             = density * shape.volume();
      centre_shape(shape);
      return shape;
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
      v += M_PI * segment_radius[s] * segment_radius[s] *
           (points[segments[s][1]] - points[segments[s][0]]).norm();
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
        const double vt = triangle_radius[t] * (points[b] - points[a]).cross(points[c] - points[a]).norm();
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

  ElementShape triangle_mesh_element(const std::string &file, const double skin_radius, const double density,
                                     const double mesh_size, const std::string &written)
  {
    AssertThrow(skin_radius >= 0 && mesh_size >= 0,
                dealii::ExcMessage("Mesh element: the skin radius and mesh size must not be negative."));
    MeshOptions options;
    options.file                  = file;
    options.written               = written;
    options.characteristic_length = mesh_size;
    const auto mesh               = read_simplex_mesh<3>(options, 2);
    check_simplex_mesh(mesh, 2);
    ElementShape shape;
    shape.name = "mesh element (" + std::filesystem::path(file).filename().string() + ")";
    for (const auto &v : mesh.vertices)
      shape.points.emplace_back(v[0], v[1], v[2]);
    // Closed and consistently oriented: every directed edge appears once and its reverse once.
    std::map<std::pair<unsigned, unsigned>, int> directed;
    for (const auto &c : mesh.cells)
      {
        shape.triangles.push_back({{c[0], c[1], c[2]}});
        shape.triangle_radius.push_back(skin_radius);
        for (int k = 0; k < 3; ++k)
          ++directed[{c[k], c[(k + 1) % 3]}];
      }
    bool closed = true;
    for (const auto &[edge, count] : directed)
      closed = closed && count == 1 && directed.count({edge.second, edge.first}) &&
               directed.at({edge.second, edge.first}) == 1;
    // Enclosed volume and its centroid by the divergence theorem (tetrahedra to the origin).
    double          volume = 0;
    Eigen::Vector3d moment = Eigen::Vector3d::Zero();
    for (const auto &[a, b, c] : shape.triangles)
      {
        const double v = shape.points[a].dot(shape.points[b].cross(shape.points[c])) / 6;
        volume += v;
        moment += v * (shape.points[a] + shape.points[b] + shape.points[c]) / 4;
      }
    Eigen::Vector3d centre;
    if (closed && std::abs(volume) > 0)
      {
        centre     = moment / volume;
        shape.mass = density * std::abs(volume);
      }
    else
      {
        AssertThrow(
            skin_radius > 0,
            dealii::ExcMessage("Mesh element <" + file +
                               ">: the surface is not closed (or not consistently oriented), so "
                               "it has no volume; give it a skin radius > 0 to count it as a shell."));
        centre     = shape.centroid();
        shape.mass = density * shape.volume();
      }
    for (auto &p : shape.points)
      p -= centre;
    return shape;
  }

  ElementShape torus_ring(const double R, const double r, const unsigned int N, const double density)
  {
    AssertThrow(R > 0 && r > 0 && r < R,
                dealii::ExcMessage("Torus ring: needs 0 < tube radius r < major radius R."));
    AssertThrow(N >= 8, dealii::ExcMessage("Torus ring: needs at least 8 centreline segments."));
    ElementShape shape;
    shape.name = "torus ring";
    add_closed_polyline(shape, circle(R, N), r);
    shape.centreline_error = R * (1 - std::cos(M_PI / N));
    shape.mass             = density * shape.volume();
    return shape;
  }

  ElementShape torus_knot(const unsigned int p, const unsigned int q, const double R, const double a,
                          const double r, const unsigned int N, const double density)
  {
    AssertThrow(p >= 1 && q >= 1 && std::gcd(p, q) == 1,
                dealii::ExcMessage("Torus knot: p and q must be positive and coprime."));
    AssertThrow(R > 0 && a > 0 && a < R && r > 0,
                dealii::ExcMessage("Torus knot: needs 0 < a < R and r > 0."));
    AssertThrow(N >= 8 * (p + q),
                dealii::ExcMessage("Torus knot: needs at least 8 (p + q) centreline segments."));
    auto curve = [&](const double t) {
      return Eigen::Vector3d((R + a * std::cos(q * t)) * std::cos(p * t),
                             (R + a * std::cos(q * t)) * std::sin(p * t), -a * std::sin(q * t));
    };
    return closed_curve_tube(curve, N, r, density,
                             "(" + std::to_string(p) + "," + std::to_string(q) + ") torus knot");
  }

  ElementShape wave_ring(const double R, const double r, const double h, const unsigned int k,
                         const double phase, const unsigned int N, const double density)
  {
    AssertThrow(R > 0 && r > 0 && r < R,
                dealii::ExcMessage("Wave ring: needs 0 < tube radius r < ring radius R."));
    AssertThrow(h >= 0, dealii::ExcMessage("Wave ring: the wave height must not be negative."));
    AssertThrow(N >= std::max(8u, 8 * k),
                dealii::ExcMessage("Wave ring: needs at least 8 k centreline segments."));
    auto curve = [&](const double t) {
      return Eigen::Vector3d(R * std::cos(t), R * std::sin(t), h * std::cos(k * (t - phase)));
    };
    return closed_curve_tube(curve, N, r, density,
                             h > 0 ? "wave ring (k = " + std::to_string(k) + ")" : "torus ring");
  }

  ElementShape scale_mail_element(const double R, const double r, const double h, const unsigned int N,
                                  const double plate_radius, const double plate_thickness,
                                  const double plate_height, const double density)
  {
    AssertThrow(plate_radius > 0 && plate_thickness > 0,
                dealii::ExcMessage("Scale mail: the plate needs a positive radius and thickness."));
    AssertThrow(plate_height > h + r + 0.5 * plate_thickness,
                dealii::ExcMessage("Scale mail: the plate must clear the base ring (plate height > h + r + "
                                   "thickness / 2)."));
    ElementShape shape = wave_ring(R, r, h, 6, M_PI / 12, N, density);
    shape.name         = "scale mail";
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
    shape.mass = density * shape.volume();
    centre_shape(shape);
    return shape;
  }

  int linking_number(const std::vector<Eigen::Vector3d> &a, const std::vector<Eigen::Vector3d> &b)
  {
    double total = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
      for (std::size_t j = 0; j < b.size(); ++j)
        {
          const Eigen::Vector3d &p1 = a[i], &p2 = a[(i + 1) % a.size()], &p3 = b[j],
                                &p4 = b[(j + 1) % b.size()];
          const Eigen::Vector3d r13 = p3 - p1, r14 = p4 - p1, r23 = p3 - p2, r24 = p4 - p2;
          Eigen::Vector3d       n[4]       = {r13.cross(r14), r14.cross(r24), r24.cross(r23), r23.cross(r13)};
          bool                  degenerate = false;
          for (auto &v : n)
            {
              const double l = v.norm();
              if (l < 1e-300)
                degenerate = true;
              else
                v /= l;
            }
          if (degenerate)
            continue;
          double omega = 0;
          for (int k = 0; k < 4; ++k)
            omega += std::asin(std::clamp(n[k].dot(n[(k + 1) % 4]), -1.0, 1.0));
          const double sign = ((p4 - p3).cross(p2 - p1)).dot(r13);
          total += sign > 0 ? omega : sign < 0 ? -omega : 0;
        }
    return int(std::lround(total / (4 * M_PI)));
  }
} // namespace nlmech::dim
