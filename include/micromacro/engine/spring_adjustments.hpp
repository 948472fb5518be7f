#pragma once
// The tangential springs moved outside a force evaluation: stepped back before the same instant
// is evaluated again, and loaded by an imposed affine deformation.
#include <cstddef>

#include "micromacro/contact/contact_list.hpp"
#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/domain.hpp"
#include "micromacro/engine/contact_response.hpp"
#include "micromacro/engine/pair_loop.hpp"
#include "micromacro/engine/wall_contacts.hpp"
#include "micromacro/walls/shape.hpp"

namespace micromacro::detail {

/// Every history of `pairs` and `wall_contacts` (null without walls) back to where the last
/// evaluation, made with step `evaluated_dt`, found it (ContactLawIn::step_back; for the built-in
/// spring, CundallStrack::step_back), so that an evaluation of the same instant with step dt does
/// not advance it twice. `in` holds the particle arrays.
template <bool rotation, int dim, class Real, class Law, class History, class WallSet>
void step_back_springs(const ContactLoopInput<dim, Real, History>& in, const Domain<dim>& domain, const Law& law,
                       ContactList<History>& pairs, const WallSet* walls, ContactList<History>* wall_contacts,
                       double evaluated_dt, double dt) {
    using V = Vec<dim>;
    for (std::size_t c = 0; c < pairs.size(); ++c) {
        const auto [i, j] = pairs.pairs()[c];
        const V d = domain.separation(convert<double>(in.x[i]), convert<double>(in.x[j]));
        const double dist = d.norm();
        if (dist == 0.0) continue;
        const V n = d * (1.0 / dist);
        const V vr = pair_point_velocity<rotation>(in, domain, i, j, d, n);
        law.step_back(n, vr, evaluated_dt, dt, pairs.history(c));
    }
    if (!walls) return;
    for (std::size_t c = 0; c < wall_contacts->size(); ++c) {
        const auto [i, w] = wall_contacts->pairs()[c];
        const auto& wall = (*walls)[w];
        const V n = wall.nearest(convert<double>(in.x[i])).normal;
        law.step_back(n, wall_point_velocity<rotation>(in, i, wall, n), evaluated_dt, dt, wall_contacts->history(c));
    }
}

/// Every spring takes up the tangential part of its contact's branch change under x -> F x,
/// as if the partners had moved there (walls null without walls; a frictionless wall's
/// contacts have no spring to load). `in` holds the particle arrays before the map.
template <int dim, class Real, class Law, class History, class WallSet>
void load_springs_affinely(const Eigen::Matrix<double, dim, dim>& F, const ContactLoopInput<dim, Real, History>& in,
                           const Domain<dim>& domain, const Law& law, ContactList<History>& pairs, const WallSet* walls,
                           ContactList<History>* wall_contacts) {
    using V = Vec<dim>;
    auto load = [&](History& h, const V& l) {
        const V n = l.normalized(), moved = F * l - l;
        law.displace(n, V(moved - n * n.dot(moved)), h);
    };
    for (std::size_t c = 0; c < pairs.size(); ++c) {
        const auto [i, j] = pairs.pairs()[c];
        load(pairs.history(c), domain.separation(convert<double>(in.x[i]), convert<double>(in.x[j])));
    }
    if (!walls) return;
    for (std::size_t c = 0; c < wall_contacts->size(); ++c) {
        const auto [i, w] = wall_contacts->pairs()[c];
        const auto& wall = (*walls)[w];
        if (wall.frictionless) continue;
        const WallPoint<dim> point = wall.nearest(convert<double>(in.x[i]));
        load(wall_contacts->history(c), V(point.distance * point.normal));
    }
}

}  // namespace micromacro::detail
