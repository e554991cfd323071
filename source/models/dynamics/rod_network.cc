#include <deal.II/base/exceptions.h>

#include <nlmech/models/dynamics/rod_network.h>
#include <nlmech/models/elastic_constants.h>

#include <algorithm>
#include <map>

namespace nlmech
{
  namespace
  {
    using V3 = std::array<double, 3>;
    V3 sub(const V3 &a, const V3 &b)
    {
      return {{a[0] - b[0], a[1] - b[1], a[2] - b[2]}};
    }
    double norm(const V3 &a)
    {
      return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    }
    /// A unit director normal to the unit tangent t (from the coordinate axis least along t).
    V3 director(const V3 &t)
    {
      int axis = 0;
      for (int i = 1; i < 3; ++i)
        if (std::abs(t[i]) < std::abs(t[axis]))
          axis = i;
      V3 a{{0, 0, 0}};
      a[axis]        = 1;
      const V3     u = rod_geometry::cross(t, a);
      const double n = norm(u);
      return {{u[0] / n, u[1] / n, u[2] / n}};
    }
  } // namespace

  RodNetwork make_rod_network(const RodNetworkDescription &d)
  {
    const RodMaterial &mat = d.material;
    AssertThrow(
        mat.radius > 0 && mat.youngs_modulus > 0 && mat.density > 0 && mat.poissons_ratio > -1 &&
            mat.poissons_ratio < 0.5,
        dealii::ExcMessage("A rod needs a positive radius, Young's modulus and density and a Poisson's "
                           "ratio in (-1, 0.5)."));
    const std::size_t nv = d.vertices.size();
    const double      pi = 3.14159265358979323846, r = mat.radius;
    const double      area = pi * r * r, inertia = pi * r * r * r * r / 4, polar = 2 * inertia;
    const double      shear = shear_modulus(mat.youngs_modulus, mat.poissons_ratio);
    RodNetwork        net;
    // Edges, and the rod ends at each vertex (edge, whether the vertex is the edge's first one).
    std::map<unsigned int, std::vector<std::pair<unsigned int, bool>>> ends;
    std::vector<std::array<unsigned int, 3>>                           hinge_vertices;
    std::vector<std::array<unsigned int, 2>>                           hinge_edges;
    for (const auto &rod : d.rods)
      {
        AssertThrow(rod.size() >= 2, dealii::ExcMessage("A rod needs at least two vertices."));
        for (const unsigned int v : rod)
          AssertThrow(v < nv, dealii::ExcMessage("A rod refers to a missing vertex."));
        const bool         closed = rod.front() == rod.back() && rod.size() >= 4;
        const unsigned int first  = unsigned(net.edges.size());
        for (std::size_t i = 0; i + 1 < rod.size(); ++i)
          {
            AssertThrow(norm(sub(d.vertices[rod[i + 1]], d.vertices[rod[i]])) > 0,
                        dealii::ExcMessage("A rod has an edge of zero length."));
            net.edges.push_back({{rod[i], rod[i + 1]}});
          }
        const unsigned int n_edges = unsigned(net.edges.size()) - first;
        for (unsigned int i = 0; i + 1 < n_edges; ++i)
          hinge_vertices.push_back({{rod[i], rod[i + 1], rod[i + 2]}}),
              hinge_edges.push_back({{first + i, first + i + 1}});
        if (closed)
          hinge_vertices.push_back({{rod[rod.size() - 2], rod[0], rod[1]}}),
              hinge_edges.push_back({{first + n_edges - 1, first}});
        else
          {
            ends[rod.front()].emplace_back(first, true);
            ends[rod.back()].emplace_back(first + n_edges - 1, false);
          }
      }
    AssertThrow(!net.edges.empty(), dealii::ExcMessage("The rod network has no edges."));
    std::vector<V3>     tangent(net.edges.size()), dir(net.edges.size());
    std::vector<double> length(net.edges.size());
    for (std::size_t e = 0; e < net.edges.size(); ++e)
      {
        const V3 a = sub(d.vertices[net.edges[e][1]], d.vertices[net.edges[e][0]]);
        length[e]  = norm(a);
        tangent[e] = {{a[0] / length[e], a[1] / length[e], a[2] / length[e]}};
        dir[e]     = director(tangent[e]);
      }
    std::map<unsigned int, unsigned int> junction_index;
    for (const auto &[v, list] : ends)
      if (list.size() >= 2)
        junction_index[v] = unsigned(net.junction_vertices.size()), net.junction_vertices.push_back(v);
    const std::size_t ne = net.edges.size(), nj = net.junction_vertices.size();
    net.theta_offset    = 3 * nv;
    net.rotation_offset = 3 * nv + ne;
    net.model           = Model(3 * nv + ne + 3 * nj);
    net.rest_positions  = Eigen::VectorXd::Zero(net.model.n_unknowns());
    for (std::size_t v = 0; v < nv; ++v)
      for (int i = 0; i < 3; ++i)
        net.rest_positions[3 * v + i] = d.vertices[v][i];
    Eigen::VectorXd &mass = net.model.lumped_mass();
    mass                  = Eigen::VectorXd::Zero(net.model.n_unknowns());
    for (std::size_t e = 0; e < ne; ++e)
      {
        for (int end = 0; end < 2; ++end)
          for (int i = 0; i < 3; ++i)
            mass[3 * net.edges[e][end] + i] += mat.density * area * length[e] / 2;
        mass[net.theta_offset + e] = mat.density * polar * length[e];
      }
    for (std::size_t v = 0; v < nv; ++v)
      AssertThrow(mass[3 * v] > 0, dealii::ExcMessage("Vertex " + std::to_string(v) + " belongs to no rod."));

    RodStretchElements stretch;
    stretch.stiffness   = mat.youngs_modulus * area;
    stretch.edges       = net.edges;
    stretch.rest_length = length;
    RodBendTwistElements hinges;
    hinges.theta_offset = net.theta_offset, hinges.bending = mat.youngs_modulus * inertia,
    hinges.twisting = shear * polar;
    for (std::size_t h = 0; h < hinge_vertices.size(); ++h)
      {
        const unsigned int a = hinge_edges[h][0], b = hinge_edges[h][1];
        hinges.vertices.push_back(hinge_vertices[h]);
        hinges.edges.push_back({{a, b}});
        hinges.rest_tangent_a.push_back(tangent[a]), hinges.rest_tangent_b.push_back(tangent[b]);
        hinges.rest_director_a.push_back(dir[a]), hinges.rest_director_b.push_back(dir[b]);
        RodHingeRest rest;
        rest.length = length[a] + length[b];
        hinges.rest.push_back(rest);
        std::array<double, 11> x;
        for (int v = 0; v < 3; ++v)
          for (int i = 0; i < 3; ++i)
            x[3 * v + i] = d.vertices[hinge_vertices[h][v]][i];
        x[9] = x[10] = 0;
        std::array<double, 5> m;
        hinges.evaluate(x, hinges.n_elements() - 1, false, &m);
        hinges.rest.back().curvature = {{m[0], m[1], m[2], m[3]}}, hinges.rest.back().twist = m[4];
      }
    RodJunctionElements joints;
    joints.theta_offset = net.theta_offset, joints.rotation_offset = net.rotation_offset;
    joints.bending = hinges.bending, joints.twisting = hinges.twisting;
    for (const auto &[v, list] : ends)
      {
        if (list.size() < 2)
          continue;
        const unsigned int j         = junction_index.at(v);
        double             inertia_j = 0;
        for (const auto &[e, first] : list)
          {
            // The edge as seen from the junction: from v to its other vertex.
            const unsigned int other = first ? net.edges[e][1] : net.edges[e][0];
            V3                 t     = tangent[e];
            if (!first)
              t = {{-t[0], -t[1], -t[2]}};
            joints.vertices.push_back({{v, other}});
            joints.junction.push_back(j), joints.edge.push_back(e);
            joints.rest_tangent.push_back(t);
            // The edge's director, so that its frame at rest is the one theta_e refers to.
            joints.rest_director.push_back(dir[e]);
            RodHingeRest rest;
            // Two arms in series across a junction must be as stiff as one interior hinge (Voronoi length
            // |e_a| + |e_b|): each arm-edge pair gets the edge's length alone.
            rest.length = length[e];
            joints.rest.push_back(rest);
            inertia_j +=
                mat.density * area * std::pow(length[e], 3) / 24 + mat.density * polar * length[e] / 2;
          }
        // q ~ phi / 2 for small turns: kinetic energy 1/2 I phi'^2 = 2 I q'^2.
        for (int i = 0; i < 3; ++i)
          mass[net.rotation_offset + 3 * j + i] = 4 * inertia_j;
      }
    // Rest measures of the junction arms (zero for straight arms, but computed, not assumed). The
    // twist of an edge met from its far end is measured with its tangent reversed: its frame must
    // be turned accordingly, which the reversed-tangent transport does.
    for (std::size_t k = 0; k < joints.n_elements(); ++k)
      {
        std::array<double, 10> x;
        for (int i = 0; i < 3; ++i)
          x[i] = d.vertices[joints.vertices[k][0]][i], x[3 + i] = 0,
          x[6 + i] = d.vertices[joints.vertices[k][1]][i];
        x[9] = 0;
        std::array<double, 5> m;
        joints.evaluate(x, k, false, &m);
        joints.rest[k].curvature = {{m[0], m[1], m[2], m[3]}}, joints.rest[k].twist = m[4];
      }
    net.model.add_term(std::make_shared<ElementEnergyTerm<RodStretchElements>>("rod stretching", stretch));
    if (hinges.n_elements() > 0)
      net.model.add_term(
          std::make_shared<ElementEnergyTerm<RodBendTwistElements>>("rod bending and twist", hinges));
    if (joints.n_elements() > 0)
      net.model.add_term(std::make_shared<ElementEnergyTerm<RodJunctionElements>>("rod junctions", joints));
    return net;
  }

  RodNetworkDescription rods_from_polylines(const std::vector<std::vector<std::array<double, 3>>> &polylines,
                                            const unsigned int segments, const double tolerance)
  {
    AssertThrow(segments >= 1, dealii::ExcMessage("Rods need at least one segment each."));
    RodNetworkDescription d;
    auto                  vertex = [&](const V3 &p) {
      for (unsigned int v = 0; v < d.vertices.size(); ++v)
        if (norm(sub(d.vertices[v], p)) <= tolerance)
          return v;
      d.vertices.push_back(p);
      return unsigned(d.vertices.size() - 1);
    };
    for (const auto &line : polylines)
      {
        AssertThrow(line.size() >= 2, dealii::ExcMessage("A rod polyline needs at least two points."));
        std::vector<double> s(1, 0.0);
        for (std::size_t i = 1; i < line.size(); ++i)
          s.push_back(s.back() + norm(sub(line[i], line[i - 1])));
        AssertThrow(s.back() > 0, dealii::ExcMessage("A rod polyline has zero length."));
        const bool                closed = norm(sub(line.front(), line.back())) <= tolerance;
        std::vector<unsigned int> rod;
        rod.push_back(vertex(line.front()));
        std::size_t piece = 1;
        for (unsigned int k = 1; k < segments; ++k)
          {
            const double target = s.back() * k / segments;
            while (s[piece] < target)
              ++piece;
            const double f = (target - s[piece - 1]) / (s[piece] - s[piece - 1]);
            V3           p;
            for (int i = 0; i < 3; ++i)
              p[i] = line[piece - 1][i] + f * (line[piece][i] - line[piece - 1][i]);
            d.vertices.push_back(p); // interior points are never shared
            rod.push_back(unsigned(d.vertices.size() - 1));
          }
        rod.push_back(closed ? rod.front() : vertex(line.back()));
        d.rods.push_back(rod);
      }
    return d;
  }

  template class ElementEnergyTerm<RodStretchElements>;
  template class ElementEnergyTerm<RodBendTwistElements>;
  template class ElementEnergyTerm<RodJunctionElements>;
} // namespace nlmech
