#pragma once
// Native-scale model of a discrete interlocking material (thesis section 4.3.1, eq. 4.3.1): rigid
// elements with six unknowns each, q_i = (x_i, omega_i) (centre of mass and rotation vector), plus
// a few global parameters that place the elements:
//   free        x_i as given;
//   periodic    a unit cell whose images are shifted by the lattice vectors t_k = U(eps) tbar_k,
//               U = I + sum_j eps_j B_j (in-plane, symmetric basis B_j), so that the periodicity
//               conditions x_j = x_i + t_ij, omega_j = omega_i (eq. 4.3.2) hold by construction and
//               the macroscopic strain eps is an unknown (the target-strain problem, eq. 4.3.3);
//   paraboloid  centres on z = A x^2 + B y^2 + C x y (+ the body's z unknown, usually fixed to 0),
//               kappa = (A, B, C) the unknowns (eq. 4.3.4).
// Contact is the incremental-potential-contact barrier on the surface gaps between the elements'
// swept-sphere primitives, with an optional minimum separation (print clearance). The broad phase
// sees periodic images. `max_safe_step` is a conservative-advancement continuous collision check, so
// no state along an accepted step intersects. Lengths in mm, forces in N, energies in N mm.

#include <nlmech/dim/element_shape.h>
#include <nlmech/dim/primitive_distance.h>
#include <nlmech/dim/sphere_tree.h>
#include <nlmech/models/energy_term.h>

#include <Eigen/Core>

#include <array>
#include <limits>
#include <memory>
#include <mutex>
#include <tuple>
#include <vector>

namespace nlmech::dim
{
  enum class Placement
  {
    free,
    periodic,
    paraboloid
  };

  struct ContactSettings
  {
    double dhat             = 0.01; // barrier activation gap [mm]
    double kappa            = 1.0;  // barrier stiffness [N mm]
    double separation       = 0.0;  // minimum gap kept between surfaces (print clearance) [mm]
    bool   project_hessians = true; // per-pair Hessians projected to positive semi-definite
  };

  /// One primitive pair within reach, reduced to its distance type; `owner[k]` tells whether point k
  /// belongs to body a (0) or to the image of body b (1).
  struct ContactPair
  {
    unsigned int                   body_a = 0, body_b = 0;
    std::array<int, 2>             image{{0, 0}}; // lattice offset of body b
    DistanceType                   type = DistanceType::point_point;
    std::array<Eigen::Vector3d, 4> body_points;
    std::array<unsigned char, 4>   owner{};
    double                         radius_sum = 0; // swept radii plus the separation
    double                         gap        = 0; // surface gap at the state it was found
  };

  class RigidAssembly
  {
  public:
    RigidAssembly(std::vector<ElementShape> shapes, std::vector<unsigned int> shape_of_body,
                  Placement placement = Placement::free);

    /// A periodic cell: lattice vectors tbar1, tbar2 (in the xy plane) and the in-plane strain
    /// basis B_j (symmetric 2x2), so that the images of the cell follow t_k = (I + sum eps_j B_j) tbar_k.
    void set_lattice(const Eigen::Vector2d &tbar1, const Eigen::Vector2d &tbar2,
                     const std::vector<Eigen::Matrix2d> &strain_basis);

    /// Paraboloid placement: (A, B, C) = sum_j p_j K_j over the given basis (default: the unit
    /// vectors, p = (A, B, C)).
    void                                set_curvature_basis(const std::vector<Eigen::Vector3d> &basis);
    const std::vector<Eigen::Vector3d> &curvature_basis() const { return curvature; }

    std::size_t n_bodies() const { return shape_of.size(); }
    std::size_t n_parameters() const;
    std::size_t n_unknowns() const { return 6 * n_bodies() + n_parameters(); }
    std::size_t parameter_index(unsigned int j) const { return 6 * n_bodies() + j; }
    Placement   placement() const { return place; }

    const ElementShape                 &shape(unsigned int body) const { return shapes[shape_of[body]]; }
    const std::vector<Eigen::Matrix2d> &strain_basis() const { return basis; }
    Eigen::Vector2d reference_lattice(unsigned int k) const { return k == 0 ? tbar1 : tbar2; }

    /// Centre of body i (image offset included) and a body-frame point in the world.
    Eigen::Vector3d centre(const Eigen::VectorXd &q, unsigned int body,
                           std::array<int, 2> image = {{0, 0}}) const;
    Eigen::Vector3d world_point(const Eigen::VectorXd &q, unsigned int body, const Eigen::Vector3d &p,
                                std::array<int, 2> image = {{0, 0}}) const;
    /// The current lattice vectors (periodic placement).
    Eigen::Vector2d lattice_vector(const Eigen::VectorXd &q, unsigned int k) const;
    /// U(eps) = I + sum eps_j B_j (periodic placement).
    Eigen::Matrix2d stretch(const Eigen::VectorXd &q) const;

    /// The surface gap of every primitive pair closer than `reach` (images included).
    std::vector<ContactPair> contact_pairs(const Eigen::VectorXd &q, double reach) const;
    /// Smallest exact surface gap between any two elements (crossing primitives give a negative
    /// gap of minus the radii), with the bodies involved; +inf when nothing is within `reach`.
    struct Gap
    {
      double             gap    = std::numeric_limits<double>::infinity();
      unsigned int       body_a = 0, body_b = 0;
      std::array<int, 2> image{{0, 0}};
    };
    Gap smallest_gap(const Eigen::VectorXd &q, double reach = std::numeric_limits<double>::infinity()) const;

    /// Largest alpha in (0, 1] such that no surface gap falls to zero along q + t dq, t in [0, alpha]
    /// (conservative advancement with a bound on every point's motion); a pair is not allowed below
    /// `keep` of its gap at the start of the step.
    double max_safe_step(const Eigen::VectorXd &q, const Eigen::VectorXd &dq, double separation,
                         double keep = 0.1) const;

    /// Per unknown, the squared length of motion a unit change causes somewhere in the assembly (1
    /// for positions, rho^2 for rotations, |tbar|^2 for lattice strains, r^4 for paraboloid
    /// curvatures): the metric that makes Newton's diagonal shift consistent across kinds of unknowns.
    Eigen::VectorXd motion_metric(const Eigen::VectorXd &q) const;

    /// The rotation matrix of a rotation vector.
    static Eigen::Matrix3d rotation(const Eigen::Vector3d &omega);

    template <typename S>
    Point<S> world_point(const S *q_body, const S *parameters, const std::array<int, 2> &image,
                         const Eigen::Vector3d &p) const;

    /// Edges (segments and triangle edges) and faces of a shape with their radii, and the points of
    /// faces' primitives, the lists the pair search runs over.
    struct Primitives
    {
      std::vector<std::array<unsigned, 2>>     edges;
      std::vector<double>                      edge_radius;
      std::vector<std::array<unsigned, 3>>     faces;
      std::vector<double>                      face_radius;
      std::vector<std::pair<unsigned, double>> vertices; // points of primitives, with radius (deduplicated)
    };

    /// Body pairs (a, b, image of b) whose bounding spheres come within `reach`.
    std::vector<std::tuple<unsigned, unsigned, std::array<int, 2>>> body_pairs(const Eigen::VectorXd &q,
                                                                               double reach) const;
    /// Exact surface gap between body a and the image of body b (radii subtracted); where it is at
    /// least `cutoff`, some value of at least `cutoff` (infinity when no primitive comes that close).
    double exact_gap(const Eigen::VectorXd &q, unsigned a, unsigned b, const std::array<int, 2> &image,
                     double cutoff = std::numeric_limits<double>::infinity()) const;
    /// Reference for tests and benchmarks, by checking every primitive pair (no pruning, O(n_a n_b)):
    /// the smallest exact gap between body a and the image of body b (as exact_gap without a
    /// cutoff) and the number of primitive pairs closer than `reach` (as contact_pairs for that pair).
    std::pair<double, std::size_t> all_pairs_gap(const Eigen::VectorXd &q, unsigned a, unsigned b,
                                                 const std::array<int, 2> &image, double reach) const;
    /// World positions of a body's (or its image's) points.
    std::vector<Eigen::Vector3d> world_points(const Eigen::VectorXd &q, unsigned body,
                                              std::array<int, 2> image = {{0, 0}}) const;

  private:
    std::vector<ElementShape> shapes;
    std::vector<Primitives>   primitives;
    /// Per shape, bounding-sphere trees (body frame) over its edges, faces and primitive points.
    struct Trees
    {
      SphereTree edges, faces, vertices;
    };
    std::vector<Trees> trees;
    /// Rigid placement of a body's (or its image's) frame in the world.
    SphereTree::Placement        placement_of(const Eigen::VectorXd &q, unsigned body,
                                              const std::array<int, 2> &image) const;
    std::vector<double>          reach_radius; // max |p| over a shape's points
    std::vector<unsigned int>    shape_of;
    Placement                    place;
    Eigen::Vector2d              tbar1 = Eigen::Vector2d::Zero(), tbar2 = Eigen::Vector2d::Zero();
    std::vector<Eigen::Matrix2d> basis;
    std::vector<Eigen::Vector3d> curvature{Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                                           Eigen::Vector3d::UnitZ()};

    int image_range() const;
  };

  /// Rodrigues' formula for R(omega) p, with a series near omega = 0 (smooth for forward AD).
  template <typename S>
  Point<S> rotate(const S *omega, const Eigen::Vector3d &p)
  {
    using std::cos;
    using std::sin;
    using std::sqrt;
    const S t2 = omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2];
    S       a, b; // R = I + a [w]x + b [w]x^2
    if (Sacado::ScalarValue<S>::eval(t2) < 1e-2)
      {
        a = 1.0 - t2 / 6.0 * (1.0 - t2 / 20.0 * (1.0 - t2 / 42.0 * (1.0 - t2 / 72.0)));
        b = 0.5 - t2 / 24.0 * (1.0 - t2 / 30.0 * (1.0 - t2 / 56.0 * (1.0 - t2 / 90.0)));
      }
    else
      {
        const S t = sqrt(t2);
        a         = sin(t) / t;
        b         = (1.0 - cos(t)) / t2;
      }
    const Point<S> w{{omega[0], omega[1], omega[2]}}, pp{{S(p[0]), S(p[1]), S(p[2])}};
    const Point<S> wp = cross(w, pp), wwp = cross(w, wp);
    return {{pp[0] + a * wp[0] + b * wwp[0], pp[1] + a * wp[1] + b * wwp[1], pp[2] + a * wp[2] + b * wwp[2]}};
  }

  template <typename S>
  Point<S> RigidAssembly::world_point(const S *q, const S *parameters, const std::array<int, 2> &image,
                                      const Eigen::Vector3d &p) const
  {
    Point<S> x = rotate(q + 3, p);
    Point<S> c{{q[0], q[1], q[2]}};
    if (place == Placement::periodic)
      {
        // Image offset i tbar1 + j tbar2 stretched by U(eps) (in-plane).
        const Eigen::Vector2d o = image[0] * tbar1 + image[1] * tbar2;
        S                     ox(o[0]), oy(o[1]);
        for (std::size_t j = 0; j < basis.size(); ++j)
          {
            ox += parameters[j] * (basis[j](0, 0) * o[0] + basis[j](0, 1) * o[1]);
            oy += parameters[j] * (basis[j](1, 0) * o[0] + basis[j](1, 1) * o[1]);
          }
        c[0] += ox, c[1] += oy;
      }
    else if (place == Placement::paraboloid)
      {
        S A(0), B(0), C(0);
        for (std::size_t j = 0; j < curvature.size(); ++j)
          A += parameters[j] * curvature[j][0], B += parameters[j] * curvature[j][1],
              C += parameters[j] * curvature[j][2];
        c[2] += A * q[0] * q[0] + B * q[1] * q[1] + C * q[0] * q[1];
      }
    return {{c[0] + x[0], c[1] + x[1], c[2] + x[2]}};
  }

  /// The contact barrier of an assembly as an energy term: sum over primitive pairs of
  /// b(gap - separation) (IPC); value, gradient and (optionally projected) Hessian by forward AD
  /// over the pair's two bodies and the placement parameters.
  class ContactBarrier : public EnergyTerm
  {
  public:
    ContactBarrier(std::shared_ptr<const RigidAssembly> assembly, ContactSettings settings);
    std::string name() const override { return "contact barrier"; }
    double      value(const Eigen::VectorXd &q) const override;
    void        add_gradient(const Eigen::VectorXd &q, Eigen::VectorXd &g) const override;
    void        add_hessian(const Eigen::VectorXd &q, Triplets &h) const override;
    bool        is_valid(const Eigen::VectorXd &q) const override;
    double      max_safe_step(const Eigen::VectorXd &q, const Eigen::VectorXd &dq) const override;

    const ContactSettings &settings() const { return contact; }
    void                   set_projection(bool project) { contact.project_hessians = project; }
    /// Broad- and narrow-phase searches run so far: value, gradient and Hessian at one state share
    /// one (the pairs of the last state are kept).
    std::size_t n_collision_searches() const;

  private:
    std::shared_ptr<const RigidAssembly> assembly;
    ContactSettings                      contact;
    /// The pairs within reach at q, separation added to their radii, from the last search if it
    /// was at the same state (bitwise).
    std::shared_ptr<const std::vector<ContactPair>>         pairs_at(const Eigen::VectorXd &q) const;
    mutable std::mutex                                      cache_mutex;
    mutable Eigen::VectorXd                                 cached_state;
    mutable std::shared_ptr<const std::vector<ContactPair>> cached_pairs;
    mutable std::size_t                                     searches = 0;
    template <typename S>
    S                    pair_energy(const ContactPair &pair, const std::array<S, 15> &v) const;
    std::array<long, 15> pair_dofs(const ContactPair &pair) const;
  };

  /// Linear potential of constant forces f_i on the bodies' centres (gravity, pulls): -sum f_i . x_i
  /// (centres through the placement, so on the paraboloid a vertical force acts on kappa too).
  class CentreForces : public EnergyTerm
  {
  public:
    CentreForces(std::shared_ptr<const RigidAssembly> assembly, std::vector<Eigen::Vector3d> forces);
    std::string name() const override { return "centre forces"; }
    double      value(const Eigen::VectorXd &q) const override;
    void        add_gradient(const Eigen::VectorXd &q, Eigen::VectorXd &g) const override;
    void        add_hessian(const Eigen::VectorXd &q, Triplets &h) const override;

  private:
    std::shared_ptr<const RigidAssembly> assembly;
    std::vector<Eigen::Vector3d>         forces;
  };

  /// 1/2 sum_j w_j (p_j - target_j)^2 on the placement parameters (eq. 4.3.3 and 4.3.4; w_j = 0 leaves
  /// p_j free).
  class ParameterTarget : public EnergyTerm
  {
  public:
    ParameterTarget(std::size_t first_index, std::vector<double> targets, std::vector<double> weights);
    std::string name() const override { return "parameter target"; }
    double      value(const Eigen::VectorXd &q) const override;
    void        add_gradient(const Eigen::VectorXd &q, Eigen::VectorXd &g) const override;
    void        add_hessian(const Eigen::VectorXd &q, Triplets &h) const override;
    void        set_targets(std::vector<double> t) { targets = std::move(t); }

  private:
    std::size_t         first;
    std::vector<double> targets, weights;
  };
} // namespace nlmech::dim
