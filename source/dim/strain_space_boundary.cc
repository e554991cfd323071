// CGAL is kept to this translation unit (heavy templates, compile time).
#include <deal.II/base/exceptions.h>

#include <nlmech/base/atomic_output.h>
#include <nlmech/dim/strain_space_boundary.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <Eigen/Dense>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace nlmech::dim
{
  namespace
  {
    using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
    using Point  = Kernel::Point_3;
    using Mesh   = CGAL::Surface_mesh<Point>;

    Mesh to_mesh(const StrainSpaceBoundary &b)
    {
      Mesh                            mesh;
      std::vector<Mesh::Vertex_index> v;
      for (const auto &x : b.vertices)
        v.push_back(mesh.add_vertex(Point(x[0], x[1], x[2])));
      for (const auto &t : b.triangles)
        {
          AssertThrow(t[0] < v.size() && t[1] < v.size() && t[2] < v.size(),
                      dealii::ExcMessage("Strain-space boundary: a triangle refers to a missing vertex."));
          AssertThrow(
              mesh.add_face(v[t[0]], v[t[1]], v[t[2]]) != Mesh::null_face(),
              dealii::ExcMessage("Strain-space boundary: the triangles do not form a manifold surface."));
        }
      return mesh;
    }
  } // namespace

  StrainSpaceBoundary star_shaped_boundary(const std::vector<Eigen::Vector3d> &samples,
                                           const Eigen::Vector3d &rest, const Eigen::Vector3d &scale)
  {
    AssertThrow((scale.array() > 0).all(),
                dealii::ExcMessage("Strain-space boundary: the axis scales must be positive."));
    // Directions of the samples about the rest state, in scaled coordinates, without duplicates.
    std::vector<Point>           directions;
    std::vector<Eigen::Vector3d> kept;
    std::map<Point, unsigned>    index_of;
    for (const auto &s : samples)
      {
        AssertThrow(s.allFinite(), dealii::ExcMessage("Strain-space boundary: a sample is not finite."));
        const Eigen::Vector3d u = (s - rest).cwiseQuotient(scale);
        if (u.norm() < 1e-9)
          continue;
        const Eigen::Vector3d d         = u.normalized();
        bool                  duplicate = false;
        for (const auto &p : directions)
          if ((Eigen::Vector3d(p.x(), p.y(), p.z()) - d).norm() < 1e-6)
            {
              duplicate = true;
              break;
            }
        if (duplicate)
          continue;
        index_of[Point(d[0], d[1], d[2])] = kept.size();
        directions.emplace_back(d[0], d[1], d[2]);
        kept.push_back(s);
      }
    AssertThrow(
        directions.size() >= 4,
        dealii::ExcMessage("Strain-space boundary: fewer than four distinct sample directions about the rest "
                           "state; there is no closed surface to build."));
    Mesh hull;
    CGAL::convex_hull_3(directions.begin(), directions.end(), hull);
    if (!CGAL::is_triangle_mesh(hull))
      CGAL::Polygon_mesh_processing::triangulate_faces(hull);
    AssertThrow(CGAL::is_closed(hull) && hull.number_of_faces() >= 4,
                dealii::ExcMessage(
                    "Strain-space boundary: the sample directions all lie in one plane through the rest "
                    "state; sample more directions."));

    // A hull of directions that spans no volume: the samples lie in a plane through the rest state.
    AssertThrow(
        CGAL::Polygon_mesh_processing::volume(hull) > 1e-6,
        dealii::ExcMessage("Strain-space boundary: the samples span no volume about the rest state (they lie "
                           "in one plane through it); sample at least three directions."));
    StrainSpaceBoundary boundary;
    boundary.rest = rest;
    std::map<Mesh::Vertex_index, unsigned> vertex_number;
    for (const auto v : hull.vertices())
      {
        const auto found = index_of.find(hull.point(v));
        AssertThrow(found != index_of.end(), dealii::ExcInternalError());
        vertex_number[v] = boundary.vertices.size();
        boundary.vertices.push_back(kept[found->second]);
      }
    for (const auto f : hull.faces())
      {
        std::array<unsigned, 3> t{};
        unsigned                k = 0;
        for (const auto v : CGAL::vertices_around_face(hull.halfedge(f), hull))
          t[k++] = vertex_number[v];
        boundary.triangles.push_back(t);
      }
    return boundary;
  }

  BoundaryCheck check(const StrainSpaceBoundary &boundary)
  {
    BoundaryCheck result;
    result.vertices  = boundary.vertices.size();
    result.triangles = boundary.triangles.size();
    const Mesh mesh  = to_mesh(boundary);
    result.closed    = CGAL::is_closed(mesh) && mesh.number_of_faces() > 0;
    for (const auto &t : boundary.triangles)
      {
        const Eigen::Vector3d a = boundary.vertices[t[0]] - boundary.rest,
                              b = boundary.vertices[t[1]] - boundary.rest,
                              c = boundary.vertices[t[2]] - boundary.rest;
        if (a.dot(b.cross(c)) <= 0)
          ++result.flipped;
      }
    if (result.closed)
      {
        result.volume = CGAL::Polygon_mesh_processing::volume(mesh);
        CGAL::Side_of_triangle_mesh<Mesh, Kernel> inside(mesh);
        result.contains_rest =
            inside(Point(boundary.rest[0], boundary.rest[1], boundary.rest[2])) == CGAL::ON_BOUNDED_SIDE;
      }
    return result;
  }

  double signed_distance(const StrainSpaceBoundary &boundary, const Eigen::Vector3d &x)
  {
    using Primitive                                = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
    using Tree                                     = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
    const Mesh                                mesh = to_mesh(boundary);
    Tree                                      tree(faces(mesh).first, faces(mesh).second, mesh);
    const Point                               p(x[0], x[1], x[2]);
    const double                              d = std::sqrt(tree.squared_distance(p));
    CGAL::Side_of_triangle_mesh<Mesh, Kernel> inside(mesh);
    return inside(p) == CGAL::ON_BOUNDED_SIDE ? -d : d;
  }

  void write_boundary(const std::string &path, const StrainSpaceBoundary &b, const std::string &comment)
  {
    std::ostringstream out;
    out.precision(17);
    std::istringstream lines(comment);
    for (std::string line; std::getline(lines, line);)
      out << "# " << line << "\n";
    out << "nlmech-strain-space-boundary 1\n"
        << "kind " << b.kind << "\n"
        << "axes " << b.axes[0] << " " << b.axes[1] << " " << b.axes[2] << "\n"
        << "rest " << b.rest[0] << " " << b.rest[1] << " " << b.rest[2] << "\n"
        << "vertices " << b.vertices.size() << "\n";
    for (const auto &v : b.vertices)
      out << v[0] << " " << v[1] << " " << v[2] << "\n";
    out << "triangles " << b.triangles.size() << "\n";
    for (const auto &t : b.triangles)
      out << t[0] << " " << t[1] << " " << t[2] << "\n";
    write_file_atomically(path, out.str());
  }

  StrainSpaceBoundary read_boundary(const std::string &path)
  {
    std::ifstream in(path);
    AssertThrow(in, dealii::ExcMessage("Strain-space boundary: cannot open '" + path + "'."));
    auto fail = [&](const std::string &what) {
      AssertThrow(false, dealii::ExcMessage("Strain-space boundary '" + path + "': " + what));
    };
    std::string line;
    auto        next = [&]() {
      while (std::getline(in, line))
        if (!line.empty() && line[0] != '#')
          return true;
      return false;
    };
    StrainSpaceBoundary b;
    if (!next() || line.rfind("nlmech-strain-space-boundary 1", 0) != 0)
      fail("not a version-1 boundary file.");
    std::string key;
    std::size_t n = 0;
    if (!next() || !(std::istringstream(line) >> key >> b.kind) || key != "kind")
      fail("missing 'kind'.");
    if (!next() || !(std::istringstream(line) >> key >> b.axes[0] >> b.axes[1] >> b.axes[2]) || key != "axes")
      fail("missing 'axes'.");
    if (!next() || !(std::istringstream(line) >> key >> b.rest[0] >> b.rest[1] >> b.rest[2]) || key != "rest")
      fail("missing 'rest'.");
    if (!next() || !(std::istringstream(line) >> key >> n) || key != "vertices")
      fail("missing 'vertices'.");
    for (std::size_t i = 0; i < n; ++i)
      {
        Eigen::Vector3d v;
        if (!next() || !(std::istringstream(line) >> v[0] >> v[1] >> v[2]) || !v.allFinite())
          fail("vertex " + std::to_string(i) + " is malformed.");
        b.vertices.push_back(v);
      }
    if (!next() || !(std::istringstream(line) >> key >> n) || key != "triangles")
      fail("missing 'triangles'.");
    for (std::size_t i = 0; i < n; ++i)
      {
        std::array<unsigned, 3> t{};
        if (!next() || !(std::istringstream(line) >> t[0] >> t[1] >> t[2]))
          fail("triangle " + std::to_string(i) + " is malformed.");
        for (const unsigned k : t)
          if (k >= b.vertices.size())
            fail("triangle " + std::to_string(i) + " refers to a missing vertex.");
        b.triangles.push_back(t);
      }
    return b;
  }
} // namespace nlmech::dim
