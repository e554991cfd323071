#pragma once
// Interlocking patterns: a unit cell (elements with centres and rotation vectors, two lattice
// vectors) from which periodic cells and finite patches are made. Four materials (thesis Fig. 4.5;
// the text gives no dimensions, so the defaults here are plausible millimetre sizes for 3D printing,
// documented with each scene's .prm file):
//   4-in-1 chainmail   flat rings in columns tilted alternately by +-tau about the column axis; each
//                      links the four rings of the neighbouring columns at (+-a, +-b/2).
//   threefold          wavy rings z = h cos 6 (t - 15 deg) on a triangular lattice of spacing D;
//                      every crossing with a neighbour is at a crest or a trough, so each element
//                      passes over and under each of its six neighbours.
//   torus knot         (p, q) torus-knot tubes on a square lattice, each linking four neighbours;
//                      the default (3, 4) knot turns three times about the symmetry axis and four
//                      times around the tube (fourfold symmetric; a true knot, p and q coprime and
//                      both at least 2).
//   scale mail         the threefold base with a hexagonal plate above it on one side.
// Linked pairs are found and checked by their linking number, so a pattern whose elements do not
// interlock as designed is rejected.

#include <nlmech/dim/rigid_assembly.h>

#include <memory>
#include <string>
#include <vector>

namespace nlmech::dim
{
  struct Pattern
  {
    std::string                  name;
    std::vector<ElementShape>    shapes;
    std::vector<unsigned>        shape_of;  // per element of the cell
    std::vector<Eigen::Vector3d> centres;   // in the cell [mm]
    std::vector<Eigen::Vector3d> rotations; // rotation vectors
    Eigen::Vector2d              t1 = Eigen::Vector2d::Zero(), t2 = Eigen::Vector2d::Zero();
    unsigned int                 neighbours = 0; // links per element by design
  };

  struct FourInOneDimensions
  {
    double       R = 3, r = 0.5, tilt = 30 * M_PI / 180, a = 2, b = 7.5;
    unsigned int segments = 64;
  };
  struct ThreefoldDimensions
  {
    double       R = 4, r = 0.5, h = 0.8, D = 5.657;
    unsigned int segments = 96;
  };
  /// A (3,4) torus knot (a true knot, fourfold symmetric) on a torus of radii R and a; each
  /// element links its four lattice neighbours once through the outer lobes (D = 9.5 mm: centreline
  /// gap 1.13 mm at rest, no link across the diagonal).
  struct TorusKnotDimensions
  {
    unsigned int p = 3, q = 4;
    double       R = 4, a = 1.5, r = 0.5, D = 9.5, phase = 0;
    unsigned int segments = 192;
  };
  struct ScaleMailDimensions
  {
    double R = 4, r = 0.5, h = 0.8, D = 5.657, plate_radius = 2.45, plate_thickness = 0.8, plate_height = 2.3;
    unsigned int segments = 96;
  };

  Pattern four_in_one_pattern(const FourInOneDimensions &d, double density);
  Pattern threefold_pattern(const ThreefoldDimensions &d, double density);
  Pattern torus_knot_pattern(const TorusKnotDimensions &d, double density);
  Pattern scale_mail_pattern(const ScaleMailDimensions &d, double density);

  /// A chain of linked torus rings along x (alternately in the xy and xz planes, `spacing` apart),
  /// rows `row_spacing` apart and not linked across: the validation material with a closed-form
  /// limit, the largest stretch along the chain 2 (R - r) / spacing - 1 (needs R + r < spacing <
  /// 2 (R - r), so that rings of one orientation clear each other and neighbours are linked).
  Pattern ring_chain_pattern(double R, double r, double spacing, unsigned int segments, double row_spacing,
                             double density);

  /// An assembly with its starting state and every element's reference in-plane position.
  struct PlacedAssembly
  {
    std::shared_ptr<RigidAssembly> assembly;
    Eigen::VectorXd                q;
    std::vector<Eigen::Vector2d>   reference;
  };

  /// The pattern's cell as a periodic assembly with strain parameters on the given basis (all zero
  /// at the start).
  PlacedAssembly periodic_cell(const Pattern &pattern, const std::vector<Eigen::Matrix2d> &strain_basis);

  enum class PatchShape
  {
    disk,
    square,
    hexagon
  };
  /// The n elements of the tiled pattern nearest to the origin in the patch's norm (Euclidean,
  /// max-norm, hexagonal), centred on the origin.
  PlacedAssembly finite_patch(const Pattern &pattern, unsigned int n_elements, PatchShape shape,
                              Placement placement = Placement::free);

  /// Two linked torus rings (R, r): ring A in the xy plane at the origin, ring B in the xz plane at
  /// (R, 0, 0). Rejects R < 2 r (a tube of diameter 2 r cannot pass through a hole of diameter
  /// 2 (R - r)) and R = 2 r (locked tight: the only linked state touches, with no free motion).
  PlacedAssembly linked_ring_pair(double R, double r, unsigned int segments, double density);

  /// The world centreline polyline of one element (or its image) at a state.
  std::vector<Eigen::Vector3d> centreline(const RigidAssembly &assembly, const Eigen::VectorXd &q,
                                          unsigned body, std::array<int, 2> image = {{0, 0}});

  /// Element pairs (with image offsets) whose centrelines are linked, and the count per element.
  struct Links
  {
    std::vector<std::tuple<unsigned, unsigned, std::array<int, 2>>> pairs;
    std::vector<unsigned>                                           per_element;
  };
  Links find_links(const RigidAssembly &assembly, const Eigen::VectorXd &q);

  /// Checks a starting state: no two elements closer than `separation` (names the pair otherwise).
  void check_initial_state(const RigidAssembly &assembly, const Eigen::VectorXd &q, double separation);
} // namespace nlmech::dim
