#pragma once
// Particles (or anything that travels with them: springs) sent between ranks as plain bytes:
// one step across a face to a neighbouring rank (a redistribution, as LAMMPS's Comm::exchange),
// or each to whichever rank owns it (the start of a run from per-rank shares); and what such a
// start needs to know of every share.
#include <algorithm>
#include <array>
#include <cstddef>
#include <map>
#include <vector>

#include <mpi.h>

#include "micromacro/core/index.hpp"
#include "micromacro/mpi/communicator.hpp"

namespace micromacro::mpi {

/// Sends `out` to rank `to` and returns what rank `from` sends (either may be MPI_PROC_NULL). T is
/// plain data (numbers and fixed-size vectors), sent as bytes.
template <class T>
std::vector<T> exchange(MPI_Comm comm, const std::vector<T>& out, int to, int from) {
    unsigned long long sending = out.size(), receiving = 0;
    check(MPI_Sendrecv(&sending, 1, MPI_UNSIGNED_LONG_LONG, to, 2, &receiving, 1, MPI_UNSIGNED_LONG_LONG, from, 2, comm, MPI_STATUS_IGNORE),
          "MPI_Sendrecv (migration counts)");
    std::vector<T> in(receiving);
    check(MPI_Sendrecv(out.data(), static_cast<int>(out.size() * sizeof(T)), MPI_BYTE, to, 3, in.data(),
                       static_cast<int>(in.size() * sizeof(T)), MPI_BYTE, from, 3, comm, MPI_STATUS_IGNORE),
          "MPI_Sendrecv (migration)");
    return in;
}

/// Each of `items` to the rank `owner(item)` of the `ranks` of `comm`, and what the others send
/// here, in rank order (MPI_Alltoallv). A collective call; T as for exchange.
template <class T, class Owner>
std::vector<T> to_owners(MPI_Comm comm, int ranks, const std::vector<T>& items, Owner&& owner) {
    std::vector<std::vector<T>> out(static_cast<std::size_t>(ranks));
    for (const T& item : items) out[static_cast<std::size_t>(owner(item))].push_back(item);
    std::vector<int> send_bytes(ranks), receive_bytes(ranks), send_at(ranks, 0), receive_at(ranks, 0);
    std::vector<T> sending;
    for (int r = 0; r < ranks; ++r) {
        send_at[r] = static_cast<int>(sending.size() * sizeof(T));
        send_bytes[r] = static_cast<int>(out[r].size() * sizeof(T));
        sending.insert(sending.end(), out[r].begin(), out[r].end());
    }
    check(MPI_Alltoall(send_bytes.data(), 1, MPI_INT, receive_bytes.data(), 1, MPI_INT, comm), "MPI_Alltoall (shares)");
    for (int r = 1; r < ranks; ++r) receive_at[r] = receive_at[r - 1] + receive_bytes[r - 1];
    std::vector<T> received(static_cast<std::size_t>(receive_at[ranks - 1] + receive_bytes[ranks - 1]) / sizeof(T));
    check(MPI_Alltoallv(sending.data(), send_bytes.data(), send_at.data(), MPI_BYTE, received.data(), receive_bytes.data(),
                        receive_at.data(), MPI_BYTE, comm),
          "MPI_Alltoallv (shares)");
    return received;
}

/// The items of `states` whose slab is another one now sent there, axis by axis to the
/// neighbouring ranks of `comm` (an item moves at most one slab along each axis between two
/// distributions), each with the `carried` items whose `carrier` is its id (`r.id`; its position
/// `r.x`, wrapped into the box). On return both hold what this rank keeps and what arrived. A
/// collective call.
template <int dim, class State, class Carried>
void migrate(const CartesianComm<dim>& comm, std::vector<State>& states, std::vector<Carried>& carried) {
    const CartesianSplit<dim>& split = comm.split();
    for (int a = 0; a < dim; ++a) {
        if (split.dims[a] == 1) continue;
        // Down (0) or up (1) one slab, across the box's end on a periodic axis; or staying.
        std::array<std::vector<State>, 2> leaving;
        std::array<std::vector<Carried>, 2> leaving_carried;
        std::map<Index, int> way;
        std::vector<State> staying;
        for (const State& st : states) {
            const int c = split.slab(a, st.r.x[a]);
            if (c == split.coords[a]) {
                staying.push_back(st);
                continue;
            }
            // Up one slab, or across the end of a periodic axis from its last slab to its first
            // (on an open axis of two slabs, the slab below is not the one above).
            const bool wraps_up = split.periodic[a] && c == 0 && split.coords[a] == split.dims[a] - 1;
            const int up = c == split.coords[a] + 1 || wraps_up ? 1 : 0;
            leaving[up].push_back(st);
            way[st.r.id] = up;
        }
        states.swap(staying);
        std::vector<Carried> kept;
        for (const Carried& cs : carried) {
            const auto found = way.find(cs.carrier);
            if (found == way.end()) kept.push_back(cs);
            else leaving_carried[found->second].push_back(cs);
        }
        carried.swap(kept);
        for (int up = 0; up < 2; ++up) {
            const int to = comm.neighbour(a, up ? +1 : -1), from = comm.neighbour(a, up ? -1 : +1);
            const auto arrived = exchange(comm.comm(), leaving[up], to, from);
            const auto arrived_carried = exchange(comm.comm(), leaving_carried[up], to, from);
            states.insert(states.end(), arrived.begin(), arrived.end());
            carried.insert(carried.end(), arrived_carried.begin(), arrived_carried.end());
        }
    }
}

/// What a run started from per-rank shares of the particles needs of all of them: the sum and
/// count of their radii and the largest (over `comm`), and the first global id of this rank's
/// share (the shares numbered in the rank order of `parent`). A collective call.
struct ShareSizes {
    double radius_sum = 0.0, count = 0.0, largest_radius = 0.0;
    Index first_id = 0;
};
template <class Radii>
ShareSizes share_sizes(MPI_Comm comm, MPI_Comm parent, const Radii& radius) {
    double here[3] = {0.0, double(radius.size()), 0.0}, all[3];
    for (const auto r : radius) here[0] += double(r), here[2] = std::max(here[2], double(r));
    check(MPI_Allreduce(here, all, 2, MPI_DOUBLE, MPI_SUM, comm), "MPI_Allreduce (radii)");
    check(MPI_Allreduce(&here[2], &all[2], 1, MPI_DOUBLE, MPI_MAX, comm), "MPI_Allreduce (largest radius)");
    unsigned long long mine = radius.size(), before = 0;
    check(MPI_Exscan(&mine, &before, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, parent), "MPI_Exscan (ids)");
    int parent_rank = 0;
    check(MPI_Comm_rank(parent, &parent_rank), "MPI_Comm_rank");
    const Index first = parent_rank == 0 ? 0 : static_cast<Index>(before);  // MPI_Exscan leaves rank 0's undefined
    return {all[0], all[1], all[2], first};
}

}  // namespace micromacro::mpi
