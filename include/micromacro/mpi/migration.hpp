#pragma once
// Particles (or anything that travels with them: springs) sent between ranks as plain bytes:
// one step across a face to a neighbouring rank (a redistribution, as LAMMPS's Comm::exchange),
// or each to whichever rank owns it (the start of a run from per-rank shares).
#include <cstddef>
#include <vector>

#include <mpi.h>

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

}  // namespace micromacro::mpi
