#pragma once
// The contacts of the present state as analysis sees them: every touching pair and wall
// contact as a ContactView, with the forces the law gives for that state (see
// ContactLawIn::state). The force loops never come here.
#include <cstddef>

#include "micromacro/contact/contact_list.hpp"
#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/domain.hpp"
#include "micromacro/engine/contact_response.hpp"
#include "micromacro/engine/pair_loop.hpp"
#include "micromacro/engine/wall_contacts.hpp"
#include "micromacro/walls/shape.hpp"

namespace micromacro::detail {

/// Calls f(ContactView) for every candidate of `pairs` with positive overlap, then every wall
/// candidate of `wall_contacts` that touches (`walls` and `wall_contacts` null without walls).
/// `in` holds the particle arrays (its pair and history pointers are not used). A frictionless
/// wall's contacts are shown to the law without history: normal part only.
template <bool rotation, int dim, class Real, class Law, class History, class WallSet, class F>
void visit_contacts(const ContactLoopInput<dim, Real, History>& in, const Domain<dim>& domain, const Law& law,
                    const ContactList<History>& pairs, const WallSet* walls, const ContactList<History>* wall_contacts, F&& f) {
    using V = Vec<dim>;
    static const History none{};  // for a law without history
    auto history = [&](const ContactList<History>& list, [[maybe_unused]] std::size_t c) -> const History* {
        if constexpr (Law::has_history) return &list.history(c);
        else return &none;
    };
    // The analysis sees the present state: no step to advance by.
    constexpr double dt = 0.0;
    for (std::size_t c = 0; c < pairs.size(); ++c) {
        const auto [i, j] = pairs.pairs()[c];
        const V d = domain.separation(convert<double>(in.x[i]), convert<double>(in.x[j]));
        const double dist = d.norm(), reach = double(in.r[i]) + double(in.r[j]);
        if (!(dist < reach) || dist == 0.0) continue;
        const V n = d * (1.0 / dist);  // as the force loop computes it
        f(contact_view(law, i, j, false, pair_kinematics<rotation>(in, domain, i, j, d, n, dist, dt), d, history(pairs, c)));
    }
    if (!walls) return;
    for (std::size_t c = 0; c < wall_contacts->size(); ++c) {
        const auto [i, w] = wall_contacts->pairs()[c];
        const auto& wall = (*walls)[w];
        const WallPoint<dim> point = wall.nearest(convert<double>(in.x[i]));
        if (!(point.distance < in.r[i])) continue;
        f(contact_view(law, i, w, true, wall_kinematics<rotation>(in, i, wall, point, dt), V(point.distance * point.normal),
                       wall.frictionless ? nullptr : history(*wall_contacts, c)));
    }
}

}  // namespace micromacro::detail
