#pragma once
// A bounding-sphere hierarchy over the primitives of one rigid element, built once in its body
// frame. Spheres are unchanged by rigid motions, so two elements in any relative placement are
// searched by traversing both trees together with each node's centre moved to the world on the fly
// (no rebuild, no refit). Used by the pair search and the exact gaps of `RigidAssembly`: with
// triangulated elements of hundreds of triangles the all-pairs search was O(n_a n_b) per query.
//
// CGAL's AABB tree was considered: it answers queries of one primitive against a tree in a fixed
// frame, so under rigid motion it would need one query per primitive of the other element (or a
// rebuild per state); the tree-against-tree traversal here prunes whole subtrees of both.

#include <Eigen/Core>

#include <limits>
#include <utility>
#include <vector>

namespace nlmech::dim
{
  class SphereTree
  {
  public:
    SphereTree() = default;
    /// Tree over items with body-frame bounding spheres (centre, radius), leaves of at most
    /// `leaf_size` items.
    SphereTree(const std::vector<Eigen::Vector3d> &centres, const std::vector<double> &radii,
               unsigned int leaf_size = 4);

    std::size_t size() const { return item_radius.size(); }
    bool        empty() const { return nodes.empty(); }

    /// A rigid placement x -> R x + t of a tree's body frame.
    struct Placement
    {
      Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
      Eigen::Vector3d t = Eigen::Vector3d::Zero();
      Eigen::Vector3d operator()(const Eigen::Vector3d &x) const { return R * x + t; }
    };

    /// Calls visit(i, j) for every item i of `a` and item j of `b` whose placed spheres are closer
    /// than threshold() (sphere gap |c_i - c_j| - r_i - r_j). threshold is read again after every
    /// visit, so a search for the smallest gap can tighten it as it goes.
    template <typename Visit, typename Threshold>
    static void for_close_pairs(const SphereTree &a, const Placement &pa, const SphereTree &b,
                                const Placement &pb, const Threshold &threshold, const Visit &visit);

  private:
    struct Node
    {
      Eigen::Vector3d centre;
      double          radius = 0;
      unsigned int    first = 0, count = 0; // leaf: items order[first, first + count)
      int             left = -1, right = -1;
    };
    std::vector<Node>            nodes;
    std::vector<unsigned int>    order;
    std::vector<Eigen::Vector3d> item_centre;
    std::vector<double>          item_radius;

    int build(unsigned int first, unsigned int count, unsigned int leaf_size);
  };

  template <typename Visit, typename Threshold>
  void SphereTree::for_close_pairs(const SphereTree &a, const Placement &pa, const SphereTree &b,
                                   const Placement &pb, const Threshold &threshold, const Visit &visit)
  {
    if (a.empty() || b.empty())
      return;
    struct Entry
    {
      int             na, nb;
      Eigen::Vector3d ca, cb; // placed node centres
    };
    std::vector<Entry> stack;
    stack.push_back({0, 0, pa(a.nodes[0].centre), pb(b.nodes[0].centre)});
    while (!stack.empty())
      {
        const Entry e = stack.back();
        stack.pop_back();
        const Node &A = a.nodes[std::size_t(e.na)], &B = b.nodes[std::size_t(e.nb)];
        if ((e.ca - e.cb).norm() - A.radius - B.radius >= threshold())
          continue;
        const bool leaf_a = A.left < 0, leaf_b = B.left < 0;
        if (leaf_a && leaf_b)
          {
            for (unsigned int u = A.first; u < A.first + A.count; ++u)
              {
                const unsigned int    i  = a.order[u];
                const Eigen::Vector3d ci = pa(a.item_centre[i]);
                for (unsigned int v = B.first; v < B.first + B.count; ++v)
                  {
                    const unsigned int j = b.order[v];
                    if ((ci - pb(b.item_centre[j])).norm() - a.item_radius[i] - b.item_radius[j] <
                        threshold())
                      visit(i, j);
                  }
              }
            continue;
          }
        // Descend into the larger node (or the one that is not a leaf); the nearer child last, so
        // that it is visited first and a shrinking threshold prunes its sibling.
        if (!leaf_a && (leaf_b || A.radius >= B.radius))
          {
            const Node     &L = a.nodes[std::size_t(A.left)], &Rn = a.nodes[std::size_t(A.right)];
            Eigen::Vector3d cl = pa(L.centre), cr = pa(Rn.centre);
            const bool      left_nearer = (cl - e.cb).norm() - L.radius < (cr - e.cb).norm() - Rn.radius;
            if (left_nearer)
              stack.push_back({A.right, e.nb, cr, e.cb}), stack.push_back({A.left, e.nb, cl, e.cb});
            else
              stack.push_back({A.left, e.nb, cl, e.cb}), stack.push_back({A.right, e.nb, cr, e.cb});
          }
        else
          {
            const Node     &L = b.nodes[std::size_t(B.left)], &Rn = b.nodes[std::size_t(B.right)];
            Eigen::Vector3d cl = pb(L.centre), cr = pb(Rn.centre);
            const bool      left_nearer = (cl - e.ca).norm() - L.radius < (cr - e.ca).norm() - Rn.radius;
            if (left_nearer)
              stack.push_back({e.na, B.right, e.ca, cr}), stack.push_back({e.na, B.left, e.ca, cl});
            else
              stack.push_back({e.na, B.left, e.ca, cl}), stack.push_back({e.na, B.right, e.ca, cr});
          }
      }
  }
} // namespace nlmech::dim
