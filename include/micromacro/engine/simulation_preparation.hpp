#pragma once
// BasicSimulation before it runs and when it fails: the thread count, the stability limit,
// prepare() with its checks of the scene, the neighbour-list rebuild, the spatial renumbering,
// the position resolution, and the report of a blow-up.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "micromacro/engine/simulation.hpp"
#include "micromacro/neighbors/skin.hpp"

namespace micromacro {

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline void BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::set_threads(int threads) {
    check_thread_count(threads);
    threads_ = threads;
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::stability_limit() const -> StabilityLimit {
    StabilityLimit limit;
    if (particles_.empty()) return limit;
    bool any_wall = false;
    if constexpr (has_walls) any_wall = walls_.size() > 0;
    const std::size_t n = particles_.size();
    const bool contacts = n > 1 || any_wall;  // else nothing to touch, but a drag may act
    // Each particle on its stiffest partner: a particle like itself (the lightest pair of a
    // polydisperse packing is at least as stable), or a wall when it is alone. The law bounds its
    // stiffness for that pair's effective radius and mass. A drag of the body forces (background
    // and affine damping) adds its rate to the contact's damping: on the pair's relative motion it
    // acts at each partner's rate; on the tangential one, which mixes sliding and turning, the
    // larger of the two rates bounds it.
    const double partners = n > 1 ? 2.0 : 1.0;
    const auto& r = particles_.radius();
    const auto& inverse_mass = particles_.template get<field::InverseMass>();
    for (std::size_t i = 0; i < n; ++i) {
        const double a = r[i], inv = inverse_mass[i];
        const auto [drag, spin_drag] = drag_rates(i);
        limit.tighten(std::min(Integrator::stability_limit(0.0, 0.5 * drag), Integrator::stability_limit(0.0, 0.5 * spin_drag)),
                      StabilityLimit::Cause::drag);
        if (!contacts) continue;
        const StiffnessBound b = law_.stiffness_bound(n > 1 ? 0.5 * a : a, 1.0 / (partners * inv));
        limit.tighten(normal_time_step_limit<Integrator>(b.normal_stiffness, b.normal_damping, partners * inv, drag),
                      StabilityLimit::Cause::normal_spring);
        if constexpr (has_tangential)
            limit.tighten(tangential_time_step_limit<Integrator>(b.tangential_stiffness, b.tangential_damping,
                                                                 partners * particles_.contact_point_mobility(i),
                                                                 std::max(drag, spin_drag)),
                          StabilityLimit::Cause::tangential_spring);
        if constexpr (has_walls) {  // a stress-controlled wall on one contact
            const double on_wall = law_.stiffness_bound(a, 1.0 / inv).normal_stiffness;
            for (std::size_t w = 0; w < walls_.size(); ++w)
                if (const auto* s = std::get_if<StressControlled>(&walls_[w].motion))
                    limit.tighten(stress_wall_time_step_limit(on_wall, s->mass, s->damping, inv), StabilityLimit::Cause::stress_wall, w);
        }
    }
    return limit;
}

/// The body forces' drag rates on particle i, translational and rotational (1/s), summed over
/// the policies that have a drag (drag_rate, as BackgroundDamping's).
template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::drag_rates(std::size_t i) const
    -> std::pair<double, double> {
    const double inv_m = particles_.template get<field::InverseMass>()[i];
    double inv_I = 0.0;
    if constexpr (rotation) inv_I = particles_.template get<field::InverseInertia>()[i];
    double drag = 0.0, spin_drag = 0.0;
    std::apply([&](const auto&... force) {
        [[maybe_unused]] auto add = [&](const auto& f) {
            if constexpr (requires { f.drag_rate(inv_m); }) {
                drag += f.drag_rate(inv_m);
                if constexpr (rotation) spin_drag += f.spin_drag_rate(inv_I);
            }
        };
        (add(force), ...);
    }, body_forces_);
    return {drag, spin_drag};
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::check_cell_motion(bool moving, bool tilted) const -> void {
    if (has_walls && moving)
        detail::throw_input_error("the periodic cell has a velocity gradient and the scene has walls; a moving cell drives a "
                                  "scene without walls (an element test): drive the walls by their motions instead");
    if (window_.any() && (tilted || moving))
        detail::throw_input_error("a distributed run's search window cannot follow a sheared or moving cell (docs/mpi.md)");
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::prepare() -> void {
    if (!(dt_ > 0.0))
        detail::throw_input_error("no time step set; call set_time_step(dt), e.g. dt = t_c / 50");
    const std::size_t n = particles_.size();
    if (n > std::numeric_limits<Index>::max() - 1)
        detail::throw_input_error("too many particles: ", n);
    const auto& r = particles_.radius();
    if (!(skin_ > 0.0)) skin_ = default_skin(r);
    interaction_range_ = n ? interaction_range(r, skin_) : 0.0;
    if (n) domain_.check_interaction_range(interaction_range_);
    check_cell_motion(domain_.moving(), domain_.tilted());
    check_position_resolution();
    if (const StabilityLimit limit = stability_limit(); dt_ > limit.seconds && !allow_unstable_) {
        using C = StabilityLimit::Cause;
        const char* what = limit.cause == C::stress_wall         ? "stress-controlled wall "
                           : limit.cause == C::drag              ? "the body forces' drag on the lightest particle"
                           : limit.cause == C::tangential_spring ? "the tangential spring of the lightest particles' contact"
                                                                 : "the normal spring and dashpot of the lightest particles' contact";
        const char* also = limit.cause == C::stress_wall ? ", a heavier wall or a weaker damper (StressControlled's mass, damping)"
                           : limit.cause == C::drag      ? ", less drag"
                                                         : "";
        detail::throw_input_error("time step dt = ", dt_, " s exceeds the stability limit ", limit.seconds, " s of ", what,
                                  limit.cause == C::stress_wall ? std::to_string(limit.wall) + " on one particle" : std::string(),
                                  "; use dt <= ", limit.seconds, " (the paper uses t_c/50)", also,
                                  ", or allow_unstable_time_step(true) to run anyway");
    }
    for (std::size_t i = 0; i < n; ++i) {  // a moving cell's wrap takes the image's velocity off (Domain::wrap)
        auto& x = particles_.position()[i];
        auto& v = particles_.template get<field::Velocity>()[i];
        V wrapped = convert<double>(x), velocity = convert<double>(v);
        domain_.wrap(wrapped, velocity);
        x = convert<Real>(wrapped), v = convert<Real>(velocity);
    }
    if constexpr (has_walls) {
        for (std::size_t w = 0; w < walls_.size(); ++w) {
            for (int k = 0; k < dim; ++k) {
                if (!domain_.periodic(k)) continue;
                // Distances from a wall are not wrapped: a plane must run along the periodic axis,
                // and a surface of another shape has no such guarantee.
                if constexpr (Boundary::planes) {
                    if (walls_[w].normal[k] != 0.0)
                        detail::throw_input_error("wall ", w, " is not parallel to periodic axis ", k,
                                                  "; walls may only bound non-periodic axes");
                } else {
                    detail::throw_input_error("wall ", w, " has shape '", Boundary::ShapeType::name, "' and axis ", k,
                                              " is periodic; walls other than planes need a domain without periodic axes");
                }
            }
            for (std::size_t i = 0; i < n; ++i)
                if (!(walls_[w].distance(convert<double>(particles_.position()[i])) > 0.0))
                    detail::throw_input_error("particle ", i, " starts outside wall ", w, " (its centre is ",
                                              -walls_[w].distance(convert<double>(particles_.position()[i])),
                                              " m behind its surface); move it inside or move the wall");
        }
    }
    rebuild_neighbors();
    if (steps_ == 0) {
        step_back_springs();  // prepare() called again before the first step
        compute_forces();
        initial_energy_ = track_energy_ ? energy().total() : 0.0;
        books_ = {};  // the first evaluation only opens the books
    } else {
        compute_forces_without_books();
    }
    prepared_ = true;
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::sort_spatially(double cell) -> std::vector<Index> {
    const std::vector<Index> order = spatial_order(particles_.position(), particles_.radius(), domain_, cell);
    renumber(order);
    ++sorts_;
    sorted_gap_ = -1.0;
    return order;
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::restore_search_state(SearchState<dim, Real> state)
    -> void {
    if (state.particles.size() != particles_.size() || state.walls.size() != wall_reference_.size())
        detail::throw_input_error("restore_search_state: positions of ", state.particles.size(), " particles and offsets of ",
                                  state.walls.size(), " walls for a scene of ", particles_.size(), " particles and ",
                                  wall_reference_.size(), " walls searched; prepare() the scene first and give one of each");
    reference_ = std::move(state.particles);
    wall_reference_ = std::move(state.walls);
    sorted_gap_ = state.sorted_gap;
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::set_pair_order(std::vector<std::uint64_t> key)
    -> void {
    if (!key.empty()) {
        if (key.size() != particles_.size())
            detail::throw_input_error("set_pair_order: ", key.size(), " keys for ", particles_.size(),
                                      " particles; give one key per particle (or none for the index order)");
        std::vector<std::uint64_t> sorted = key;
        std::sort(sorted.begin(), sorted.end());
        if (const auto twin = std::adjacent_find(sorted.begin(), sorted.end()); twin != sorted.end())
            detail::throw_input_error("set_pair_order: the key ", *twin, " is given to two particles; give each particle its own");
    }
    pair_key_ = std::move(key);
    // The present list in the new order, each turned pair's spring seen from its other partner.
    std::vector<Index> same(particles_.size());
    std::iota(same.begin(), same.end(), Index{0});
    pairs_.renumber(same, true, pair_order());
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::renumber(const std::vector<Index>& order) -> void {
    const std::size_t n = particles_.size();
    if (order.size() != n)
        detail::throw_input_error("renumber: an order of ", order.size(), " entries for ", n, " particles; give a permutation of 0..",
                                  n, " - 1");
    if (const std::size_t k = first_not_permuted(order); k < n)
        detail::throw_input_error("renumber: entry ", k, " of the order is ", order[k], ", outside 0..", n,
                                  " - 1 or named before; give a permutation of 0..", n, " - 1");
    std::vector<Index> new_index(n);
    for (std::size_t k = 0; k < n; ++k) new_index[order[k]] = static_cast<Index>(k);
    const detail::Permutation permute{order};  // an archive that reorders every array it visits
    particles_.serialize(permute);
    permute.array(reference_);
    permute.array(pair_key_);  // each particle keeps its key
    if constexpr (Integrator::keeps_previous_forces) {
        permute.array(previous_force_);
        if constexpr (rotation) permute.array(previous_torque_);
    }
    pairs_.renumber(new_index, true, pair_order());
    if constexpr (has_walls) wall_contacts_.renumber(new_index, false);
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::position_resolution() const -> double {
    double far = 0.0;
    for (const auto& x : particles_.position()) far = std::max(far, double(x.cwiseAbs().maxCoeff()));
    if constexpr (has_walls)
        for (const auto& w : walls_) far = std::max(far, std::abs(w.offset));
    return far * std::numeric_limits<Real>::epsilon();
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::rebuild_neighbors() -> void {
    const auto& x = particles_.position();
    const auto& r = particles_.radius();
    auto& next = pairs_.scratch();
    const Domain<dim> search = window_.search_domain(domain_);
    auto find = [&] {
        next.clear();
        neighbors_.find_pairs(window_.any() ? window_.map(x, domain_, window_x_) : x, r, search, skin_, next);
    };
    find();
    if (auto_sort_ && particles_.size() >= auto_sort_min_particles && !next.empty()) {
        const double gap = mean_index_gap(next);
        const OrderAction action = order_action(sorted_gap_, gap);
        if (action == OrderAction::measure) {
            sorted_gap_ = gap;  // the order sort_spatially left
        } else if (action == OrderAction::sort) {
            sort_spatially();  // renumbers the present candidates and their histories too
            find();
            sorted_gap_ = mean_index_gap(next);
        }
    }
    if (first_ghost_ < particles_.size())  // two ghosts' pair is their owners' to compute
        next.erase(std::remove_if(next.begin(), next.end(),
                                  [g = static_cast<Index>(first_ghost_)](const IndexPair& p) { return p.i >= g && p.j >= g; }),
                   next.end());
    if (!pair_key_.empty()) {  // the search gives the index order
        if (pair_key_.size() != particles_.size())
            detail::throw_input_error("set_pair_order: ", pair_key_.size(), " keys for ", particles_.size(),
                                      " particles; give the keys again after adding particles");
        const PairOrder order = pair_order();
        for (IndexPair& p : next) p = order.oriented(p);
        std::sort(next.begin(), next.end(), [&](const IndexPair& a, const IndexPair& b) { return order.less(a, b); });
    }
    pairs_.commit_scratch(pair_order());
    reference_ = x;
    lattice_reference_ = domain_.lattice();
    if constexpr (has_walls) {
        auto& wn = wall_contacts_.scratch();
        wn.clear();
        detail::find_wall_candidates(x, r, walls_, skin_, wn);
        if (first_ghost_ < particles_.size())  // a ghost's wall contact is its owner's
            wn.erase(std::remove_if(wn.begin(), wn.end(), [g = static_cast<Index>(first_ghost_)](const IndexPair& p) { return p.i >= g; }),
                     wn.end());
        wall_contacts_.commit_scratch();
        wall_reference_.resize(walls_.size());
        for (std::size_t w = 0; w < walls_.size(); ++w) wall_reference_[w] = walls_[w].offset;
    }
    ++rebuilds_;
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::check_position_resolution() const -> void {
    if (particles_.empty() || allow_coarse_positions_) return;
    const auto& r = particles_.radius();
    micromacro::check_position_resolution(position_resolution(), *std::min_element(r.begin(), r.end()),
                                          std::numeric_limits<Real>::epsilon(), std::is_same_v<Real, float>);
}

template <int dim, class Real, class Law, class Boundary, class Integrator, class Neighbors, class... BodyForces>
inline auto BasicSimulation<dim, Real, Law, Boundary, Integrator, Neighbors, BodyForces...>::report_blow_up() const -> void {
    const auto& x = particles_.position();
    std::size_t bad = 0;  // the first particle whose displacement overflowed or is NaN
    while (bad + 1 < x.size() &&
           std::isfinite(domain_.separation(convert<double>(x[bad]), convert<double>(reference_[bad])).squaredNorm()))
        ++bad;
    throw SimulationError(detail::concat(
        "the simulation blew up at step ", steps_ + 1, " (t = ", time_, " s): particle ", bad,
        " reached position component ", x[bad][0], ". The time step dt = ", dt_,
        " s against the stability limit ", stable_time_step(), " s is the usual cause; reduce dt"));
}

}  // namespace micromacro
