#include <nlmech/mesh/gmsh_mesh.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/grid/grid_tools.h>

#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <sstream>
#include <unordered_map>

namespace nlmech
{
  using dealii::ExcMessage;

  namespace
  {
    std::string list_names(const std::map<std::string, unsigned int> &groups)
    {
      if (groups.empty())
        return "(none)";
      std::string out;
      for (const auto &g : groups)
        out += (out.empty() ? "" : ", ") + g.first;
      return out;
    }

    /// Runs a block of gmsh API calls; gmsh reports its errors by throwing a std::string (parse errors,
    /// unreadable sections), which becomes one deal.II exception naming the file.
    template <typename Calls>
    void call_gmsh(const MeshOptions &options, const std::string &doing, Calls &&calls)
    {
      std::string what;
      try
        {
          calls();
          return;
        }
      catch (const dealii::ExceptionBase &)
        {
          throw; // our own checks inside the block
        }
      catch (const std::string &message)
        {
          what = message;
        }
      catch (const char *message)
        {
          what = message;
        }
      catch (const std::exception &e)
        {
          what = e.what();
        }
      catch (...)
        {
          what = "an unknown error";
        }
      std::string last;
      gmsh::logger::getLastError(last);
      if (!last.empty() && what.find(last) == std::string::npos && last.find(what) == std::string::npos)
        what += " (" + last + ")";
      AssertThrow(false,
                  ExcMessage("gmsh could not " + doing + " the mesh file " + options.name() + ": " + what));
    }

    // gmsh keeps global state; one session at a time.
    std::mutex gmsh_mutex;

    class GmshSession
    {
    public:
      explicit GmshSession(const MeshOptions &options)
      {
        std::vector<std::string> arguments = {"nlmech"};
        for (const auto &c : options.constants)
          {
            std::ostringstream value;
            value.precision(17);
            value << c.second;
            arguments.insert(arguments.end(), {"-setnumber", c.first, value.str()});
          }
        std::vector<char *> argv;
        for (auto &a : arguments)
          argv.push_back(a.data());
        gmsh::initialize(static_cast<int>(argv.size()), argv.data(), /*readConfigFiles=*/false);
        gmsh::option::setNumber("General.Terminal", 0);
        gmsh::option::setNumber("General.Verbosity", 1);
        gmsh::option::setNumber("General.NumThreads", 1);
      }
      ~GmshSession() { gmsh::finalize(); }
    };
  } // namespace

  std::string MeshOptions::name() const
  {
    if (written.empty() || written == file)
      return "<" + file + ">";
    return "<" + written + "> (" + file + ")";
  }

  unsigned int MeshGroups::boundary_id(const std::string &name) const
  {
    const auto it = boundary_ids.find(name);
    AssertThrow(it != boundary_ids.end(),
                ExcMessage("The physical group <" + name +
                           "> does not exist among the boundary groups of mesh " + source +
                           ". Boundary groups present: " + list_names(boundary_ids) + "."));
    return it->second;
  }

  unsigned int MeshGroups::material_id(const std::string &name) const
  {
    const auto it = material_ids.find(name);
    AssertThrow(it != material_ids.end(),
                ExcMessage("The physical group <" + name +
                           "> does not exist among the volume groups of mesh " + source +
                           ". Volume groups present: " + list_names(material_ids) + "."));
    return it->second;
  }

  template <int spacedim>
  void extract_simplices(const MeshOptions &options, int dim, RawSimplexMesh<spacedim> &mesh);

  namespace
  {
    /// The file checks before gmsh sees it; returns the extension.
    std::string check_mesh_file(const MeshOptions &options)
    {
      namespace fs = std::filesystem;
      AssertThrow(!options.file.empty(), ExcMessage("No mesh file was given."));
      AssertThrow(fs::is_regular_file(options.file),
                  ExcMessage("The mesh file " + options.name() + " does not exist."));
      const std::string extension = fs::path(options.file).extension().string();
      AssertThrow(
          extension == ".geo" || extension == ".msh",
          ExcMessage("The mesh file " + options.name() + " must be a gmsh .geo source or a .msh mesh."));
      return extension;
    }
  } // namespace

  void check_mesh_readable(const MeshOptions &options)
  {
    const std::string           extension = check_mesh_file(options);
    std::lock_guard<std::mutex> lock(gmsh_mutex);
    GmshSession                 session(options);
    call_gmsh(options, "read", [&] { gmsh::open(options.file); });
  }

  template <int spacedim>
  RawSimplexMesh<spacedim> read_simplex_mesh(const MeshOptions &options, const int dim)
  {
    const std::string           extension = check_mesh_file(options);
    std::lock_guard<std::mutex> lock(gmsh_mutex);
    GmshSession                 session(options);
    RawSimplexMesh<spacedim>    mesh;
    mesh.groups.source = options.name();

    // Everything that talks to gmsh in one block: gmsh throws its errors as std::string.
    call_gmsh(options, extension == ".geo" ? "read or mesh" : "read", [&] {
      if (extension == ".geo" && options.characteristic_length > 0)
        {
          gmsh::option::setNumber("Mesh.CharacteristicLengthMax", options.characteristic_length);
          gmsh::option::setNumber("Mesh.CharacteristicLengthFromPoints", 0);
        }
      gmsh::open(options.file);
      if (extension == ".geo")
        gmsh::model::mesh::generate(dim);
      extract_simplices(options, dim, mesh);
    });
    return mesh;
  }

  template <int spacedim>
  void extract_simplices(const MeshOptions &options, const int dim, RawSimplexMesh<spacedim> &mesh)
  {
    // Only linear simplices are supported.
    const int cell_type = (dim == 3 ? 4 : 2), face_type = (dim == 3 ? 2 : 1);
    {
      std::vector<int> types;
      gmsh::model::mesh::getElementTypes(types, dim);
      for (int t : types)
        if (t != cell_type)
          {
            std::string         name;
            int                 d, order, n_nodes, n_primary;
            std::vector<double> local;
            gmsh::model::mesh::getElementProperties(t, name, d, order, n_nodes, local, n_primary);
            AssertThrow(false, ExcMessage("The mesh " + options.name() + " contains elements of type <" +
                                          name + ">; nlmech needs linear " +
                                          (dim == 3 ? "tetrahedra" : "triangles") + "."));
          }
    }

    // Nodes, compacted to those used by cells.
    std::vector<std::size_t> node_tags;
    std::vector<double>      coordinates, parametric;
    gmsh::model::mesh::getNodes(node_tags, coordinates, parametric, -1, -1, false, false);
    std::unordered_map<std::size_t, std::size_t> node_position;
    for (std::size_t i = 0; i < node_tags.size(); ++i)
      node_position[node_tags[i]] = i;
    std::unordered_map<std::size_t, unsigned int> vertex_index;
    auto                                          vertex_of = [&](std::size_t tag) {
      auto it = vertex_index.find(tag);
      if (it != vertex_index.end())
        return it->second;
      const std::size_t       p = node_position.at(tag);
      dealii::Point<spacedim> x;
      for (int d = 0; d < spacedim; ++d)
        x[d] = coordinates[3 * p + d];
      if (spacedim == 2)
        AssertThrow(std::abs(coordinates[3 * p + 2]) < 1e-12 * (1 + std::abs(x[0]) + std::abs(x[1])),
                                                             ExcMessage("The 2D mesh " + options.name() + " has nodes with z != 0."));
      const unsigned int index = mesh.vertices.size();
      mesh.vertices.push_back(x);
      vertex_index.emplace(tag, index);
      return index;
    };

    // Cells, with the material id of the (first) physical group of their entity.
    gmsh::vectorpair cell_entities;
    gmsh::model::getEntities(cell_entities, dim);
    for (const auto &entity : cell_entities)
      {
        std::vector<int> physical;
        gmsh::model::getPhysicalGroupsForEntity(entity.first, entity.second, physical);
        const unsigned int material = physical.empty() ? 0u : static_cast<unsigned int>(physical.front());
        std::vector<std::size_t> element_tags, element_nodes;
        gmsh::model::mesh::getElementsByType(cell_type, element_tags, element_nodes, entity.second);
        for (std::size_t e = 0; e < element_tags.size(); ++e)
          {
            std::vector<unsigned int> cell(dim + 1);
            for (int v = 0; v <= dim; ++v)
              cell[v] = vertex_of(element_nodes[(dim + 1) * e + v]);
            mesh.cells.push_back(cell);
            mesh.cell_material.push_back(material);
          }
      }

    gmsh::vectorpair groups;
    gmsh::model::getPhysicalGroups(groups);
    for (const auto &g : groups)
      {
        std::string name;
        gmsh::model::getPhysicalName(g.first, g.second, name);
        if (name.empty())
          name = std::to_string(g.second);
        if (g.first == dim)
          mesh.groups.material_ids[name] = g.second;
        else if (g.first == dim - 1)
          mesh.groups.boundary_ids[name] = g.second;
      }

    // Boundary faces of each face group; faces that are not on the boundary are ignored.
    std::map<std::vector<unsigned int>, unsigned int> face_count;
    for (const auto &cell : mesh.cells)
      for (int skip = 0; skip <= dim; ++skip)
        {
          std::vector<unsigned int> face;
          for (int v = 0; v <= dim; ++v)
            if (v != skip)
              face.push_back(cell[v]);
          std::sort(face.begin(), face.end());
          ++face_count[face];
        }
    for (const auto &g : groups)
      if (g.first == dim - 1)
        {
          std::vector<int> entities;
          gmsh::model::getEntitiesForPhysicalGroup(g.first, g.second, entities);
          for (int entity : entities)
            {
              std::vector<std::size_t> element_tags, element_nodes;
              gmsh::model::mesh::getElementsByType(face_type, element_tags, element_nodes, entity);
              for (std::size_t e = 0; e < element_tags.size(); ++e)
                {
                  std::vector<unsigned int> face(dim);
                  bool                      known = true;
                  for (int v = 0; v < dim; ++v)
                    {
                      const auto tag = element_nodes[dim * e + v];
                      if (vertex_index.count(tag) == 0)
                        known = false;
                      else
                        face[v] = vertex_index[tag];
                    }
                  std::vector<unsigned int> key = face;
                  std::sort(key.begin(), key.end());
                  if (known && face_count[key] == 1)
                    {
                      mesh.boundary_faces.push_back(face);
                      mesh.boundary_face_id.push_back(g.second);
                    }
                }
            }
        }
  }

  template <int spacedim>
  void check_simplex_mesh(const RawSimplexMesh<spacedim> &mesh, const int dim)
  {
    const std::string &file = mesh.groups.source;
    AssertThrow(!mesh.cells.empty(),
                ExcMessage("The mesh " + file + " has no " + (dim == 3 ? "tetrahedra" : "triangles") + "."));
    for (std::size_t c = 0; c < mesh.cells.size(); ++c)
      {
        const auto                              &cell = mesh.cells[c];
        std::vector<dealii::Tensor<1, spacedim>> edges;
        double                                   longest = 0;
        for (int v = 1; v <= dim; ++v)
          {
            edges.push_back(mesh.vertices[cell[v]] - mesh.vertices[cell[0]]);
            longest = std::max(longest, edges.back().norm());
          }
        double measure = 0; // signed volume (3D), signed area (2D), area (surface in 3D)
        if (dim == 3 && spacedim == 3)
          measure = dealii::determinant(dealii::Tensor<2, 3>{{{edges[0][0], edges[1][0], edges[2][0]},
                                                              {edges[0][1], edges[1][1], edges[2][1]},
                                                              {edges[0][2], edges[1][2], edges[2][2]}}}) /
                    6.0;
        else if (dim == 2 && spacedim == 2)
          measure = 0.5 * (edges[0][0] * edges[1][1] - edges[0][1] * edges[1][0]);
        else if (dim == 2 && spacedim == 3)
          {
            dealii::Tensor<1, 3> a, b;
            for (int d = 0; d < 3; ++d)
              a[d] = edges[0][d], b[d] = edges[1][d];
            measure = 0.5 * dealii::cross_product_3d(a, b).norm();
          }
        std::ostringstream where;
        where << "element " << c << " (first vertex at " << mesh.vertices[cell[0]] << ")";
        AssertThrow(longest > 0 && std::abs(measure) > 1e-10 * std::pow(longest, dim),
                    ExcMessage("The mesh " + file + " has a degenerate " + where.str() + ": its " +
                               (dim == 3 ? "volume" : "area") + " is zero."));
        AssertThrow(measure > 0, ExcMessage("The mesh " + file + " has an inverted " + where.str() +
                                            ": its vertices are ordered with negative orientation."));
      }
  }

  template <int dim, int spacedim>
  MeshGroups load_gmsh_mesh(const MeshOptions &options, dealii::Triangulation<dim, spacedim> &tria)
  {
    const RawSimplexMesh<spacedim> raw = read_simplex_mesh<spacedim>(options, dim);
    check_simplex_mesh(raw, dim);

    std::vector<dealii::CellData<dim>> cells(raw.cells.size());
    for (std::size_t c = 0; c < cells.size(); ++c)
      {
        cells[c].vertices    = raw.cells[c];
        cells[c].material_id = raw.cell_material[c];
      }
    dealii::SubCellData faces;
    for (std::size_t f = 0; f < raw.boundary_faces.size(); ++f)
      {
        if constexpr (dim == 3)
          {
            dealii::CellData<2> face;
            face.vertices    = raw.boundary_faces[f];
            face.boundary_id = raw.boundary_face_id[f];
            faces.boundary_quads.push_back(face);
          }
        else
          {
            dealii::CellData<1> face;
            face.vertices    = raw.boundary_faces[f];
            face.boundary_id = raw.boundary_face_id[f];
            faces.boundary_lines.push_back(face);
          }
      }
    tria.clear();
    tria.create_triangulation(raw.vertices, cells, faces);
    return raw.groups;
  }

  template RawSimplexMesh<2> read_simplex_mesh<2>(const MeshOptions &, int);
  template RawSimplexMesh<3> read_simplex_mesh<3>(const MeshOptions &, int);
  template void              check_simplex_mesh<2>(const RawSimplexMesh<2> &, int);
  template void              check_simplex_mesh<3>(const RawSimplexMesh<3> &, int);
  template MeshGroups        load_gmsh_mesh<2, 2>(const MeshOptions &, dealii::Triangulation<2, 2> &);
  template MeshGroups        load_gmsh_mesh<2, 3>(const MeshOptions &, dealii::Triangulation<2, 3> &);
  template MeshGroups        load_gmsh_mesh<3, 3>(const MeshOptions &, dealii::Triangulation<3, 3> &);
} // namespace nlmech
