#pragma once
// DistributedRun's hand-over of particles between ranks: the constructor splits the scene,
// redistribute() sends the particles that left a rank's subdomain to their new owners with their
// springs (the split's boundaries moved to the particles first, mpi/balance.hpp), distribute()
// builds a rank's engine on the particles it owns and the ghosts of its new halo, searching where
// the serial engine searches (its sorts followed, a resumed scene's references taken over).
#include <algorithm>
#include <array>
#include <cstddef>
#include <numeric>
#include <optional>
#include <utility>
#include <vector>

#include "micromacro/mpi/distributed_run.hpp"

namespace micromacro::mpi {

template <class Sim>
inline DistributedRun<Sim>::DistributedRun(MPI_Comm parent, const Sim& whole, Start start, Input input, Split split)
    : comm_(parent, split_box(whole, input == Input::share ? parent : MPI_COMM_NULL)), box_(whole.domain()), law_(whole.law()),
      walls_(whole.walls()),
      forces_(detail::EngineParts<Sim>::forces_of(whole)), follows_(following_axes(whole)), skin_(whole.skin()),
      dt_(whole.time_step()), time_(whole.time()), steps_(whole.steps_done()), track_(whole.track_energy()),
      balance_(split == Split::balanced) {
    const auto& p = whole.particles();
    const bool resume = start == Start::resume, share = input == Input::share;
    if (!share && steps_ > 0)  // the books of a scene that has run go on, on rank 0
        books_at_start_ = comm_.rank() == 0 ? whole.open_books() : whole.open_books().without_bookings();
    if (resume && share)
        micromacro::detail::throw_input_error("DistributedRun: a resumed run starts from the whole scene on every rank (its springs "
                                              "span the shares); use Input::whole, as mpi::whole_scene gives it");
    if (resume && !whole.prepared())
        micromacro::detail::throw_input_error("DistributedRun: Start::resume keeps the scene's last forces, but they are not the "
                                              "present scene's (never prepared, or particles, law, time step or skin changed "
                                              "since); call its prepare() first, or use Start::fresh");
    if constexpr (Sim::has_walls) check_wall_areas(walls_, comm_.split());  // before an engine measures them
    Index first_id = 0;  // of this rank's share
    std::size_t total = p.size();
    if (share) {
        // The skin and halo from every share's radii; the ids after the earlier ranks' shares.
        const ShareSizes all = share_sizes(comm_.comm(), parent, p.radius());
        if (!(skin_ > 0.0)) skin_ = default_skin(all.radius_sum, all.count);
        width_ = interaction_range(all.largest_radius, skin_);
        first_id = all.first_id;
        total = static_cast<std::size_t>(all.count);
    } else {
        if (!(skin_ > 0.0)) skin_ = default_skin(p.radius());
        width_ = interaction_range(p.radius(), skin_);
    }
    std::vector<State> all;
    for (std::size_t i = 0; i < p.size(); ++i) {
        State s{record_of(p, i, first_id + p.id(i), first_id + static_cast<Index>(i)), {}, {}};
        Vec<dim> x = p.position()[i];
        box_.wrap(x);  // as the serial engine does before its first step
        for (int a = 0; a < dim; ++a) s.r.x[a] = x[a], s.force[a] = resume ? double(p.force()[i][a]) : 0.0;
        if (resume) s.torque = record_angular<dim>(convert<double>(p.template get<field::Torque>()[i]));
        all.push_back(s);
    }
    SearchState<dim, typename Sim::Scalar> search = whole.search_state();
    order_ = SerialOrder(comm_.comm(), whole.auto_sort(), total >= Sim::auto_sort_min_particles, search.sorted_gap,
                         whole.spatial_sorts());
    SpringsByPair<History> springs, wall_springs;
    if (resume) {
        start_search_.emplace(search);  // by global id (whole: the particle's id)
        for (std::size_t i = 0; i < p.size(); ++i) start_search_->particles[p.id(i)] = search.particles[i];
        whole.visit_pair_histories([&](Index i, Index j, const History& h) {
            const auto spring = PairSpring<History>::of(p.id(i), p.id(j), h);
            springs.emplace(std::pair{spring.a, spring.b}, spring.h);
        });
        if constexpr (Sim::has_walls)
            whole.visit_wall_histories([&](Index i, Index w, const History& h) { wall_springs.emplace(std::pair{p.id(i), w}, h); });
    }
    balance_start(all, share);
    if (share)
        all = to_owners(comm_.comm(), comm_.size(), all, [&](const State& st) {
            return comm_.owner(vector_of_record<dim>(st.r.x));
        });
    distribute(all, springs, wall_springs, resume ? Stage::resume : Stage::fresh);
}

template <class Sim>
inline void DistributedRun<Sim>::redistribute() {
    const auto& p = local_->particles();
    follow_extent<dim>(comm_, p, owned_, follows_);  // where walls alone bound the box
    if (balance_) balance_split<dim>(comm_, owned_, [&](std::size_t i, int a) { return double(p.position()[i][a]); }, width_, true);
    std::vector<State> states;
    for (std::size_t i = 0; i < owned_; ++i) {
        State s{record_of(p, i, global_[i], place_[i]), {}, record_angular<dim>(p.template get<field::Torque>()[i])};
        Vec<dim> x = p.position()[i];
        box_.wrap(x);
        for (int a = 0; a < dim; ++a) s.r.x[a] = x[a], s.force[a] = p.force()[i][a];
        states.push_back(s);
    }
    // Every spring with at least one of this rank's particles, carried by each of them that
    // is this rank's (so that it goes wherever either goes).
    std::vector<CarriedSpring> carried;
    local_->visit_pair_histories([&](Index i, Index j, const History& h) {
        if (i >= owned_ && j >= owned_) return;  // between two ghosts: another rank's
        const Index a = global_id(i), b = global_id(j);
        const auto pair = PairSpring<History>::of(a, b, h);
        if (i < owned_) carried.push_back({a, false, pair});
        if (j < owned_) carried.push_back({b, false, pair});
    });
    if constexpr (Sim::has_walls) {  // every wall contact is an owned particle's
        local_->visit_wall_histories([&](Index i, Index w, const History& h) {
            carried.push_back({global_id(i), true, {global_id(i), w, h}});
        });
        walls_ = local_->walls();
    }
    migrate(comm_, states, carried);
    SpringsByPair<History> by_pair, by_wall;
    for (const CarriedSpring& cs : carried)  // a pair's held twice: the first
        (cs.wall ? by_wall : by_pair).emplace(std::pair{cs.pair.a, cs.pair.b}, cs.pair.h);
    distribute(states, by_pair, by_wall, Stage::within_step);
    ++redistributions_;
}

template <class Sim>
inline void DistributedRun<Sim>::distribute(const std::vector<State>& all, const SpringsByPair<History>& springs,
                                            const SpringsByPair<History>& wall_springs, Stage stage) {
    std::vector<const State*> own_states;
    for (const State& s : all)
        if (comm_.split().owns(vector_of_record<dim>(s.r.x))) own_states.push_back(&s);
    std::vector<Index> places(own_states.size());
    for (std::size_t k = 0; k < own_states.size(); ++k) places[k] = own_states[k]->r.place;
    // Within a step this rank's books go on in its new engine; at the start, a scene's that has run.
    std::optional<OpenBooks> books = std::exchange(books_at_start_, std::nullopt);
    if (local_) books = local_->open_books();
    build(own_states, places);
    if (stage == Stage::resume) {
        take_start_search();
    } else {  // a search where the serial engine searches: where it sorts, built again in its new order
        auto pairs = [&](auto&& f) { local_->visit_pair_histories([&](Index i, Index j, const History&) { f(i, j); }); };
        auto place_of = [&](Index i) { return place_[i]; };
        auto gap = [&] { return SerialOrder::mean_gap(comm_.comm(), pairs, place_of, owned_); };
        if (order_.at_search(gap) == OrderAction::sort) {
            const auto& p = local_->particles();
            build(own_states, SerialOrder::sorted_places(comm_.comm(), box_, p.position(), p.radius(), place_of, owned_));
            order_.sorted(*gap());
        }
    }
    rearrange_walls();
    if (books) local_->continue_books(std::move(*books));  // as if prepare() had not evaluated
    rebuilds_ = local_->neighbor_rebuilds();
    ghosts_current_ = true;
    if (stage == Stage::fresh) {
        sum_walls();
        return;
    }
    if constexpr (Sim::has_walls)
        for (std::size_t k = 0; k < walls_.size(); ++k) local_->walls()[k].force = walls_[k].force;
    auto& p = local_->particles();
    for (std::size_t i = 0; i < owned_; ++i) {
        for (int a = 0; a < dim; ++a) p.template get<field::Force>()[i][a] = own_states[i]->force[a];
        p.template get<field::Torque>()[i] = angular_of_record<dim>(own_states[i]->torque);
    }
    restore_springs(*local_, springs, [&](Index i) { return global_id(i); });
    if constexpr (Sim::has_walls) restore_wall_springs(*local_, wall_springs, [&](Index i) { return global_id(i); });
}

template <class Sim>
inline void DistributedRun<Sim>::build(std::vector<const State*>& own_states, const std::vector<Index>& places) {
    // In the order of the places: on one rank, the serial engine's own numbering. The particles
    // that stayed come in that order, those that arrived after them: those sorted, then merged.
    std::vector<std::size_t> by_place(own_states.size());
    std::iota(by_place.begin(), by_place.end(), std::size_t{0});
    const auto before = [&](std::size_t a, std::size_t b) { return places[a] < places[b]; };
    const auto arrived = std::is_sorted_until(by_place.begin(), by_place.end(), before);
    std::sort(arrived, by_place.end(), before);
    std::inplace_merge(by_place.begin(), arrived, by_place.end(), before);
    std::vector<ParticleRecord> owned;
    std::vector<const State*> ordered;
    for (const std::size_t k : by_place) {
        owned.push_back(own_states[k]->r);
        owned.back().place = places[k];
        ordered.push_back(own_states[k]);
    }
    own_states = std::move(ordered);
    halo_.emplace(comm_, owned, width_);
    local_.emplace(engine(box_, walls_));
    global_.clear();
    place_.clear();
    for (const auto* set : std::array<const std::vector<ParticleRecord>*, 2>{&owned, &halo_->ghosts()})
        for (const ParticleRecord& r : *set) {
            const std::size_t i = local_->particles().add(vector_of_record<dim>(r.x), r.radius, r.mass, r.inertia);
            write_motion(i, Motion<dim>::of(r));
            global_.push_back(r.id);
            place_.push_back(r.place);
        }
    owned_ = owned.size();
    local_->set_time_step(dt_);
    local_->set_skin(skin_);
    local_->set_auto_sort(false);     // the first owned_ particles stay the owned ones
    local_->set_search_window(comm_.split().search_window(width_, skin_));
    local_->set_first_ghost(owned_, comm_.rank() == 0);  // the walls' own books on rank 0
    local_->set_track_energy(track_);
    local_->set_threads(threads_);
    serial_pair_order();
    if constexpr (Sim::has_walls) local_->keep_wall_terms(serial_wall_sums_);
    local_->set_clock(time_, steps_);  // a strain-controlled wall's motion reads it
    local_->prepare();                 // the lists (and forces, replaced by distribute() unless fresh)
}

template <class Sim>
inline void DistributedRun<Sim>::balance_start(const std::vector<State>& all, bool share) {
    if (!balance_) return;
    const auto& dims = comm_.split().dims;  // the split is not handed out yet: every boundary may move all the way
    balance_split<dim>(comm_, all.size(), [&](std::size_t i, int a) { return all[i].r.x[a]; }, width_, share,
                       *std::max_element(dims.begin(), dims.end()));
}

template <class Sim>
inline void DistributedRun<Sim>::take_start_search() {
    auto s = local_->search_state();
    for (std::size_t i = 0; i < owned_; ++i) s.particles[i] = start_search_->particles[global_[i]];
    s.walls = start_search_->walls;
    local_->restore_search_state(std::move(s));
    start_search_.reset();
}

template <class Sim>
inline auto DistributedRun<Sim>::search_state() const -> SearchState<dim, typename Sim::Scalar> {
    SearchState<dim, typename Sim::Scalar> s = local_->search_state();
    s.particles.resize(owned_);
    s.sorted_gap = order_.sorted_gap();
    return s;
}

}  // namespace micromacro::mpi
