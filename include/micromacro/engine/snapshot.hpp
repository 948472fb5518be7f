#pragma once
// The engine's side of the averaging: a simulation's present state frozen into the
// PackingSnapshot that every average works on.
#include <type_traits>

#include "micromacro/averaging/snapshot.hpp"
#include "micromacro/engine/contact_view.hpp"

namespace micromacro {

/// The packing and contacts of a simulation at its present state (forces and each contact's
/// stiffnesses as for_each_contact reports them).
template <class Sim>
PackingSnapshot<Sim::dimension> take_snapshot(const Sim& sim) {
    constexpr int dim = Sim::dimension;
    PackingSnapshot<dim> s;
    s.domain = sim.domain();
    const auto& p = sim.particles();
    for (std::size_t i = 0; i < p.size(); ++i) {  // stored in Real, analysed in double
        s.position.push_back(convert<double>(p.position()[i]));
        s.velocity.push_back(convert<double>(p.velocity()[i]));
        s.radius.push_back(p.radius()[i]);
        s.mass.push_back(p.mass()[i]);
    }
    sim.for_each_contact([&](const ContactView<dim>& v) {
        ContactRecord<dim> c;
        if (v.wall) {
            c.i = v.i;
            c.j = v.j;
            c.wall = true;
            c.normal = v.geometry.normal;
            c.branch = v.branch;
            c.overlap = v.geometry.overlap;
            c.point = s.position[v.i] - v.branch;
            s.domain.wrap(c.point);
            c.share_i = 1.0;
        } else {
            c = detail::pair_record<dim>(v.i, v.j, s.position[v.i], s.radius[v.i], s.radius[v.j], v.branch, s.domain);
        }
        c.normal_force = v.normal_force;
        c.tangential_force = v.tangential_force;
        c.k = v.stiffness;
        c.kt = v.tangential_stiffness;
        c.sliding = v.sliding;
        s.contacts.push_back(c);
    });
    if constexpr (Sim::has_walls) {  // the averages know planar walls; other shapes are left out
        if constexpr (std::remove_cvref_t<decltype(sim.walls())>::planes)
            for (const auto& w : sim.walls()) s.walls.push_back({w.normal, w.offset, w.force});
    }
    return s;
}

}  // namespace micromacro
