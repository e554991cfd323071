#pragma once
// The geometry of one rigid interlocking element in its body frame, as swept-sphere primitives:
// segments (a tube of radius r around a centreline segment) and triangles (a slab of half-thickness
// r around a flat triangle). Tubes around polyline centrelines give exact distances for segment
// chains; circles are sampled by polygons whose vertices lie on the circle (the chords are inside
// it by at most R (1 - cos(pi / N)), stated by `centreline_error`). Lengths in millimetres.

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

namespace nlmech::dim
{
  struct ElementShape
  {
    std::string                          name;
    std::vector<Eigen::Vector3d>         points; // body frame, centre of mass at the origin
    std::vector<std::array<unsigned, 2>> segments;
    std::vector<double>                  segment_radius;
    std::vector<std::array<unsigned, 3>> triangles;
    std::vector<double>                  triangle_radius;
    std::vector<unsigned>                loop;                 // the closed centreline (for linking numbers)
    double                               mass             = 0; // kg
    double                               centreline_error = 0; // mm, polygon vs exact curve
    /// Largest distance of any surface point from the body origin (points plus radius).
    double bounding_radius() const;
    /// Centre of mass of the primitives (uniform density); the generators move it to the origin.
    Eigen::Vector3d centroid() const;
    /// Volume of the primitives (tubes pi r^2 l, slabs 2 r A; overlaps counted twice) [mm^3].
    double volume() const;
  };

  /// A ring: circle of radius R in the body xy plane, tube radius r, N segments. Requires r < R.
  ElementShape torus_ring(double R, double r, unsigned int N, double density);

  /// A wavy ring: centreline (R cos t, R sin t, h cos k (t - phase)), tube radius r, N segments.
  /// With k even, identical wavy rings whose circles overlap are linked (one passes over and under
  /// the other at the two crossings); k = 6 gives the six-neighbour rings of the threefold chainmail.
  ElementShape wave_ring(double R, double r, double h, unsigned int k, double phase, unsigned int N,
                         double density);

  /// A (p, q) torus-knot tube: ((R + a cos q t) cos p t, (R + a cos q t) sin p t, -a sin q t),
  /// t in [0, 2 pi), tube radius r, N segments. Requires gcd(p, q) = 1, a < R.
  ElementShape torus_knot(unsigned int p, unsigned int q, double R, double a, double r, unsigned int N,
                          double density);

  /// A scale-mail element: a base ring (the wavy ring above with k = 6 when h > 0, flat when h = 0)
  /// with a flat hexagonal plate of circumradius `plate_radius` and thickness `plate_thickness` held
  /// at height `plate_height` above the ring's plane on one side, so the element is not symmetric
  /// through its thickness. The plate's flats face the directions 0, 60, ... degrees. The plate is
  /// rigidly part of the element; its supports are not modelled as contact geometry.
  ElementShape scale_mail_element(double R, double r, double h, unsigned int N, double plate_radius,
                                  double plate_thickness, double plate_height, double density);

  /// An element of arbitrary shape from a triangulated surface: a gmsh .msh file or a .geo source
  /// (meshed in 2D with elements of at most `mesh_size`, 0: the file's own sizes; STL, OBJ, STEP
  /// and other inputs go through a .geo that merges them). Every triangle becomes a swept-sphere
  /// slab of radius `skin_radius` (0: the bare triangles; exact triangle distances either way).
  /// For a closed, consistently oriented surface the mass is density times the enclosed volume
  /// and the origin is the solid's centre of mass; otherwise the surface counts as a shell of
  /// thickness 2 skin_radius. The element has no centreline, so its links are not checked.
  /// `written` is the path as the user wrote it, for messages.
  ElementShape triangle_mesh_element(const std::string &file, double skin_radius, double density,
                                     double mesh_size = 0, const std::string &written = "");

  /// Linking number of two closed polylines (exact for polylines: the sum of the signed solid
  /// angles of segment pairs over 4 pi, Klenin and Langowski 2000), rounded to the nearest integer.
  int linking_number(const std::vector<Eigen::Vector3d> &a, const std::vector<Eigen::Vector3d> &b);

  /// Moves the shape's points so that its centre of mass is at the origin (returns the shift).
  Eigen::Vector3d centre_shape(ElementShape &shape);
} // namespace nlmech::dim
