#include <deal.II/base/exceptions.h>

#include <nlmech/models/dynamics/elastic_solids.h>
#include <nlmech/models/dynamics/mechanism.h>
#include <nlmech/models/dynamics/spring_network.h>
#include <nlmech/models/scaled_energy.h>
#include <nlmech/solvers/hbm/design_parameters.h>

#include <cmath>

namespace nlmech
{
  namespace
  {
    /// The Model with its term i replaced (masses and fixed unknowns kept).
    void replace_term(Model &model, const std::size_t i, std::shared_ptr<const EnergyTerm> term)
    {
      AssertThrow(i < model.terms().size(),
                  dealii::ExcMessage("Design: no energy term " + std::to_string(i) + "."));
      Model rebuilt(model.n_unknowns());
      for (std::size_t t = 0; t < model.terms().size(); ++t)
        rebuilt.add_term(t == i ? term : model.terms()[t]);
      rebuilt.lumped_mass() = model.lumped_mass();
      for (const auto &f : model.fixed())
        rebuilt.fix(f.first, f.second);
      model = std::move(rebuilt);
    }

    /// The weight m g of an added point mass as an energy term of the model (-m g . x), m shared
    /// with the parameter that sets it: the structure's own gravity term holds only its masses.
    class AddedWeight : public EnergyTerm
    {
    public:
      AddedWeight(Eigen::VectorXd weight_per_kg, std::shared_ptr<const double> mass)
          : weight(std::move(weight_per_kg))
          , mass(std::move(mass))
      {
      }
      std::string name() const override { return "added weight"; }
      double      value(const Eigen::VectorXd &x) const override { return -*mass * weight.dot(x); }
      void add_gradient(const Eigen::VectorXd &, Eigen::VectorXd &g) const override { g -= *mass * weight; }
      void add_hessian(const Eigen::VectorXd &, Triplets &) const override {}
      bool has_series() const override { return true; }
      void add_gradient_series_coefficient(const std::vector<Eigen::VectorXd> &, unsigned int,
                                           Eigen::VectorXd &) const override
      {
      }

    private:
      Eigen::VectorXd               weight;
      std::shared_ptr<const double> mass;
    };

    class PointMass : public DesignParameter
    {
    public:
      PointMass(std::string name, Model &model, std::vector<std::size_t> dofs, double initial, double lower,
                double upper, Eigen::VectorXd gravity)
          : DesignParameter(std::move(name), lower, upper)
          , model(model)
          , dofs(std::move(dofs))
          , gravity(std::move(gravity))
          , current(initial)
      {
        AssertThrow(!this->dofs.empty(), dealii::ExcMessage("Design: a point mass needs unknowns."));
        for (const std::size_t d : this->dofs)
          {
            AssertThrow(d < model.n_unknowns(),
                        dealii::ExcMessage("Design: a point mass on a missing unknown."));
            base.push_back(model.lumped_mass()[Eigen::Index(d)]);
          }
        if (this->gravity.size() > 0)
          {
            // Its weight: g on the listed unknowns, as a term of the model the parameter changes.
            Eigen::VectorXd w = Eigen::VectorXd::Zero(this->gravity.size());
            for (const std::size_t d : this->dofs)
              w[Eigen::Index(d)] = this->gravity[Eigen::Index(d)];
            model.add_term(std::make_shared<AddedWeight>(w, weight_mass));
          }
        set(initial);
      }
      double value() const override { return current; }
      void   set(const double m) override
      {
        current = m, *weight_mass = m;
        for (std::size_t i = 0; i < dofs.size(); ++i)
          model.lumped_mass()[Eigen::Index(dofs[i])] = base[i] + m;
      }
      Eigen::VectorXd mass_change(const std::size_t n) const override
      {
        Eigen::VectorXd d = Eigen::VectorXd::Zero(Eigen::Index(n));
        for (const std::size_t i : dofs)
          d[Eigen::Index(i)] = 1;
        return d;
      }
      bool changes_force() const override { return gravity.size() > 0; }
      void add_force_change(const HarmonicBalance &, const Eigen::VectorXd &, const Eigen::VectorXd &,
                            const double, const double, Eigen::VectorXd &df) const override
      {
        // The weight m g is constant: the static part of the force (harmonic 0).
        for (const std::size_t i : dofs)
          df[Eigen::Index(i)] += gravity[Eigen::Index(i)];
      }

    private:
      Model                   &model;
      std::vector<std::size_t> dofs;
      Eigen::VectorXd          gravity;
      std::vector<double>      base;
      double                   current;
      std::shared_ptr<double>  weight_mass = std::make_shared<double>(0.0);
    };

    /// The point forces' amplitude factor (phase = false) or a phase offset added to them.
    class ForceParameter : public DesignParameter
    {
    public:
      ForceParameter(std::string name, std::vector<HarmonicForce> &forces, std::vector<std::size_t> which,
                     const bool phase, double lower, double upper)
          : DesignParameter(std::move(name), lower, upper)
          , forces(forces)
          , which(std::move(which))
          , phase(phase)
          , current(phase ? 0.0 : 1.0)
      {
        for (const std::size_t i : this->which)
          {
            AssertThrow(i < forces.size(), dealii::ExcMessage("Design: no such point force."));
            base.push_back({forces[i].amplitude, forces[i].phase});
          }
      }
      double value() const override { return current; }
      void   set(const double p) override
      {
        current = p;
        for (std::size_t k = 0; k < which.size(); ++k)
          if (phase)
            forces[which[k]].phase = base[k].second + p;
          else
            forces[which[k]].amplitude = p * base[k].first;
      }
      bool changes_force() const override { return true; }
      void add_force_change(const HarmonicBalance &hb, const Eigen::VectorXd &, const Eigen::VectorXd &,
                            const double theta, const double, Eigen::VectorXd &df) const override
      {
        // f = s a cos(theta + phi): d/d(factor) = s a_0 cos(...), d/d(offset) = -s a sin(...).
        for (std::size_t k = 0; k < which.size(); ++k)
          {
            const HarmonicForce &f = forces[which[k]];
            const double         a = phase ? f.amplitude : base[k].first;
            df[Eigen::Index(f.dof)] +=
                hb.excitation_scale() * a * (phase ? -std::sin(theta + f.phase) : std::cos(theta + f.phase));
          }
      }

    private:
      std::vector<HarmonicForce>            &forces;
      std::vector<std::size_t>               which;
      std::vector<std::pair<double, double>> base; // amplitude, phase as declared
      bool                                   phase;
      double                                 current;
    };

    class DriveAmplitude : public DesignParameter
    {
    public:
      DriveAmplitude(std::string name, std::vector<HarmonicDrive> &drives, double lower, double upper)
          : DesignParameter(std::move(name), lower, upper)
          , drives(drives)
          , base(drives)
      {
        AssertThrow(!drives.empty(), dealii::ExcMessage("Design: the drive amplitude needs a drive."));
      }
      double value() const override { return factor; }
      void   set(const double p) override
      {
        factor = p;
        for (std::size_t k = 0; k < drives.size(); ++k)
          {
            drives[k].amplitude = p * base[k].amplitude;
            for (std::size_t h = 0; h < base[k].sine.size(); ++h)
              drives[k].sine[h] = p * base[k].sine[h];
            for (std::size_t h = 0; h < base[k].cosine.size(); ++h)
              drives[k].cosine[h] = p * base[k].cosine[h];
          }
      }
      bool changes_force() const override { return true; }
      void add_force_change(const HarmonicBalance &hb, const Eigen::VectorXd &x, const Eigen::VectorXd &v,
                            const double theta, const double omega, Eigen::VectorXd &df) const override
      {
        // Penalty drives pull with k (target - x): df = k d(target)/dp. Prescribed drives move their
        // unknowns: df = -d(grad E + D_beta K v)/dx dx_p - D_beta K dv_p for dx_p, dv_p the motion.
        const double    s  = hb.excitation_scale();
        Eigen::VectorXd dx = Eigen::VectorXd::Zero(x.size()), dv = Eigen::VectorXd::Zero(x.size());
        bool            prescribed = false;
        for (const auto &d : base)
          if (d.stiffness > 0)
            df[Eigen::Index(d.dof)] += d.stiffness * s * d.motion(theta);
          else
            dx[Eigen::Index(d.dof)] = s * d.motion(theta),
            dv[Eigen::Index(d.dof)] = s * d.velocity(theta, omega), prescribed = true;
        if (!prescribed)
          return;
        const Model &model = hb.model();
        const double beta  = hb.parameters().rayleigh_stiffness;
        df -= model.hessian(x) * dx;
        if (beta > 0)
          df -= beta * (model.directional_hessian(x, v) * dx + model.hessian_vector_product(x, dv));
      }

    private:
      std::vector<HarmonicDrive>      &drives;
      const std::vector<HarmonicDrive> base;
      double                           factor = 1;
    };

    class TermModulus : public DesignParameter
    {
    public:
      TermModulus(std::string name, Model &model, const std::size_t term, const double modulus, double lower,
                  double upper)
          : DesignParameter(std::move(name), lower, upper)
          , inner(model.terms().at(term))
          , factor(std::make_shared<double>(1.0))
          , modulus(modulus)
      {
        AssertThrow(modulus > 0, dealii::ExcMessage("Design: the initial modulus must be positive."));
        replace_term(model, term, std::make_shared<ScaledEnergyTerm>(inner, factor));
      }
      double value() const override { return *factor * modulus; }
      void   set(const double E) override { *factor = E / modulus; }
      bool   changes_force() const override { return true; }
      void   add_force_change(const HarmonicBalance &hb, const Eigen::VectorXd &x, const Eigen::VectorXd &v,
                              const double, const double, Eigen::VectorXd &df) const override
      {
        // f = -s grad E(x) - D_beta s H(x) v with s = E / E_0.
        Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
        inner->add_gradient(x, g);
        const double beta = hb.parameters().rayleigh_stiffness;
        if (beta > 0)
          inner->add_hessian_vector_product(x, beta * v, g);
        df -= g / modulus;
      }

    private:
      std::shared_ptr<const EnergyTerm> inner;
      std::shared_ptr<double>           factor;
      double                            modulus;
    };

    using ScaledPlane = ScaledElements<PlaneTriangleElements>;

    class ElementModulus : public DesignParameter
    {
    public:
      ElementModulus(std::string name, std::shared_ptr<const ScaledPlane> elements,
                     std::vector<std::size_t> group, double modulus, double lower, double upper)
          : DesignParameter(std::move(name), lower, upper)
          , elements(std::move(elements))
          , group(std::move(group))
          , modulus(modulus)
      {
      }
      double value() const override { return (*elements->factors)[group.front()] * modulus; }
      void   set(const double E) override
      {
        for (const std::size_t e : group)
          (*elements->factors)[e] = E / modulus;
      }
      bool changes_force() const override { return true; }
      void add_force_change(const HarmonicBalance &hb, const Eigen::VectorXd &x, const Eigen::VectorXd &v,
                            const double, const double, Eigen::VectorXd &df) const override
      {
        const double beta = hb.parameters().rayleigh_stiffness;
        for (const std::size_t e : group)
          add_element_force_derivatives(elements->inner, e, x, v, -1.0 / modulus, -beta / modulus, df);
      }

    private:
      std::shared_ptr<const ScaledPlane> elements;
      std::vector<std::size_t>           group;
      double                             modulus;
    };

    /// A mechanism's elements (link springs, rigid links) with their data shared with (and changed
    /// by) the design parameters.
    template <typename Elements>
    struct SharedElements
    {
      static constexpr std::size_t    n_dofs = Elements::n_dofs;
      std::shared_ptr<Elements>       data;
      std::size_t                     n_elements() const { return data->n_elements(); }
      std::array<std::size_t, n_dofs> dofs(const std::size_t e) const { return data->dofs(e); }
      template <typename S>
      S energy(const std::array<S, n_dofs> &x, const std::size_t e) const
      {
        return data->energy(x, e);
      }
    };
    using SharedSprings = SharedElements<AttachedSpringElements>;
    using SharedLinks   = SharedElements<SpringElements<2>>;

    /// One datum of one link spring: an attachment coordinate (0-3: u_a, w_a, u_b, w_b), the rest
    /// length (4) or the stiffness (5).
    class SpringParameter : public DesignParameter
    {
    public:
      SpringParameter(std::string name, std::shared_ptr<AttachedSpringElements> springs, std::size_t spring,
                      unsigned int datum, double lower, double upper)
          : DesignParameter(std::move(name), lower, upper)
          , springs(std::move(springs))
          , spring(spring)
          , datum(datum)
      {
      }
      double value() const override { return springs->data(spring)[datum]; }
      void   set(const double p) override
      {
        if (datum < 4)
          springs->local[spring][datum] = p;
        else if (datum == 4)
          springs->rest_length[spring] = p;
        else
          springs->stiffness[spring] = p;
      }
      bool changes_force() const override { return true; }
      void add_force_change(const HarmonicBalance &hb, const Eigen::VectorXd &x, const Eigen::VectorXd &v,
                            const double, const double, Eigen::VectorXd &df) const override
      {
        // f = -grad E - D_beta H v, differentiated in the datum q by nested forward AD: the
        // innermost level carries d/dq, the middle one d/de along v (H v), the outer one d/dx.
        using Q             = Sacado::Fad::SFad<double, 1>;
        using V             = Sacado::Fad::SFad<Q, 1>;
        using X             = Sacado::Fad::SFad<V, AttachedSpringElements::n_dofs>;
        constexpr auto   N  = AttachedSpringElements::n_dofs;
        const auto       ds = springs->dofs(spring);
        std::array<X, N> local;
        for (std::size_t i = 0; i < N; ++i)
          {
            V along(Q(x[Eigen::Index(ds[i])]));
            along.resizeAndZero(1);
            along.fastAccessDx(0) = Q(v.size() > 0 ? v[Eigen::Index(ds[i])] : 0.0);
            local[i]              = X(N, i, along);
          }
        const auto       values = springs->data(spring);
        std::array<X, 6> data;
        for (unsigned int k = 0; k < 6; ++k)
          data[k] = X(V(k == datum ? Q(1, 0, values[k]) : Q(values[k])));
        const X      energy = AttachedSpringElements::energy_of(local, data);
        const double beta   = hb.parameters().rayleigh_stiffness;
        for (std::size_t i = 0; i < N; ++i)
          df[Eigen::Index(ds[i])] -= energy.dx(i).val().dx(0) + beta * energy.dx(i).dx(0).dx(0);
      }

    private:
      std::shared_ptr<AttachedSpringElements> springs;
      std::size_t                             spring;
      unsigned int                            datum;
    };

    /// The length L of one rigid link, E = k_l / 2 (|x_b - x_a| - L)^2: the link's force grows by
    /// k_l n per unit of L (n the unit vector a -> b) and its stiffness damping by
    /// beta k_l / |d| (I - n n^T)(v_b - v_a), both on b and with the opposite sign on a.
    class LinkLength : public DesignParameter
    {
    public:
      LinkLength(std::string name, std::shared_ptr<SpringElements<2>> links, std::size_t link, double lower,
                 double upper)
          : DesignParameter(std::move(name), lower, upper)
          , links(std::move(links))
          , link(link)
      {
      }
      double value() const override { return links->springs[link].rest_length; }
      void   set(const double L) override { links->springs[link].rest_length = L; }
      bool   changes_force() const override { return true; }
      void   add_force_change(const HarmonicBalance &hb, const Eigen::VectorXd &x, const Eigen::VectorXd &v,
                              const double, const double, Eigen::VectorXd &df) const override
      {
        const Spring<2>      &s = links->springs[link];
        const std::size_t     a = 2 * s.a, b = 2 * s.b;
        const Eigen::Vector2d d(x[Eigen::Index(b)] - x[Eigen::Index(a)],
                                x[Eigen::Index(b + 1)] - x[Eigen::Index(a + 1)]);
        const double          length = d.norm();
        if (!(length > 0))
          return;
        const Eigen::Vector2d n      = d / length;
        Eigen::Vector2d       change = s.stiffness * n;
        const double          beta   = hb.parameters().rayleigh_stiffness;
        if (beta != 0 && v.size() > 0)
          {
            const Eigen::Vector2d dv(v[Eigen::Index(b)] - v[Eigen::Index(a)],
                                     v[Eigen::Index(b + 1)] - v[Eigen::Index(a + 1)]);
            change += beta * s.stiffness / length * (dv - n * n.dot(dv));
          }
        for (Eigen::Index i = 0; i < 2; ++i)
          df[Eigen::Index(b) + i] += change[i], df[Eigen::Index(a) + i] -= change[i];
      }

    private:
      std::shared_ptr<SpringElements<2>> links;
      std::size_t                        link;
    };
  } // namespace

  std::shared_ptr<DesignParameter> make_spring_parameter(std::string name, Model &model,
                                                         const std::size_t spring, const unsigned int datum,
                                                         const double initial, const double lower,
                                                         const double upper)
  {
    AssertThrow(datum < 6, dealii::ExcMessage("Design: a spring datum is 0-3 (attachment), 4 (rest length) "
                                              "or 5 (stiffness)."));
    // The springs' term, replaced on first use by one whose data the parameters share.
    std::shared_ptr<AttachedSpringElements> shared;
    for (std::size_t t = 0; t < model.terms().size() && !shared; ++t)
      if (const auto *d = dynamic_cast<const ElementEnergyTerm<SharedSprings> *>(model.terms()[t].get()))
        shared = d->elements().data;
      else if (const auto *a =
                   dynamic_cast<const ElementEnergyTerm<AttachedSpringElements> *>(model.terms()[t].get()))
        {
          shared = std::make_shared<AttachedSpringElements>(a->elements());
          replace_term(model, t,
                       std::make_shared<ElementEnergyTerm<SharedSprings>>(a->name() + " (design)",
                                                                          SharedSprings{shared}));
        }
    AssertThrow(shared, dealii::ExcMessage("Design: spring parameters need a mechanism with link springs."));
    AssertThrow(spring < shared->n_elements(),
                dealii::ExcMessage("Design: no spring " + std::to_string(spring) + " (the mechanism has " +
                                   std::to_string(shared->n_elements()) + ")."));
    AssertThrow(
        datum < 4 || lower >= 0,
        dealii::ExcMessage("Design: a spring's rest length and stiffness bounds must not be negative."));
    auto p = std::make_shared<SpringParameter>(std::move(name), shared, spring, datum, lower, upper);
    p->set(initial);
    return p;
  }

  std::shared_ptr<DesignParameter> make_link_length_parameter(std::string name, Model &model,
                                                              const std::size_t link, const double initial,
                                                              const double lower, const double upper)
  {
    AssertThrow(lower > 0, dealii::ExcMessage("Design: a link length's lower bound must be positive."));
    // The rigid links' term, replaced on first use by one whose lengths the parameters share.
    std::shared_ptr<SpringElements<2>> shared;
    for (std::size_t t = 0; t < model.terms().size() && !shared; ++t)
      if (const auto *d = dynamic_cast<const ElementEnergyTerm<SharedLinks> *>(model.terms()[t].get()))
        shared = d->elements().data;
      else if (const auto *a = dynamic_cast<const SpringTerm<2> *>(model.terms()[t].get());
               a && a->name().rfind("rigid links", 0) == 0)
        {
          shared = std::make_shared<SpringElements<2>>(a->elements());
          replace_term(
              model, t,
              std::make_shared<ElementEnergyTerm<SharedLinks>>(a->name() + " (design)", SharedLinks{shared}));
        }
    AssertThrow(shared, dealii::ExcMessage("Design: link length parameters need a mechanism's rigid links."));
    AssertThrow(link < shared->n_elements(),
                dealii::ExcMessage("Design: no link " + std::to_string(link) + " (the mechanism has " +
                                   std::to_string(shared->n_elements()) + ")."));
    AssertThrow(!shared->springs[link].axial && shared->springs[link].cubic == 0,
                dealii::ExcMessage("Design: the link is not a plain length penalty."));
    auto p = std::make_shared<LinkLength>(std::move(name), shared, link, lower, upper);
    p->set(initial);
    return p;
  }

  std::shared_ptr<DesignParameter> make_point_mass_parameter(std::string name, Model &model,
                                                             std::vector<std::size_t> dofs,
                                                             const double initial, const double lower,
                                                             const double upper, Eigen::VectorXd gravity)
  {
    AssertThrow(lower >= 0, dealii::ExcMessage("Design: a point mass's lower bound must not be negative."));
    AssertThrow(gravity.size() == 0 || gravity.size() == Eigen::Index(model.n_unknowns()),
                dealii::ExcMessage("Design: gravity needs one value per unknown."));
    return std::make_shared<PointMass>(std::move(name), model, std::move(dofs), initial, lower, upper,
                                       std::move(gravity));
  }

  std::shared_ptr<DesignParameter> make_force_amplitude_parameter(std::string                 name,
                                                                  std::vector<HarmonicForce> &forces,
                                                                  std::vector<std::size_t>    which,
                                                                  const double lower, const double upper)
  {
    return std::make_shared<ForceParameter>(std::move(name), forces, std::move(which), false, lower, upper);
  }

  std::shared_ptr<DesignParameter> make_force_phase_parameter(std::string                 name,
                                                              std::vector<HarmonicForce> &forces,
                                                              std::vector<std::size_t>    which,
                                                              const double lower, const double upper)
  {
    return std::make_shared<ForceParameter>(std::move(name), forces, std::move(which), true, lower, upper);
  }

  std::shared_ptr<DesignParameter> make_drive_amplitude_parameter(std::string                 name,
                                                                  std::vector<HarmonicDrive> &drives,
                                                                  const double lower, const double upper)
  {
    return std::make_shared<DriveAmplitude>(std::move(name), drives, lower, upper);
  }

  std::shared_ptr<DesignParameter> make_term_modulus_parameter(std::string name, Model &model,
                                                               const std::size_t term, const double modulus,
                                                               const double lower, const double upper)
  {
    return std::make_shared<TermModulus>(std::move(name), model, term, modulus, lower, upper);
  }

  std::vector<std::shared_ptr<DesignParameter>> make_element_modulus_parameters(
      const std::string &name, Model &model, const std::vector<std::vector<std::size_t>> &groups,
      const std::vector<double> &moduli, const double lower_factor, const double upper_factor)
  {
    AssertThrow(groups.size() == moduli.size(), dealii::ExcMessage("Design: one modulus per element group."));
    std::size_t term = model.terms().size();
    for (std::size_t t = 0; t < model.terms().size(); ++t)
      if (dynamic_cast<const PlaneTriangleTerm *>(model.terms()[t].get()))
        term = t;
    AssertThrow(term < model.terms().size(),
                dealii::ExcMessage("Design: a modulus per element needs a plane-triangle model."));
    const auto &plane  = static_cast<const PlaneTriangleTerm &>(*model.terms()[term]).elements();
    auto        scaled = std::make_shared<ScaledPlane>();
    scaled->inner      = plane;
    scaled->factors    = std::make_shared<std::vector<double>>(plane.n_elements(), 1.0);
    std::vector<std::shared_ptr<DesignParameter>> out;
    for (std::size_t g = 0; g < groups.size(); ++g)
      {
        AssertThrow(!groups[g].empty(), dealii::ExcMessage("Design: an empty element group."));
        for (const std::size_t e : groups[g])
          AssertThrow(e < plane.n_elements(), dealii::ExcMessage("Design: a missing element."));
        out.push_back(std::make_shared<ElementModulus>(name + "_" + std::to_string(g), scaled, groups[g],
                                                       moduli[g], lower_factor * moduli[g],
                                                       upper_factor * moduli[g]));
      }
    replace_term(model, term,
                 std::make_shared<ElementEnergyTerm<ScaledPlane>>("plane StVK triangles (design)", *scaled));
    return out;
  }
} // namespace nlmech
