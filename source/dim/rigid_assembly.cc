#include <deal.II/base/exceptions.h>

#include <nlmech/base/threads.h>
#include <nlmech/dim/rigid_assembly.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <set>
#include <vector>

namespace nlmech::dim
{
  namespace
  {
    using Gradient = Sacado::Fad::SFad<double, 15>;
    using Hessian  = Sacado::Fad::SFad<Gradient, 15>;

    Eigen::Vector3d to_eigen(const Point<double> &p)
    {
      return {p[0], p[1], p[2]};
    }

    /// Bounding sphere of a primitive's points in the world (centre, radius without the sweep).
    template <std::size_t N>
    std::pair<Eigen::Vector3d, double> sphere(const std::vector<Eigen::Vector3d> &x,
                                              const std::array<unsigned, N>      &ids)
    {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (const unsigned i : ids)
        c += x[i];
      c /= double(N);
      double r = 0;
      for (const unsigned i : ids)
        r = std::max(r, (x[i] - c).norm());
      return {c, r};
    }
  } // namespace

  RigidAssembly::RigidAssembly(std::vector<ElementShape> shapes_in, std::vector<unsigned int> shape_of_body,
                               const Placement placement)
      : shapes(std::move(shapes_in))
      , shape_of(std::move(shape_of_body))
      , place(placement)
  {
    AssertThrow(!shape_of.empty(), dealii::ExcMessage("Rigid assembly: there are no elements."));
    for (const unsigned s : shape_of)
      AssertThrow(s < shapes.size(),
                  dealii::ExcMessage("Rigid assembly: an element refers to an unknown shape."));
    for (const auto &shape : shapes)
      {
        Primitives                              p;
        std::set<std::pair<unsigned, unsigned>> edges;
        std::set<std::pair<unsigned, double>>   vertices;
        for (std::size_t s = 0; s < shape.segments.size(); ++s)
          {
            const auto [i, j] = shape.segments[s];
            if (edges.insert({std::min(i, j), std::max(i, j)}).second)
              p.edges.push_back({{i, j}}), p.edge_radius.push_back(shape.segment_radius[s]);
            vertices.insert({i, shape.segment_radius[s]}), vertices.insert({j, shape.segment_radius[s]});
          }
        for (std::size_t t = 0; t < shape.triangles.size(); ++t)
          {
            const auto &tri = shape.triangles[t];
            p.faces.push_back(tri), p.face_radius.push_back(shape.triangle_radius[t]);
            for (unsigned k = 0; k < 3; ++k)
              {
                const unsigned i = tri[k], j = tri[(k + 1) % 3];
                if (edges.insert({std::min(i, j), std::max(i, j)}).second)
                  p.edges.push_back({{i, j}}), p.edge_radius.push_back(shape.triangle_radius[t]);
                vertices.insert({i, shape.triangle_radius[t]});
              }
          }
        p.vertices.assign(vertices.begin(), vertices.end());
        // Sphere trees over the primitives in the body frame (radius: points plus sweep).
        Trees                        t;
        std::vector<Eigen::Vector3d> centres;
        std::vector<double>          radii;
        for (std::size_t e = 0; e < p.edges.size(); ++e)
          {
            const auto [c, r] = sphere(shape.points, p.edges[e]);
            centres.push_back(c), radii.push_back(r + p.edge_radius[e]);
          }
        t.edges = SphereTree(centres, radii);
        centres.clear(), radii.clear();
        for (std::size_t f = 0; f < p.faces.size(); ++f)
          {
            const auto [c, r] = sphere(shape.points, p.faces[f]);
            centres.push_back(c), radii.push_back(r + p.face_radius[f]);
          }
        t.faces = SphereTree(centres, radii);
        centres.clear(), radii.clear();
        for (const auto &[v, rv] : p.vertices)
          centres.push_back(shape.points[v]), radii.push_back(rv);
        t.vertices = SphereTree(centres, radii);
        trees.push_back(std::move(t));
        primitives.push_back(std::move(p));
        double rho = 0;
        for (const auto &x : shape.points)
          rho = std::max(rho, x.norm());
        reach_radius.push_back(rho);
      }
  }

  void RigidAssembly::set_lattice(const Eigen::Vector2d &t1, const Eigen::Vector2d &t2,
                                  const std::vector<Eigen::Matrix2d> &strain_basis)
  {
    AssertThrow(place == Placement::periodic,
                dealii::ExcMessage("Rigid assembly: a lattice needs periodic placement."));
    AssertThrow(std::abs(t1[0] * t2[1] - t1[1] * t2[0]) > 1e-12 * t1.squaredNorm(),
                dealii::ExcMessage("Periodic cell: the two lattice vectors are parallel."));
    AssertThrow(strain_basis.size() <= 3,
                dealii::ExcMessage("Periodic cell: at most three strain parameters."));
    tbar1 = t1, tbar2 = t2, basis = strain_basis;
  }

  std::size_t RigidAssembly::n_parameters() const
  {
    return place == Placement::periodic     ? basis.size()
           : place == Placement::paraboloid ? curvature.size()
                                            : 0;
  }

  void RigidAssembly::set_curvature_basis(const std::vector<Eigen::Vector3d> &b)
  {
    AssertThrow(place == Placement::paraboloid,
                dealii::ExcMessage("Rigid assembly: a curvature basis needs paraboloid placement."));
    AssertThrow(!b.empty() && b.size() <= 3,
                dealii::ExcMessage("Paraboloid: one to three curvature parameters."));
    curvature = b;
  }

  Eigen::Matrix3d RigidAssembly::rotation(const Eigen::Vector3d &omega)
  {
    Eigen::Matrix3d R;
    for (int k = 0; k < 3; ++k)
      R.col(k) = to_eigen(rotate(omega.data(), Eigen::Vector3d::Unit(k)));
    return R;
  }

  Eigen::Vector3d RigidAssembly::world_point(const Eigen::VectorXd &q, const unsigned int body,
                                             const Eigen::Vector3d &p, const std::array<int, 2> image) const
  {
    const double *parameters = n_parameters() > 0 ? q.data() + parameter_index(0) : nullptr;
    return to_eigen(world_point<double>(q.data() + 6 * body, parameters, image, p));
  }

  Eigen::Vector3d RigidAssembly::centre(const Eigen::VectorXd &q, const unsigned int body,
                                        const std::array<int, 2> image) const
  {
    return world_point(q, body, Eigen::Vector3d::Zero(), image);
  }

  Eigen::VectorXd RigidAssembly::motion_metric(const Eigen::VectorXd &q) const
  {
    Eigen::VectorXd metric = Eigen::VectorXd::Ones(n_unknowns());
    double          extent = 0;
    for (unsigned b = 0; b < n_bodies(); ++b)
      {
        const double rho = std::max(reach_radius[shape_of[b]], 1e-12);
        metric.segment<3>(6 * b + 3).setConstant(rho * rho);
        extent = std::max(extent, q.segment<2>(6 * b).norm() + rho);
      }
    for (std::size_t j = 0; j < n_parameters(); ++j)
      {
        double w = 1;
        if (place == Placement::periodic)
          w = std::max((basis[j] * tbar1).squaredNorm(), (basis[j] * tbar2).squaredNorm());
        else if (place == Placement::paraboloid)
          w = std::pow(extent, 4) * curvature[j].squaredNorm();
        metric[parameter_index(j)] = std::max(w, 1e-12);
      }
    return metric;
  }

  Eigen::Matrix2d RigidAssembly::stretch(const Eigen::VectorXd &q) const
  {
    Eigen::Matrix2d U = Eigen::Matrix2d::Identity();
    if (place == Placement::periodic)
      for (std::size_t j = 0; j < basis.size(); ++j)
        U += q[parameter_index(j)] * basis[j];
    return U;
  }

  Eigen::Vector2d RigidAssembly::lattice_vector(const Eigen::VectorXd &q, const unsigned int k) const
  {
    return stretch(q) * (k == 0 ? tbar1 : tbar2);
  }

  int RigidAssembly::image_range() const
  {
    if (place != Placement::periodic)
      return 0;
    double rho = 0;
    for (const auto &s : shapes)
      rho = std::max(rho, s.bounding_radius());
    // Heights of the cell over each lattice vector bound how many images a body can reach.
    const double area = std::abs(tbar1[0] * tbar2[1] - tbar1[1] * tbar2[0]);
    const double h    = std::min(area / tbar1.norm(), area / tbar2.norm());
    return 1 + int(std::ceil(3 * rho / h));
  }

  std::vector<std::tuple<unsigned, unsigned, std::array<int, 2>>>
  RigidAssembly::body_pairs(const Eigen::VectorXd &q, const double reach) const
  {
    std::vector<std::tuple<unsigned, unsigned, std::array<int, 2>>> pairs;
    const int                                                       range = image_range();
    for (unsigned a = 0; a < n_bodies(); ++a)
      for (unsigned b = a; b < n_bodies(); ++b)
        for (int i = -range; i <= range; ++i)
          for (int j = -range; j <= range; ++j)
            {
              if (a == b && (i < 0 || (i == 0 && j <= 0)))
                continue; // a body against itself only through a positive image
              const std::array<int, 2> image{{i, j}};
              const double gap = (centre(q, a) - centre(q, b, image)).norm() - shape(a).bounding_radius() -
                                 shape(b).bounding_radius();
              if (gap < reach)
                pairs.emplace_back(a, b, image);
            }
    return pairs;
  }

  SphereTree::Placement RigidAssembly::placement_of(const Eigen::VectorXd &q, const unsigned body,
                                                    const std::array<int, 2> &image) const
  {
    SphereTree::Placement p;
    p.R = rotation(q.segment<3>(6 * body + 3));
    p.t = centre(q, body, image);
    return p;
  }

  std::vector<ContactPair> RigidAssembly::contact_pairs(const Eigen::VectorXd &q, const double reach) const
  {
    // Each pair of bodies (an image) on its own, on deal.II's threads, then joined in pair order.
    const auto                            candidates = body_pairs(q, reach);
    std::vector<std::vector<ContactPair>> found(candidates.size());
    const auto                            within = [reach]() { return reach; };
    const auto                            search = [&](const std::size_t c) {
      const auto &[a, b, image]                 = candidates[c];
      std::vector<ContactPair>          &result = found[c];
      const auto                        &sa = shape(a), &sb = shape(b);
      const auto                        &pa = primitives[shape_of[a]], &pb = primitives[shape_of[b]];
      const auto                        &ta = trees[shape_of[a]], &tb = trees[shape_of[b]];
      const SphereTree::Placement        la = placement_of(q, a, {{0, 0}}), lb = placement_of(q, b, image);
      const std::vector<Eigen::Vector3d> xa = world_points(q, a), xb = world_points(q, b, image);
      auto add = [&](const ClosestType &c, const std::array<Eigen::Vector3d, 4> &points,
                     const std::array<unsigned char, 4> &owner, const double radius_sum) {
        const double gap = std::sqrt(c.squared_distance) - radius_sum;
        if (!(gap < reach))
          return;
        ContactPair pair;
        pair.body_a = a, pair.body_b = b, pair.image = image, pair.type = c.type;
        pair.radius_sum = radius_sum, pair.gap = gap;
        for (unsigned k = 0; k < 4; ++k)
          pair.body_points[k] = points[c.points[k]], pair.owner[k] = owner[c.points[k]];
        result.push_back(pair);
      };
      // Edge pairs whose swept spheres come within reach (the trees prune whole subtrees).
      SphereTree::for_close_pairs(ta.edges, la, tb.edges, lb, within, [&](unsigned ea, unsigned eb) {
        const auto &[i0, i1] = pa.edges[ea];
        const auto &[j0, j1] = pb.edges[eb];
        add(segment_segment_type(xa[i0], xa[i1], xb[j0], xb[j1]),
                                       {{sa.points[i0], sa.points[i1], sb.points[j0], sb.points[j1]}}, {{0, 0, 1, 1}},
                                       pa.edge_radius[ea] + pb.edge_radius[eb]);
      });
      // Points of one element against the faces of the other (both ways).
      for (int side = 0; side < 2; ++side)
        {
          const auto         &pv = side == 0 ? pa : pb, &pf = side == 0 ? pb : pa;
          const auto         &xv = side == 0 ? xa : xb, &xf = side == 0 ? xb : xa;
          const auto         &sv = side == 0 ? sa : sb, &sf = side == 0 ? sb : sa;
          const auto         &tv = side == 0 ? ta : tb, &tf = side == 0 ? tb : ta;
          const auto         &lv = side == 0 ? la : lb, &lf = side == 0 ? lb : la;
          const unsigned char ov = side == 0 ? 0 : 1, of = side == 0 ? 1 : 0;
          SphereTree::for_close_pairs(tv.vertices, lv, tf.faces, lf, within, [&](unsigned k, unsigned f) {
            const auto &[v, rv]      = pv.vertices[k];
            const auto &[t0, t1, t2] = pf.faces[f];
            add(point_triangle_type(xv[v], xf[t0], xf[t1], xf[t2]),
                                           {{sv.points[v], sf.points[t0], sf.points[t1], sf.points[t2]}}, {{ov, of, of, of}},
                                           rv + pf.face_radius[f]);
          });
        }
    };
    for_each_block(candidates.size(), 1, [&](const std::size_t begin, const std::size_t end) {
      for (std::size_t c = begin; c < end; ++c)
        search(c);
    });
    std::vector<ContactPair> result;
    for (auto &f : found)
      result.insert(result.end(), f.begin(), f.end());
    return result;
  }

  std::vector<Eigen::Vector3d> RigidAssembly::world_points(const Eigen::VectorXd &q, const unsigned body,
                                                           const std::array<int, 2> image) const
  {
    const Eigen::Matrix3d        R = rotation(q.segment<3>(6 * body + 3));
    const Eigen::Vector3d        c = centre(q, body, image);
    std::vector<Eigen::Vector3d> x;
    x.reserve(shape(body).points.size());
    for (const auto &p : shape(body).points)
      x.push_back(c + R * p);
    return x;
  }

  double RigidAssembly::exact_gap(const Eigen::VectorXd &q, const unsigned a, const unsigned b,
                                  const std::array<int, 2> &image, const double cutoff) const
  {
    const auto                        &pa = primitives[shape_of[a]], &pb = primitives[shape_of[b]];
    const auto                        &ta = trees[shape_of[a]], &tb = trees[shape_of[b]];
    const SphereTree::Placement        la = placement_of(q, a, {{0, 0}}), lb = placement_of(q, b, image);
    const std::vector<Eigen::Vector3d> xa = world_points(q, a), xb = world_points(q, b, image);
    // Branch and bound over both trees: a pair of subtrees whose spheres are farther apart than the
    // best gap so far (or the cutoff) cannot hold a closer pair. Edges against edges, and edges
    // against faces both ways (a crossing gives distance 0, so the gap is minus the radii).
    double     gap   = std::numeric_limits<double>::infinity();
    const auto bound = [&]() { return std::min(gap, cutoff); };
    SphereTree::for_close_pairs(ta.edges, la, tb.edges, lb, bound, [&](unsigned i, unsigned j) {
      const auto &[i0, i1] = pa.edges[i];
      const auto &[j0, j1] = pb.edges[j];
      gap = std::min(gap, std::sqrt(segment_segment_type(xa[i0], xa[i1], xb[j0], xb[j1]).squared_distance) -
                              pa.edge_radius[i] - pb.edge_radius[j]);
    });
    for (int side = 0; side < 2; ++side)
      {
        const auto &pe = side == 0 ? pa : pb, &pf = side == 0 ? pb : pa;
        const auto &xe = side == 0 ? xa : xb, &xf = side == 0 ? xb : xa;
        const auto &te = side == 0 ? ta : tb, &tf = side == 0 ? tb : ta;
        const auto &le = side == 0 ? la : lb, &lf = side == 0 ? lb : la;
        SphereTree::for_close_pairs(te.edges, le, tf.faces, lf, bound, [&](unsigned i, unsigned f) {
          const auto &[t0, t1, t2] = pf.faces[f];
          gap                      = std::min(
                                   gap, segment_triangle_distance(xe[pe.edges[i][0]], xe[pe.edges[i][1]], xf[t0], xf[t1], xf[t2]) -
                                            pe.edge_radius[i] - pf.face_radius[f]);
        });
      }
    return gap;
  }

  std::pair<double, std::size_t> RigidAssembly::all_pairs_gap(const Eigen::VectorXd &q, const unsigned a,
                                                              const unsigned            b,
                                                              const std::array<int, 2> &image,
                                                              const double              reach) const
  {
    const auto                        &pa = primitives[shape_of[a]], &pb = primitives[shape_of[b]];
    const std::vector<Eigen::Vector3d> xa = world_points(q, a), xb = world_points(q, b, image);
    double                             gap   = std::numeric_limits<double>::infinity();
    std::size_t                        close = 0;
    for (std::size_t i = 0; i < pa.edges.size(); ++i)
      for (std::size_t j = 0; j < pb.edges.size(); ++j)
        {
          const auto &[i0, i1] = pa.edges[i];
          const auto &[j0, j1] = pb.edges[j];
          const double g = std::sqrt(segment_segment_type(xa[i0], xa[i1], xb[j0], xb[j1]).squared_distance) -
                           pa.edge_radius[i] - pb.edge_radius[j];
          gap = std::min(gap, g);
          close += g < reach;
        }
    for (int side = 0; side < 2; ++side)
      {
        const auto &pe = side == 0 ? pa : pb, &pf = side == 0 ? pb : pa;
        const auto &xe = side == 0 ? xa : xb, &xf = side == 0 ? xb : xa;
        for (std::size_t f = 0; f < pf.faces.size(); ++f)
          {
            const auto &[t0, t1, t2] = pf.faces[f];
            for (std::size_t i = 0; i < pe.edges.size(); ++i)
              gap = std::min(gap, segment_triangle_distance(xe[pe.edges[i][0]], xe[pe.edges[i][1]], xf[t0],
                                                            xf[t1], xf[t2]) -
                                      pe.edge_radius[i] - pf.face_radius[f]);
            for (const auto &[v, rv] : pe.vertices)
              close += std::sqrt(point_triangle_type(xe[v], xf[t0], xf[t1], xf[t2]).squared_distance) - rv -
                           pf.face_radius[f] <
                       reach;
          }
      }
    return {gap, close};
  }

  RigidAssembly::Gap RigidAssembly::smallest_gap(const Eigen::VectorXd &q, const double reach) const
  {
    Gap best;
    for (const auto &[a, b, image] : body_pairs(q, reach))
      {
        const double gap = exact_gap(q, a, b, image, std::min(reach, best.gap));
        if (gap < best.gap)
          best.gap = gap, best.body_a = a, best.body_b = b, best.image = image;
      }
    return best;
  }

  double RigidAssembly::max_safe_step(const Eigen::VectorXd &q, const Eigen::VectorXd &dq,
                                      const double separation, const double keep) const
  {
    // Bound on the speed (per unit step) of every point of body b's image: centre, rotation about it
    // (|d/dt R(omega + t domega) p| <= |domega| |p|, the exponential map's Jacobian has norm <= 1),
    // the stretched lattice offset, the paraboloid's height.
    std::vector<double> speed(n_bodies());
    for (unsigned b = 0; b < n_bodies(); ++b)
      {
        double v = dq.segment<3>(6 * b).norm() + dq.segment<3>(6 * b + 3).norm() * reach_radius[shape_of[b]];
        if (place == Placement::paraboloid)
          {
            Eigen::Vector3d k0 = Eigen::Vector3d::Zero(), dk = Eigen::Vector3d::Zero();
            for (std::size_t j = 0; j < curvature.size(); ++j)
              k0 += q[parameter_index(j)] * curvature[j], dk += dq[parameter_index(j)] * curvature[j];
            const double x = std::abs(q[6 * b]) + std::abs(dq[6 * b]);
            const double y = std::abs(q[6 * b + 1]) + std::abs(dq[6 * b + 1]);
            const double A = std::abs(k0[0]) + std::abs(dk[0]), B = std::abs(k0[1]) + std::abs(dk[1]),
                         C  = std::abs(k0[2]) + std::abs(dk[2]);
            const double dx = std::abs(dq[6 * b]), dy = std::abs(dq[6 * b + 1]);
            v += std::abs(dk[0]) * x * x + 2 * A * x * dx + std::abs(dk[1]) * y * y + 2 * B * y * dy +
                 std::abs(dk[2]) * x * y + C * (dx * y + x * dy);
          }
        speed[b] = v;
      }
    auto image_speed = [&](const std::array<int, 2> &image) {
      if (place != Placement::periodic || (image[0] == 0 && image[1] == 0))
        return 0.0;
      const Eigen::Vector2d o = image[0] * tbar1 + image[1] * tbar2;
      Eigen::Vector2d       v = Eigen::Vector2d::Zero();
      for (std::size_t j = 0; j < basis.size(); ++j)
        v += dq[parameter_index(j)] * basis[j] * o;
      return v.norm();
    };
    const double max_speed = *std::max_element(speed.begin(), speed.end());
    double       reach     = 2 * max_speed + separation;
    if (place == Placement::periodic)
      reach += image_speed({{image_range(), image_range()}}) * 2;
    // The body pairs that can meet during the step, with their gaps at its start.
    struct Candidate
    {
      unsigned           a, b;
      std::array<int, 2> image;
      double             speed, start_gap;
    };
    std::vector<Candidate> candidates;
    for (const auto &[a, b, image] : body_pairs(q, reach))
      {
        double v = speed[a] + speed[b] + image_speed(image);
        if (place != Placement::paraboloid)
          {
            // Centres (and image offsets) move linearly with the step: bound the relative motion
            // of the pair by the exact relative translation plus each body's rotation.
            Eigen::Vector3d relative = dq.segment<3>(6 * b) - dq.segment<3>(6 * a);
            if (place == Placement::periodic)
              {
                const Eigen::Vector2d o = image[0] * tbar1 + image[1] * tbar2;
                for (std::size_t j = 0; j < basis.size(); ++j)
                  relative.head<2>() += dq[parameter_index(j)] * basis[j] * o;
              }
            v = relative.norm() + dq.segment<3>(6 * a + 3).norm() * reach_radius[shape_of[a]] +
                dq.segment<3>(6 * b + 3).norm() * reach_radius[shape_of[b]];
          }
        if (v > 0)
          candidates.push_back({a, b, image, v, 0});
      }
    if (candidates.empty())
      return 1.0;
    // A pair is checked exactly only while it could reach its floor within the rest of the step.
    auto pair_gap = [&](const Eigen::VectorXd &x, const Candidate &c, const double cutoff) {
      return exact_gap(x, c.a, c.b, c.image, cutoff + separation) - separation;
    };
    std::vector<Candidate> reachable;
    for (auto &c : candidates)
      {
        const double cutoff = c.speed / (1 - keep);
        c.start_gap         = pair_gap(q, c, cutoff);
        if (c.start_gap < cutoff)
          reachable.push_back(c); // otherwise it stays above keep * its gap during the whole step
      }
    // Each pair's gap is known exactly at the step where it was last computed, and falls at most by
    // its speed per unit step after that: advance to where the first pair could reach its floor,
    // compute that pair exactly there, and repeat (only the limiting pair is recomputed).
    std::vector<double> known_at(reachable.size(), 0.0), known_gap(reachable.size());
    for (std::size_t k = 0; k < reachable.size(); ++k)
      {
        known_gap[k] = reachable[k].start_gap;
        if (known_gap[k] <= keep * reachable[k].start_gap)
          return 0.0;
      }
    double alpha = 0;
    for (unsigned iteration = 0; iteration < 1000; ++iteration)
      {
        std::size_t limiting = reachable.size();
        double      next     = std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < reachable.size(); ++k)
          {
            const double reach_floor =
                known_at[k] + (known_gap[k] - keep * reachable[k].start_gap) / reachable[k].speed;
            if (reach_floor < next)
              next = reach_floor, limiting = k;
          }
        if (next >= 1 || limiting == reachable.size())
          return 1.0;
        alpha              = std::max(alpha, next); // ties (symmetric pairs) are recomputed without advancing
        const Candidate &c = reachable[limiting];
        const double     floor = keep * c.start_gap;
        const double     g     = pair_gap(q + alpha * dq, c, floor + c.speed * (1 - alpha));
        if (std::getenv("NLMECH_CCD_DEBUG"))
          std::fprintf(stderr, "ccd it %u alpha %.3e pair %zu/%zu g %.3e floor %.3e speed %.3e start %.3e\n",
                       iteration, alpha, limiting, reachable.size(), g, floor, c.speed, c.start_gap);
        if (g <= floor)
          return alpha;
        known_at[limiting] = alpha, known_gap[limiting] = g;
      }
    return alpha;
  }

  // ---------------------------------------------------------------------------------------------

  ContactBarrier::ContactBarrier(std::shared_ptr<const RigidAssembly> assembly_in,
                                 const ContactSettings                settings)
      : assembly(std::move(assembly_in))
      , contact(settings)
  {
    AssertThrow(contact.dhat > 0 && contact.kappa > 0,
                dealii::ExcMessage("Contact: the barrier gap dhat and stiffness kappa must be positive."));
    AssertThrow(contact.separation >= 0,
                dealii::ExcMessage("Contact: the minimum separation must not be negative."));
  }

  std::shared_ptr<const std::vector<ContactPair>> ContactBarrier::pairs_at(const Eigen::VectorXd &q) const
  {
    {
      const std::lock_guard<std::mutex> lock(cache_mutex);
      if (cached_pairs && cached_state.size() == q.size() &&
          std::equal(q.data(), q.data() + q.size(), cached_state.data()))
        return cached_pairs;
    }
    auto pairs = std::make_shared<std::vector<ContactPair>>(
        assembly->contact_pairs(q, contact.dhat + contact.separation));
    for (ContactPair &p : *pairs)
      p.radius_sum += contact.separation;
    const std::lock_guard<std::mutex> lock(cache_mutex);
    cached_state = q;
    cached_pairs = pairs;
    ++searches;
    return pairs;
  }

  std::size_t ContactBarrier::n_collision_searches() const
  {
    const std::lock_guard<std::mutex> lock(cache_mutex);
    return searches;
  }

  std::array<long, 15> ContactBarrier::pair_dofs(const ContactPair &pair) const
  {
    std::array<long, 15> dofs;
    dofs.fill(-1);
    for (unsigned k = 0; k < 6; ++k)
      dofs[k] = 6 * pair.body_a + k, dofs[6 + k] = 6 * pair.body_b + k;
    for (unsigned j = 0; j < assembly->n_parameters(); ++j)
      dofs[12 + j] = assembly->parameter_index(j);
    return dofs;
  }

  template <typename S>
  S ContactBarrier::pair_energy(const ContactPair &pair, const std::array<S, 15> &v) const
  {
    using std::sqrt;
    std::array<Point<S>, 4> x;
    for (unsigned k = 0; k < 4; ++k)
      x[k] = assembly->world_point(pair.owner[k] == 0 ? &v[0] : &v[6], &v[12],
                                   pair.owner[k] == 0 ? std::array<int, 2>{{0, 0}} : pair.image,
                                   pair.body_points[k]);
    const S d = sqrt(squared_distance(pair.type, x)) - pair.radius_sum;
    return barrier(d, contact.dhat, contact.kappa);
  }

  // The pair loops run in fixed blocks on deal.II's threads, into one buffer entry per pair that is
  // then added in pair order: the same sums for every thread count.
  namespace
  {
    constexpr std::size_t pairs_per_block = 16;
  }

  double ContactBarrier::value(const Eigen::VectorXd &q) const
  {
    const auto          pairs = pairs_at(q);
    std::vector<double> values(pairs->size());
    for_each_block(pairs->size(), pairs_per_block, [&](const std::size_t begin, const std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
        {
          const auto             dofs = pair_dofs((*pairs)[i]);
          std::array<double, 15> v{};
          for (unsigned k = 0; k < 15; ++k)
            v[k] = dofs[k] >= 0 ? q[dofs[k]] : 0.0;
          values[i] = pair_energy((*pairs)[i], v);
        }
    });
    double total = 0;
    for (const double v : values)
      total += v;
    return total;
  }

  void ContactBarrier::add_gradient(const Eigen::VectorXd &q, Eigen::VectorXd &g) const
  {
    const auto                          pairs = pairs_at(q);
    std::vector<std::array<double, 15>> local(pairs->size());
    std::vector<std::array<long, 15>>   dofs(pairs->size());
    for_each_block(pairs->size(), pairs_per_block, [&](const std::size_t begin, const std::size_t end) {
      for (std::size_t p = begin; p < end; ++p)
        {
          dofs[p] = pair_dofs((*pairs)[p]);
          std::array<Gradient, 15> v;
          for (unsigned k = 0; k < 15; ++k)
            v[k] = Gradient(15, k, dofs[p][k] >= 0 ? q[dofs[p][k]] : 0.0);
          const Gradient e = pair_energy((*pairs)[p], v);
          for (unsigned k = 0; k < 15; ++k)
            local[p][k] = e.dx(k);
        }
    });
    for (std::size_t p = 0; p < pairs->size(); ++p)
      for (unsigned k = 0; k < 15; ++k)
        if (dofs[p][k] >= 0)
          g[dofs[p][k]] += local[p][k];
  }

  void ContactBarrier::add_hessian(const Eigen::VectorXd &q, Triplets &h) const
  {
    const auto                                 pairs = pairs_at(q);
    std::vector<Eigen::Matrix<double, 15, 15>> local(pairs->size());
    std::vector<std::array<long, 15>>          dofs(pairs->size());
    for_each_block(pairs->size(), pairs_per_block, [&](const std::size_t begin, const std::size_t end) {
      for (std::size_t p = begin; p < end; ++p)
        {
          dofs[p] = pair_dofs((*pairs)[p]);
          std::array<Hessian, 15> v;
          for (unsigned k = 0; k < 15; ++k)
            v[k] = Hessian(15, k, Gradient(15, k, dofs[p][k] >= 0 ? q[dofs[p][k]] : 0.0));
          const Hessian                  e = pair_energy((*pairs)[p], v);
          Eigen::Matrix<double, 15, 15> &H = local[p];
          for (unsigned i = 0; i < 15; ++i)
            for (unsigned j = 0; j < 15; ++j)
              H(i, j) = e.dx(i).dx(j);
          H = 0.5 * (H + H.transpose()).eval();
          if (contact.project_hessians)
            project_to_positive_semidefinite(H); // IPC: negative eigenvalues clamped to zero
        }
    });
    for (std::size_t p = 0; p < pairs->size(); ++p)
      for (unsigned i = 0; i < 15; ++i)
        for (unsigned j = 0; j < 15; ++j)
          if (dofs[p][i] >= 0 && dofs[p][j] >= 0 && local[p](i, j) != 0)
            h.emplace_back(dofs[p][i], dofs[p][j], local[p](i, j));
  }

  bool ContactBarrier::is_valid(const Eigen::VectorXd &q) const
  {
    if (!q.allFinite())
      return false;
    return assembly->smallest_gap(q, contact.separation + contact.dhat).gap > contact.separation;
  }

  double ContactBarrier::max_safe_step(const Eigen::VectorXd &q, const Eigen::VectorXd &dq) const
  {
    return assembly->max_safe_step(q, dq, contact.separation);
  }

  // ---------------------------------------------------------------------------------------------

  CentreForces::CentreForces(std::shared_ptr<const RigidAssembly> assembly_in, std::vector<Eigen::Vector3d> f)
      : assembly(std::move(assembly_in))
      , forces(std::move(f))
  {
    AssertThrow(forces.size() == assembly->n_bodies(),
                dealii::ExcMessage("Centre forces: one force per element is needed."));
  }

  namespace
  {
    using CentreGradient = Sacado::Fad::SFad<double, 9>;
    using CentreHessian  = Sacado::Fad::SFad<CentreGradient, 9>;
    template <typename S>
    S centre_work(const RigidAssembly &assembly, const std::array<S, 9> &v, const Eigen::Vector3d &f)
    {
      const Point<S> c = assembly.world_point(&v[0], &v[6], {{0, 0}}, Eigen::Vector3d::Zero());
      return -(f[0] * c[0] + f[1] * c[1] + f[2] * c[2]);
    }
  } // namespace

  double CentreForces::value(const Eigen::VectorXd &q) const
  {
    double total = 0;
    for (unsigned b = 0; b < assembly->n_bodies(); ++b)
      total -= forces[b].dot(assembly->centre(q, b));
    return total;
  }

  void CentreForces::add_gradient(const Eigen::VectorXd &q, Eigen::VectorXd &g) const
  {
    const std::size_t np = assembly->n_parameters();
    for (unsigned b = 0; b < assembly->n_bodies(); ++b)
      {
        if (forces[b].squaredNorm() == 0)
          continue;
        std::array<CentreGradient, 9> v;
        for (unsigned k = 0; k < 9; ++k)
          v[k] = CentreGradient(9, k,
                                k < 6        ? q[6 * b + k]
                                : k - 6 < np ? q[assembly->parameter_index(k - 6)]
                                             : 0.0);
        const CentreGradient e = centre_work(*assembly, v, forces[b]);
        for (unsigned k = 0; k < 6; ++k)
          g[6 * b + k] += e.dx(k);
        for (unsigned k = 0; k < np && k < 3; ++k)
          g[assembly->parameter_index(k)] += e.dx(6 + k);
      }
  }

  void CentreForces::add_hessian(const Eigen::VectorXd &q, Triplets &h) const
  {
    if (assembly->placement() != Placement::paraboloid)
      return; // linear in the unknowns
    const std::size_t np = assembly->n_parameters();
    for (unsigned b = 0; b < assembly->n_bodies(); ++b)
      {
        if (forces[b].squaredNorm() == 0)
          continue;
        std::array<CentreHessian, 9> v;
        std::array<long, 9>          dofs;
        for (unsigned k = 0; k < 9; ++k)
          {
            dofs[k] = k < 6 ? long(6 * b + k) : long(assembly->parameter_index(k - 6));
            v[k]    = CentreHessian(9, k, CentreGradient(9, k, k < 6 || k - 6 < np ? q[dofs[k]] : 0.0));
          }
        const CentreHessian e = centre_work(*assembly, v, forces[b]);
        for (unsigned i = 0; i < 9; ++i)
          for (unsigned j = 0; j < 9; ++j)
            if (e.dx(i).dx(j) != 0)
              h.emplace_back(dofs[i], dofs[j], e.dx(i).dx(j));
      }
  }

  // ---------------------------------------------------------------------------------------------

  ParameterTarget::ParameterTarget(const std::size_t first_index, std::vector<double> t,
                                   std::vector<double> w)
      : first(first_index)
      , targets(std::move(t))
      , weights(std::move(w))
  {
    AssertThrow(targets.size() == weights.size(),
                dealii::ExcMessage("Parameter target: one weight per target is needed."));
  }

  double ParameterTarget::value(const Eigen::VectorXd &q) const
  {
    double e = 0;
    for (std::size_t j = 0; j < targets.size(); ++j)
      e += 0.5 * weights[j] * std::pow(q[first + j] - targets[j], 2);
    return e;
  }

  void ParameterTarget::add_gradient(const Eigen::VectorXd &q, Eigen::VectorXd &g) const
  {
    for (std::size_t j = 0; j < targets.size(); ++j)
      g[first + j] += weights[j] * (q[first + j] - targets[j]);
  }

  void ParameterTarget::add_hessian(const Eigen::VectorXd &, Triplets &h) const
  {
    for (std::size_t j = 0; j < targets.size(); ++j)
      h.emplace_back(first + j, first + j, weights[j]);
  }
} // namespace nlmech::dim
