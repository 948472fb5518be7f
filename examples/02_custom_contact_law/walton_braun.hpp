#pragma once
// A contact law written outside the library, as a user writes one: the hysteretic linear spring
// of Walton and Braun (1986), the loading branch of Luding's adhesive model without adhesion.
// The contact loads with stiffness k1 (plastic) and unloads and reloads with k2 >= k1 (elastic)
// from the largest overlap it reached, delta_max:
//     f = k2 (delta - delta_0) >= 0, delta_0 = (1 - k1/k2) delta_max,
// which equals k1 delta while loading. In a head-on collision the force lasts
// (pi/2) (sqrt(m*/k1) + sqrt(m*/k2)) and the rebound is e = sqrt(k1/k2), at every speed.
//
// Everything the engine needs is here (micromacro::ContactLawModel): the flags, the history
// type with its default "not in contact", the force of one step, the state for analysis, the
// stiffness bound for the stable time step, and the history operations.
#include <algorithm>

#include <micromacro/micromacro.hpp>

namespace example {

namespace mm = micromacro;

/// What a contact remembers: the largest overlap it reached (0: not in contact).
template <int dim>
struct PlasticHistory {
    double max_overlap = 0.0;
};
/// The same seen from the other particle of the pair (the overlap is symmetric).
template <int dim>
PlasticHistory<dim> seen_from_partner(const PlasticHistory<dim>& h) {
    return h;
}

class WaltonBraun {
public:
    static constexpr bool has_tangential = false;  // smooth particles: no rotation, no friction
    static constexpr bool has_history = true;
    static constexpr bool needs_rotation = false;
    template <int dim>
    using History = PlasticHistory<dim>;

    WaltonBraun(double k1, double k2) : k1_(k1), k2_(k2) {
        mm::require_positive(k1, "loading stiffness k1", "give it in N/m");
        if (!(k2 >= k1)) mm::throw_input_error("unloading stiffness k2 = ", k2, " is below k1 = ", k1, "; use k2 >= k1");
    }

    template <bool track, int dim>
    mm::ContactForce<dim> force(const mm::ContactKinematics<dim>& c, History<dim>& h) const {
        h.max_overlap = std::max(h.max_overlap, c.overlap);
        mm::ContactForce<dim> out;
        out.normal = normal_force(c, h);
        return out;
    }
    template <int dim>
    mm::NormalForce normal_force(const mm::ContactKinematics<dim>& c) const {
        return {k1_ * c.overlap, 0.0};  // a contact seen without its history: loading
    }
    template <int dim>
    mm::ContactState<dim> state(const mm::ContactKinematics<dim>& c, const History<dim>* h) const {
        mm::ContactState<dim> s;
        if (!h) {
            s.normal = normal_force(c);
            s.stiffness = k1_;
            return s;
        }
        s.normal = normal_force(c, *h);
        const double unloaded = rest_overlap<dim>(*h);
        s.normal_energy = c.overlap > unloaded ? 0.5 * k2_ * (c.overlap - unloaded) * (c.overlap - unloaded) : 0.0;
        s.stiffness = k2_;  // unloading and reloading
        return s;
    }
    mm::StiffnessBound stiffness_bound(double, double) const { return {k2_, 0.0}; }

    template <int dim>
    bool touched(const History<dim>& h) const {
        return h.max_overlap > 0.0;
    }
    template <int dim>
    mm::Vec<dim> opening_force(const mm::ContactKinematics<dim>&, const History<dim>&) const {
        return mm::Vec<dim>::Zero();
    }
    // Evaluating the same instant twice leaves delta_max as it was, and there is no tangential
    // spring to load: nothing to do.
    template <int dim>
    void step_back(const mm::Vec<dim>&, const mm::Vec<dim>&, double, double, History<dim>&) const {}
    template <int dim>
    void displace(const mm::Vec<dim>&, const mm::Vec<dim>&, History<dim>&) const {}

private:
    template <int dim>
    double rest_overlap(const History<dim>& h) const {  // delta_0
        return (1.0 - k1_ / k2_) * h.max_overlap;
    }
    template <int dim>
    mm::NormalForce normal_force(const mm::ContactKinematics<dim>& c, const History<dim>& h) const {
        return {std::max(k2_ * (c.overlap - rest_overlap<dim>(h)), 0.0), 0.0};
    }

    double k1_, k2_;
};
static_assert(mm::ContactLawModel<WaltonBraun>);

}  // namespace example
