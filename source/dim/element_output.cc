#include <nlmech/dim/element_output.h>
#include <nlmech/mesh/vertex_field_output.h>

#include <Eigen/Geometry>

namespace nlmech::dim
{
  namespace
  {
    dealii::Point<3> point(const Eigen::Vector3d &x)
    {
      return dealii::Point<3>(x[0], x[1], x[2]);
    }
  } // namespace

  RawSimplexMesh<3> element_surfaces(const RigidAssembly &assembly, const Eigen::VectorXd &q,
                                     const std::vector<std::array<int, 2>> &images,
                                     std::vector<double> &element, const unsigned int sides)
  {
    RawSimplexMesh<3> mesh;
    element.clear();
    auto add_triangle = [&](unsigned a, unsigned b, unsigned c, unsigned body) {
      mesh.cells.push_back({a, b, c});
      mesh.cell_material.push_back(0);
      element.push_back(body);
    };
    for (const auto &image : images)
      for (unsigned body = 0; body < assembly.n_bodies(); ++body)
        {
          const ElementShape                &shape = assembly.shape(body);
          const std::vector<Eigen::Vector3d> x     = assembly.world_points(q, body, image);
          const auto                        &loop  = shape.loop;
          const std::size_t                  n     = loop.size();
          if (n >= 3)
            {
              // Tube: rings of `sides` points in planes normal to the centreline, parallel transported.
              const double    r      = shape.segment_radius.front();
              Eigen::Vector3d t0     = (x[loop[1]] - x[loop[n - 1]]).normalized();
              Eigen::Vector3d normal = t0.unitOrthogonal();
              const unsigned  first  = mesh.vertices.size();
              for (std::size_t i = 0; i < n; ++i)
                {
                  const Eigen::Vector3d t = (x[loop[(i + 1) % n]] - x[loop[(i + n - 1) % n]]).normalized();
                  normal                  = (normal - normal.dot(t) * t).normalized();
                  const Eigen::Vector3d binormal = t.cross(normal);
                  for (unsigned k = 0; k < sides; ++k)
                    {
                      const double phi = 2 * M_PI * k / sides;
                      mesh.vertices.push_back(
                          point(x[loop[i]] + r * (std::cos(phi) * normal + std::sin(phi) * binormal)));
                    }
                }
              for (std::size_t i = 0; i < n; ++i)
                for (unsigned k = 0; k < sides; ++k)
                  {
                    const unsigned a = first + i * sides + k, b = first + i * sides + (k + 1) % sides,
                                   c = first + ((i + 1) % n) * sides + k,
                                   d = first + ((i + 1) % n) * sides + (k + 1) % sides;
                    add_triangle(a, c, b, body), add_triangle(b, c, d, body);
                  }
            }
          // Slabs: each face offset by its radius on both sides, joined along its boundary edges.
          for (std::size_t f = 0; f < shape.triangles.size(); ++f)
            {
              const auto           &tri = shape.triangles[f];
              const Eigen::Vector3d nrm = (x[tri[1]] - x[tri[0]]).cross(x[tri[2]] - x[tri[0]]).normalized() *
                                          shape.triangle_radius[f];
              const unsigned first = mesh.vertices.size();
              for (const unsigned v : tri)
                mesh.vertices.push_back(point(x[v] + nrm));
              for (const unsigned v : tri)
                mesh.vertices.push_back(point(x[v] - nrm));
              add_triangle(first, first + 1, first + 2, body);
              add_triangle(first + 3, first + 5, first + 4, body);
              for (unsigned k = 0; k < 3; ++k)
                {
                  const unsigned a = first + k, b = first + (k + 1) % 3;
                  add_triangle(a, a + 3, b, body), add_triangle(b, a + 3, b + 3, body);
                }
            }
        }
    return mesh;
  }

  void write_elements_vtu(const RigidAssembly &assembly, const Eigen::VectorXd &q,
                          const std::vector<std::array<int, 2>> &images, const std::string &path)
  {
    std::vector<double>     element;
    const RawSimplexMesh<3> mesh = element_surfaces(assembly, q, images, element);
    write_vertex_fields_vtu(
        mesh, {}, {{"element", Eigen::Map<const Eigen::VectorXd>(element.data(), element.size())}}, path);
  }

  void write_boundary_vtu(const StrainSpaceBoundary &boundary, const std::string &path)
  {
    RawSimplexMesh<3> mesh;
    for (const auto &v : boundary.vertices)
      mesh.vertices.push_back(point(v));
    for (const auto &t : boundary.triangles)
      mesh.cells.push_back({t[0], t[1], t[2]}), mesh.cell_material.push_back(0);
    Eigen::VectorXd distance(boundary.vertices.size() * 3);
    for (std::size_t i = 0; i < boundary.vertices.size(); ++i)
      distance.segment<3>(3 * i) = boundary.vertices[i] - boundary.rest;
    write_vertex_fields_vtu(mesh, {{"from_rest", distance}}, {}, path);
  }
} // namespace nlmech::dim
