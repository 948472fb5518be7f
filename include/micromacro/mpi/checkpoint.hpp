#pragma once
// Checkpoints of a scene run over MPI ranks: whole_scene() gathers the ranks' particles, their
// last forces and torques, every pair's and wall contact's spring and the walls into one serial
// scene on every rank, the state the serial engine would hold. io::save_state writes it like any
// scene; loaded again, it continues serially, or over any number of ranks through
// DistributedRun's Start::resume. So a checkpoint restarts on another rank count and on one
// process. Every rank then holds the whole scene, as every rank holds it when a run starts.
#include <cstddef>
#include <map>
#include <utility>
#include <vector>

#include <mpi.h>

#include "micromacro/engine/simulation.hpp"
#include "micromacro/mpi/communicator.hpp"
#include "micromacro/mpi/distributed_run.hpp"
#include "micromacro/mpi/energy.hpp"
#include "micromacro/mpi/halo.hpp"
#include "micromacro/neighbors/search_state.hpp"

namespace micromacro::mpi {

namespace checkpoint_detail {
/// What every rank sends of one of its particles.
struct Particle {
    ParticleRecord r;
    std::array<double, 3> force, torque, reference;  // reference: where the last neighbour search found it
};

/// Every rank's `mine`, on every rank, in rank order (MPI_Allgatherv of bytes).
template <class T>
std::vector<T> all_of(MPI_Comm comm, const std::vector<T>& mine) {
    int ranks = 1;
    check(MPI_Comm_size(comm, &ranks), "MPI_Comm_size");
    const int bytes = static_cast<int>(mine.size() * sizeof(T));
    std::vector<int> counts(static_cast<std::size_t>(ranks)), offsets(static_cast<std::size_t>(ranks), 0);
    check(MPI_Allgather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, comm), "MPI_Allgather (checkpoint sizes)");
    for (std::size_t k = 1; k < counts.size(); ++k) offsets[k] = offsets[k - 1] + counts[k - 1];
    std::vector<T> all(static_cast<std::size_t>(offsets.back() + counts.back()) / sizeof(T));
    check(MPI_Allgatherv(mine.data(), bytes, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, comm),
          "MPI_Allgatherv (checkpoint)");
    return all;
}
}  // namespace checkpoint_detail

/// The whole scene of `run` as one serial scene, the same on every rank (a collective call):
/// particles numbered in the serial order (DistributedRun::place: as the serial engine numbers
/// them, its spatial sorts followed, or the shares in rank order) with their global ids, their
/// positions (in the box), velocities, angular velocities and the last forces and torques, each
/// pair's and wall contact's spring, the walls (every rank's copy is the same) and body forces,
/// the run's clock, time step and skin, the energy books added over the ranks (mpi::open_books),
/// and the neighbour-list references and sorting (search_state, set_auto_sort). So the serial
/// engine goes on from it as from the scene the run started from: summing in its order, and
/// searching and sorting where it would.
template <class Sim>
Sim whole_scene(const DistributedRun<Sim>& run) {
    constexpr int dim = Sim::dimension;
    using History = typename Sim::History;
    const Sim& local = run.local();
    const auto& p = local.particles();
    const auto search = run.search_state();
    std::vector<checkpoint_detail::Particle> mine;
    for (std::size_t i = 0; i < run.owned(); ++i)
        mine.push_back({record_of(p, i, run.global_id(i), run.place(i)), record_vector<dim>(convert<double>(p.force()[i])),
                        record_angular<dim>(convert<double>(p.template get<field::Torque>()[i])),
                        record_vector<dim>(convert<double>(search.particles[i]))});
    // Each pair's spring once: from the rank that owns its partner of smaller global id.
    std::vector<PairSpring<History>> springs;
    local.visit_pair_histories([&](Index i, Index j, const History& h) {
        const Index a = run.global_id(i), b = run.global_id(j);
        if ((a < b ? i : j) < run.owned()) springs.push_back(PairSpring<History>::of(a, b, h));
    });
    // Each wall contact's spring from its particle's rank.
    std::vector<PairSpring<History>> wall_springs;
    if constexpr (Sim::has_walls)
        local.visit_wall_histories([&](Index i, Index w, const History& h) { wall_springs.push_back({run.global_id(i), w, h}); });
    const auto particles = checkpoint_detail::all_of(run.comm().comm(), mine);
    const auto all_springs = checkpoint_detail::all_of(run.comm().comm(), springs);
    const auto all_wall_springs = checkpoint_detail::all_of(run.comm().comm(), wall_springs);

    std::vector<const checkpoint_detail::Particle*> by_id(particles.size(), nullptr);
    for (const auto& q : particles) by_id.at(q.r.id) = &q;
    Sim whole = run.empty_scene();
    auto& w = whole.particles();
    for (const auto* q : by_id) {
        Vec<dim> x = vector_of_record<dim>(q->r.x);
        run.box().wrap(x);  // a rank's particle may have crossed the box's end since its last redistribution
        const std::size_t i = w.add(x, q->r.radius, q->r.mass, q->r.inertia);
        for (int a = 0; a < dim; ++a) w.velocity()[i][a] = q->r.v[a];
        w.template get<field::AngularVelocity>()[i] = angular_of_record<dim>(q->r.w);
    }
    whole.set_time_step(run.time_step());
    whole.set_skin(run.skin());
    whole.set_auto_sort(false);
    whole.set_track_energy(local.track_energy());
    whole.prepare();  // the lists; its forces, springs, books and references are replaced below
    // Its next neighbour search and sort where the run's would be.
    SearchState<dim, typename Sim::Scalar> references{{}, search.walls, search.sorted_gap};
    for (const auto* q : by_id)
        references.particles.push_back(vector_of_record<dim>(q->reference).template cast<typename Sim::Scalar>());
    whole.restore_search_state(std::move(references));
    whole.set_auto_sort(run.auto_sort());
    SpringsByPair<History> spring_of;
    for (const auto& s : all_springs) spring_of.emplace(std::pair{s.a, s.b}, s.h);
    restore_springs(whole, spring_of, [](Index i) { return i; });  // indices are the global ids
    if constexpr (Sim::has_walls) {
        SpringsByPair<History> wall_spring_of;
        for (const auto& s : all_wall_springs) wall_spring_of.emplace(std::pair{s.a, s.b}, s.h);
        restore_wall_springs(whole, wall_spring_of, [](Index i) { return i; });
        for (std::size_t k = 0; k < whole.walls().size(); ++k) whole.walls()[k].force = local.walls()[k].force;  // the last evaluation's, as the forces
    }
    for (std::size_t i = 0; i < by_id.size(); ++i) {
        for (int a = 0; a < dim; ++a) w.template get<field::Force>()[i][a] = by_id[i]->force[a];
        w.template get<field::Torque>()[i] = angular_of_record<dim>(by_id[i]->torque);
    }
    // Built in the order of the global ids (the springs find their particles by them), then
    // numbered in the serial order, the springs and lists following.
    std::vector<Index> order(by_id.size());
    for (const auto* q : by_id) order.at(q->r.place) = q->r.id;
    bool identity = true;
    for (std::size_t k = 0; k < order.size(); ++k) identity = identity && order[k] == k;
    if (!identity) whole.renumber(order);
    whole.set_clock(run.time(), run.steps_done());
    whole.continue_books(open_books(run));
    return whole;
}

}  // namespace micromacro::mpi
