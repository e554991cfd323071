// The four interlocking patterns: every starting state is intersection-free, and every element is
// linked (linking number of the centrelines) with exactly the neighbours its design says, in the
// periodic cell and at the centre of a finite patch; patches have the requested sizes.
#include <nlmech/dim/patterns.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

using namespace nlmech::dim;

namespace
{
  std::vector<Pattern> materials()
  {
    const double density = 1.24e-6; // PLA [kg/mm^3]
    return {four_in_one_pattern({}, density), threefold_pattern({}, density), torus_knot_pattern({}, density),
            scale_mail_pattern({}, density)};
  }
  std::vector<Eigen::Matrix2d> full_basis()
  {
    Eigen::Matrix2d Bx, By, Bxy;
    Bx << 1, 0, 0, 0;
    By << 0, 0, 0, 1;
    Bxy << 0, 1, 1, 0;
    return {Bx, By, Bxy};
  }
} // namespace

TEST(Patterns, PeriodicCellsAreIntersectionFreeAndLinkedAsDesigned)
{
  for (const auto &pattern : materials())
    {
      const auto cell  = periodic_cell(pattern, full_basis());
      const auto gap   = cell.assembly->smallest_gap(cell.q);
      const auto links = find_links(*cell.assembly, cell.q);
      std::printf("%-20s cell: %zu elements, smallest gap %.3f mm, links per element:", pattern.name.c_str(),
                  cell.assembly->n_bodies(), gap.gap);
      for (const unsigned l : links.per_element)
        std::printf(" %u", l);
      std::printf("\n");
      EXPECT_GT(gap.gap, 0.05) << pattern.name;
      for (const unsigned l : links.per_element)
        EXPECT_EQ(l, pattern.neighbours) << pattern.name;
    }
}

TEST(Patterns, HexagonalPatchesHave19To61ElementsAndALinkedCentre)
{
  for (const auto &pattern : materials())
    for (const unsigned n : {19u, 37u, 61u})
      {
        const auto patch = finite_patch(pattern, n, PatchShape::hexagon);
        ASSERT_EQ(patch.assembly->n_bodies(), n);
        const auto gap   = patch.assembly->smallest_gap(patch.q);
        const auto links = find_links(*patch.assembly, patch.q);
        EXPECT_GT(gap.gap, 0.05) << pattern.name;
        EXPECT_EQ(links.per_element[0], pattern.neighbours) << pattern.name << " " << n;
        if (n == 19)
          std::printf("%-20s 19-patch: smallest gap %.3f mm, %zu links\n", pattern.name.c_str(), gap.gap,
                      links.pairs.size());
      }
}

TEST(Patterns, TorusKnotTubesThatIntersectThemselvesAreRejected)
{
  // The default (3,4) knot (R 4, a 1.5): its strands pass each other 2.41 mm apart (centrelines,
  // sampled independently in Python), so tubes up to r ~ 1.2 mm clear themselves and thicker ones
  // do not.
  const double density = 1.24e-6;
  EXPECT_NO_THROW(torus_knot(3, 4, 4, 1.5, 0.5, 192, density));
  EXPECT_NO_THROW(torus_knot(3, 4, 4, 1.5, 1.1, 192, density));
  try
    {
      torus_knot(3, 4, 4, 1.5, 1.3, 192, density);
      ADD_FAILURE() << "a self-intersecting knot tube was accepted";
    }
  catch (const std::exception &e)
    {
      EXPECT_NE(std::string(e.what()).find("intersects itself"), std::string::npos) << e.what();
    }
  // The (1,4) coil of the earlier default: four turns of radius 1 about the core, 4.8 mm apart
  // where they come closest; a tube of radius 2.5 fills that.
  EXPECT_NO_THROW(torus_knot(1, 4, 4, 1, 0.4, 128, density));
  EXPECT_THROW(torus_knot(1, 4, 4, 1, 2.5, 128, density), std::exception);
}
