// Strain-space boundaries from samples on a known surface: an ellipsoid about the rest state (and a
// star-shaped, non-convex one). The mesh must be closed, contain the rest state, have no flipped
// triangles, enclose the ellipsoid's volume to the sampling error, give signed distances of the
// right sign, and survive a write/read round trip; malformed files are rejected clearly.
#include <nlmech/dim/strain_space_boundary.h>

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>

using namespace nlmech::dim;

namespace
{
  /// Directions on the sphere (a latitude-longitude grid plus the poles), on the surface
  /// rest + r(d) (a, b, c) . d.
  std::vector<Eigen::Vector3d> star_samples(const Eigen::Vector3d &rest, const Eigen::Vector3d &axes,
                                            const double bumps, const unsigned n)
  {
    std::vector<Eigen::Vector3d> s;
    for (unsigned i = 1; i < n; ++i)
      for (unsigned j = 0; j < 2 * n; ++j)
        {
          const double          th = M_PI * i / n, ph = M_PI * j / n;
          const Eigen::Vector3d d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
          s.push_back(rest + (1 + bumps * std::cos(3 * ph) * std::sin(th)) * axes.cwiseProduct(d));
        }
    s.push_back(rest + Eigen::Vector3d(0, 0, axes[2]));
    s.push_back(rest - Eigen::Vector3d(0, 0, axes[2]));
    return s;
  }
} // namespace

TEST(StrainSpaceBoundary, EllipsoidIsClosedContainsRestAndHasItsVolume)
{
  const Eigen::Vector3d rest(0.01, -0.02, 0.0), axes(0.05, 0.03, 0.02);
  const auto            samples  = star_samples(rest, axes, 0.0, 24);
  const auto            boundary = star_shaped_boundary(samples, rest, axes);
  const auto            c        = check(boundary);
  const double          exact    = 4.0 / 3.0 * M_PI * axes.prod();
  std::printf("ellipsoid: %zu vertices, %zu triangles, volume %.6e (exact %.6e, %.2f %%)\n", c.vertices,
              c.triangles, c.volume, exact, 100 * (c.volume / exact - 1));
  EXPECT_TRUE(c.closed);
  EXPECT_TRUE(c.contains_rest);
  EXPECT_EQ(c.flipped, 0u);
  EXPECT_EQ(c.vertices, samples.size());
  EXPECT_NEAR(c.volume, exact, 0.02 * exact); // inscribed polyhedron: a little smaller
  EXPECT_LT(c.volume, exact);
  // Signed distance: inside negative, outside positive, about the analytic gap along an axis.
  EXPECT_LT(signed_distance(boundary, rest), 0);
  EXPECT_NEAR(signed_distance(boundary, rest + Eigen::Vector3d(0.08, 0, 0)), 0.03, 1e-3);
}

TEST(StrainSpaceBoundary, NonConvexStarShapedSetKeepsItsDents)
{
  const Eigen::Vector3d rest     = Eigen::Vector3d::Zero(), axes(1, 1, 1);
  const auto            boundary = star_shaped_boundary(star_samples(rest, axes, 0.4, 24), rest, axes);
  const auto            c        = check(boundary);
  EXPECT_TRUE(c.closed);
  EXPECT_TRUE(c.contains_rest);
  EXPECT_EQ(c.flipped, 0u);
  // A dent (cos 3 phi = -1 at phi = 60 deg on the equator, radius 0.6) stays a dent: a point at
  // radius 0.8 there is outside, although it is inside the convex hull.
  const Eigen::Vector3d dent(0.8 * std::cos(M_PI / 3), 0.8 * std::sin(M_PI / 3), 0);
  EXPECT_GT(signed_distance(boundary, dent), 0.1);
}

TEST(StrainSpaceBoundary, FileRoundTripAndMalformedFiles)
{
  const auto boundary =
      star_shaped_boundary(star_samples(Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 2, 3), 0, 8),
                           Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
  const std::string path = "boundary_round_trip.ssb";
  write_boundary(path, boundary, "test boundary\nsecond comment line");
  const auto back = read_boundary(path);
  ASSERT_EQ(back.vertices.size(), boundary.vertices.size());
  ASSERT_EQ(back.triangles.size(), boundary.triangles.size());
  for (std::size_t i = 0; i < back.vertices.size(); ++i)
    EXPECT_EQ(back.vertices[i], boundary.vertices[i]);
  EXPECT_EQ(back.triangles, boundary.triangles);
  EXPECT_EQ(back.kind, boundary.kind);
  // A triangle pointing at a missing vertex, and a truncated file.
  std::ofstream("bad.ssb")
      << "nlmech-strain-space-boundary 1\nkind stretch\naxes a b c\nrest 0 0 0\nvertices 1\n"
         "0 0 0\ntriangles 1\n0 1 2\n";
  try
    {
      read_boundary("bad.ssb");
      FAIL() << "accepted a triangle with missing vertices";
    }
  catch (const std::exception &e)
    {
      // deal.II wraps its messages: compare with the whitespace collapsed.
      std::string text;
      for (const char ch : std::string(e.what()))
        if (!std::isspace(static_cast<unsigned char>(ch)) || (!text.empty() && text.back() != ' '))
          text += std::isspace(static_cast<unsigned char>(ch)) ? ' ' : ch;
      EXPECT_NE(text.find("refers to a missing vertex"), std::string::npos) << text;
    }
  std::ofstream("truncated.ssb") << "nlmech-strain-space-boundary 1\nkind stretch\n";
  EXPECT_THROW(read_boundary("truncated.ssb"), std::exception);
  // Samples in one plane through the rest state span nothing.
  std::vector<Eigen::Vector3d> flat;
  for (int k = 0; k < 12; ++k)
    flat.emplace_back(std::cos(k * 0.5), std::sin(k * 0.5), 0);
  EXPECT_THROW(star_shaped_boundary(flat, Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()), std::exception);
}
