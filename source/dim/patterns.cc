#include <deal.II/base/exceptions.h>

#include <nlmech/dim/patterns.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace nlmech::dim
{
  Pattern four_in_one_pattern(const FourInOneDimensions &d, const double density)
  {
    AssertThrow(d.a > 0 && d.b > 0,
                dealii::ExcMessage("4-in-1: the column spacing a and row spacing b must be positive."));
    Pattern p;
    p.name = "4-in-1 chainmail";
    p.shapes.push_back(torus_ring(d.R, d.r, d.segments, density));
    p.shape_of  = {0, 0};
    p.centres   = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(d.a, 0.5 * d.b, 0)};
    p.rotations = {Eigen::Vector3d(0, d.tilt, 0), Eigen::Vector3d(0, -d.tilt, 0)};
    p.t1 = Eigen::Vector2d(2 * d.a, 0), p.t2 = Eigen::Vector2d(0, d.b);
    p.neighbours = 4;
    return p;
  }

  Pattern threefold_pattern(const ThreefoldDimensions &d, const double density)
  {
    AssertThrow(d.D > 0, dealii::ExcMessage("Threefold chainmail: the lattice spacing D must be positive."));
    Pattern p;
    p.name = "threefold chainmail";
    p.shapes.push_back(wave_ring(d.R, d.r, d.h, 6, M_PI / 12, d.segments, density));
    p.shape_of  = {0};
    p.centres   = {Eigen::Vector3d::Zero()};
    p.rotations = {Eigen::Vector3d::Zero()};
    p.t1 = Eigen::Vector2d(d.D, 0), p.t2 = Eigen::Vector2d(0.5 * d.D, 0.5 * std::sqrt(3.0) * d.D);
    p.neighbours = 6;
    return p;
  }

  Pattern torus_knot_pattern(const TorusKnotDimensions &d, const double density)
  {
    AssertThrow(d.D > 0, dealii::ExcMessage("Torus-knot material: the lattice spacing D must be positive."));
    Pattern p;
    p.name = "torus knot";
    p.shapes.push_back(torus_knot(d.p, d.q, d.R, d.a, d.r, d.segments, density));
    p.shape_of  = {0};
    p.centres   = {Eigen::Vector3d::Zero()};
    p.rotations = {Eigen::Vector3d(0, 0, d.phase)};
    p.t1 = Eigen::Vector2d(d.D, 0), p.t2 = Eigen::Vector2d(0, d.D);
    p.neighbours = 4;
    return p;
  }

  Pattern scale_mail_pattern(const ScaleMailDimensions &d, const double density)
  {
    AssertThrow(d.D > 0, dealii::ExcMessage("Scale mail: the lattice spacing D must be positive."));
    Pattern p;
    p.name = "scale mail";
    p.shapes.push_back(scale_mail_element(d.R, d.r, d.h, d.segments, d.plate_radius, d.plate_thickness,
                                          d.plate_height, density));
    p.shape_of  = {0};
    p.centres   = {Eigen::Vector3d::Zero()};
    p.rotations = {Eigen::Vector3d::Zero()};
    p.t1 = Eigen::Vector2d(d.D, 0), p.t2 = Eigen::Vector2d(0.5 * d.D, 0.5 * std::sqrt(3.0) * d.D);
    p.neighbours = 6;
    return p;
  }

  Pattern ring_chain_pattern(const double R, const double r, const double spacing,
                             const unsigned int segments, const double row_spacing, const double density)
  {
    AssertThrow(R > 2 * r, dealii::ExcMessage("Ring chain: needs R > 2 r for the rings to link."));
    {
      // Neighbours must clear each other (spacing > R + r) and stay linked (spacing < 2 (R - r)):
      // an interval that is empty unless R > 3 r.
      std::ostringstream why;
      why << "Ring chain: the spacing must exceed R + r = " << R + r << " (the rings clear each other) and "
          << "stay below 2 (R - r) = " << 2 * (R - r) << " (they stay linked)";
      AssertThrow(R > 3 * r, dealii::ExcMessage(why.str() + "; with R = " + std::to_string(R) +
                                                " and r = " + std::to_string(r) +
                                                " no spacing does, which needs R > 3 r: a larger ring "
                                                "radius or a thinner tube."));
      why << "; it is " << spacing << ".";
      AssertThrow(spacing > R + r && spacing < 2 * (R - r), dealii::ExcMessage(why.str()));
    }
    AssertThrow(row_spacing > 2 * (R + r),
                dealii::ExcMessage("Ring chain: the rows must be more than 2 (R + r) apart."));
    Pattern p;
    p.name = "ring chain";
    p.shapes.push_back(torus_ring(R, r, segments, density));
    p.shape_of  = {0, 0};
    p.centres   = {Eigen::Vector3d::Zero(), Eigen::Vector3d(spacing, 0, 0)};
    p.rotations = {Eigen::Vector3d::Zero(), Eigen::Vector3d(M_PI / 2, 0, 0)};
    p.t1 = Eigen::Vector2d(2 * spacing, 0), p.t2 = Eigen::Vector2d(0, row_spacing);
    p.neighbours = 2;
    return p;
  }

  namespace
  {
    Eigen::VectorXd initial_state(const RigidAssembly &assembly, const std::vector<Eigen::Vector3d> &centres,
                                  const std::vector<Eigen::Vector3d> &rotations)
    {
      Eigen::VectorXd q = Eigen::VectorXd::Zero(assembly.n_unknowns());
      for (std::size_t b = 0; b < centres.size(); ++b)
        q.segment<3>(6 * b) = centres[b], q.segment<3>(6 * b + 3) = rotations[b];
      return q;
    }
  } // namespace

  PlacedAssembly periodic_cell(const Pattern &pattern, const std::vector<Eigen::Matrix2d> &strain_basis)
  {
    PlacedAssembly placed;
    auto assembly = std::make_shared<RigidAssembly>(pattern.shapes, pattern.shape_of, Placement::periodic);
    assembly->set_lattice(pattern.t1, pattern.t2, strain_basis);
    placed.q = initial_state(*assembly, pattern.centres, pattern.rotations);
    for (const auto &c : pattern.centres)
      placed.reference.emplace_back(c[0], c[1]);
    placed.assembly = assembly;
    return placed;
  }

  PlacedAssembly finite_patch(const Pattern &pattern, const unsigned int n_elements, const PatchShape shape,
                              const Placement placement)
  {
    AssertThrow(n_elements >= 1, dealii::ExcMessage("Patch: needs at least one element."));
    AssertThrow(placement != Placement::periodic,
                dealii::ExcMessage("Patch: a finite patch is not periodic."));
    auto norm = [&](const Eigen::Vector2d &x) {
      switch (shape)
        {
          case PatchShape::square: return x.lpNorm<Eigen::Infinity>();
          case PatchShape::hexagon:
            {
              double n = 0;
              for (int k = 0; k < 3; ++k)
                n = std::max(n, std::abs(x.dot(Eigen::Vector2d(std::cos(M_PI / 6 + k * M_PI / 3),
                                                               std::sin(M_PI / 6 + k * M_PI / 3)))));
              return n;
            }
          default: return x.norm();
        }
    };
    struct Candidate
    {
      double          key, angle;
      unsigned        element;
      Eigen::Vector3d centre;
    };
    std::vector<Candidate> candidates;
    const int              range = int(std::ceil(std::sqrt(double(n_elements)))) + 3;
    for (int i = -range; i <= range; ++i)
      for (int j = -range; j <= range; ++j)
        for (unsigned e = 0; e < pattern.centres.size(); ++e)
          {
            const Eigen::Vector2d o = i * pattern.t1 + j * pattern.t2;
            const Eigen::Vector3d c = pattern.centres[e] + Eigen::Vector3d(o[0], o[1], 0);
            const Eigen::Vector2d xy(c[0], c[1]);
            // Round the key so that elements of one ring of the patch tie exactly.
            candidates.push_back({std::round(norm(xy) * 1e6) / 1e6, std::atan2(xy[1], xy[0]), e, c});
          }
    std::sort(candidates.begin(), candidates.end(), [](const Candidate &x, const Candidate &y) {
      return x.key != y.key ? x.key < y.key : x.angle < y.angle;
    });
    AssertThrow(n_elements <= candidates.size(), dealii::ExcMessage("Patch: too many elements requested."));
    std::vector<unsigned>        shape_of;
    std::vector<Eigen::Vector3d> centres, rotations;
    PlacedAssembly               placed;
    for (unsigned k = 0; k < n_elements; ++k)
      {
        shape_of.push_back(pattern.shape_of[candidates[k].element]);
        centres.push_back(candidates[k].centre);
        rotations.push_back(pattern.rotations[candidates[k].element]);
        placed.reference.emplace_back(candidates[k].centre[0], candidates[k].centre[1]);
      }
    auto assembly   = std::make_shared<RigidAssembly>(pattern.shapes, shape_of, placement);
    placed.q        = initial_state(*assembly, centres, rotations);
    placed.assembly = assembly;
    return placed;
  }

  PlacedAssembly linked_ring_pair(const double R, const double r, const unsigned int segments,
                                  const double density)
  {
    AssertThrow(R > 0 && r > 0, dealii::ExcMessage("Ring pair: R and r must be positive."));
    AssertThrow(
        R >= 2 * r * (1 - 1e-9),
        dealii::ExcMessage("Ring pair: R = " + std::to_string(R) + " mm < 2 r = " + std::to_string(2 * r) +
                           " mm: a tube of diameter 2 r cannot pass through a hole of diameter 2 (R - r), so "
                           "the rings cannot be linked."));
    AssertThrow(
        R > 2 * r * (1 + 1e-9),
        dealii::ExcMessage("Ring pair: R = 2 r: the rings are locked tight. Their only linked state has "
                           "the tubes touching at both holes, with no free motion (range of centre distance "
                           "2 R - 4 r = 0), which an intersection-free model cannot start from."));
    PlacedAssembly placed;
    auto           assembly = std::make_shared<RigidAssembly>(
        std::vector<ElementShape>{torus_ring(R, r, segments, density)}, std::vector<unsigned>{0, 0});
    placed.q         = initial_state(*assembly, {Eigen::Vector3d::Zero(), Eigen::Vector3d(R, 0, 0)},
                                     {Eigen::Vector3d::Zero(), Eigen::Vector3d(M_PI / 2, 0, 0)});
    placed.reference = {Eigen::Vector2d::Zero(), Eigen::Vector2d(R, 0)};
    placed.assembly  = assembly;
    return placed;
  }

  std::vector<Eigen::Vector3d> centreline(const RigidAssembly &assembly, const Eigen::VectorXd &q,
                                          const unsigned body, const std::array<int, 2> image)
  {
    std::vector<Eigen::Vector3d> x;
    for (const unsigned i : assembly.shape(body).loop)
      x.push_back(assembly.world_point(q, body, assembly.shape(body).points[i], image));
    return x;
  }

  Links find_links(const RigidAssembly &assembly, const Eigen::VectorXd &q)
  {
    Links links;
    links.per_element.assign(assembly.n_bodies(), 0);
    for (const auto &[a, b, image] : assembly.body_pairs(q, 0.0))
      if (linking_number(centreline(assembly, q, a), centreline(assembly, q, b, image)) != 0)
        {
          links.pairs.emplace_back(a, b, image);
          ++links.per_element[a], ++links.per_element[b];
        }
    return links;
  }

  void check_initial_state(const RigidAssembly &assembly, const Eigen::VectorXd &q, const double separation)
  {
    const auto gap = assembly.smallest_gap(q, separation + 1e-9);
    if (gap.gap > separation)
      return;
    std::ostringstream message;
    message << "Pattern: elements " << gap.body_a << " and " << gap.body_b;
    if (gap.image[0] != 0 || gap.image[1] != 0)
      message << " (image " << gap.image[0] << ", " << gap.image[1] << ")";
    message << (gap.gap < 0 ? " overlap" : " are too close") << " in the initial pattern (surface gap "
            << gap.gap << " mm, the model needs more than " << separation
            << " mm); increase the spacing or reduce the tube radius.";
    AssertThrow(false, dealii::ExcMessage(message.str()));
  }
} // namespace nlmech::dim
