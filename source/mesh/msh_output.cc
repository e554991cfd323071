#include <nlmech/mesh/msh_output.h>

#include <sstream>

namespace nlmech
{
  std::string simplex_mesh_msh(const RawSimplexMesh<3> &mesh, const Eigen::VectorXd &X)
  {
    std::ostringstream out;
    out.precision(17);
    out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n"
        << mesh.groups.boundary_ids.size() + mesh.groups.material_ids.size() << "\n";
    for (const auto &g : mesh.groups.boundary_ids)
      out << "2 " << g.second << " \"" << g.first << "\"\n";
    for (const auto &g : mesh.groups.material_ids)
      out << "3 " << g.second << " \"" << g.first << "\"\n";
    out << "$EndPhysicalNames\n$Nodes\n" << mesh.vertices.size() << "\n";
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
      out << v + 1 << " " << X[3 * v] << " " << X[3 * v + 1] << " " << X[3 * v + 2] << "\n";
    out << "$EndNodes\n$Elements\n" << mesh.boundary_faces.size() + mesh.cells.size() << "\n";
    std::size_t id = 1;
    for (std::size_t f = 0; f < mesh.boundary_faces.size(); ++f, ++id)
      out << id << " 2 2 " << mesh.boundary_face_id[f] << " " << mesh.boundary_face_id[f] << " "
          << mesh.boundary_faces[f][0] + 1 << " " << mesh.boundary_faces[f][1] + 1 << " "
          << mesh.boundary_faces[f][2] + 1 << "\n";
    for (std::size_t c = 0; c < mesh.cells.size(); ++c, ++id)
      out << id << " 4 2 " << mesh.cell_material[c] << " " << mesh.cell_material[c] << " "
          << mesh.cells[c][0] + 1 << " " << mesh.cells[c][1] + 1 << " " << mesh.cells[c][2] + 1 << " "
          << mesh.cells[c][3] + 1 << "\n";
    out << "$EndElements\n";
    return out.str();
  }
} // namespace nlmech
