#pragma once
// VTK output of a scene run over MPI ranks: each rank writes its own particles, or the contacts
// it counts, as one piece (a .vtp file, the serial file's arrays, particles with their global
// ids), and rank 0 writes the summary (.pvtp) that ParaView opens as one data set, also within a
// .pvd series (io::PvdCollection). A piece is complete before the summary names it; a rank that
// cannot write fails every rank with the message.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <mpi.h>

#include "micromacro/averaging/snapshot.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/engine/snapshot.hpp"
#include "micromacro/io/vtk.hpp"
#include "micromacro/mpi/communicator.hpp"
#include "micromacro/mpi/distributed_run.hpp"

namespace micromacro::mpi {

/// The piece of rank `rank` for the summary `path` (x.pvtp -> x_<rank>.vtp beside it).
inline std::filesystem::path piece_path(const std::filesystem::path& path, int rank) {
    return path.parent_path() / (path.stem().string() + "_" + std::to_string(rank) + ".vtp");
}

namespace vtk_detail {
/// Writes this rank's `piece` of the data set `path` (.pvtp) and, once every rank's is written,
/// rank 0 the summary; a failure on any rank fails every rank. `who` names the caller in messages.
template <class Sim>
void write_pieces(const DistributedRun<Sim>& run, const std::filesystem::path& path, vtkPolyData* piece, const char* who) {
    const int rank = run.comm().rank();
    std::string failure;
    try {
        io::detail::write_polydata(piece, piece_path(path, rank));
    } catch (const std::exception& e) {
        failure = e.what();
    }
    int failed = failure.empty() ? 0 : 1, any = 0;
    check(MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, run.comm().comm()), "MPI_Allreduce (VTK pieces)");
    if (any)
        micromacro::detail::throw_input_error(who, ": a piece of ", path.string(), " was not written",
                                              failure.empty() ? std::string(" (on another rank)") : ": " + failure);
    if (rank == 0) {
        std::vector<std::string> pieces;
        for (int r = 0; r < run.comm().size(); ++r) pieces.push_back(piece_path(path, r).filename().string());
        try {
            io::write_piece_summary(piece, pieces, path);
        } catch (const std::exception& e) {
            failure = e.what();
        }
    }
    failed = failure.empty() ? 0 : 1;
    check(MPI_Bcast(&failed, 1, MPI_INT, 0, run.comm().comm()), "MPI_Bcast (VTK summary)");
    if (failed)
        micromacro::detail::throw_input_error(who, ": the summary ", path.string(), " was not written",
                                              failure.empty() ? std::string(" (on rank 0)") : ": " + failure);
}

inline void require_summary_name(const std::filesystem::path& path, const char* who) {
    if (path.extension() != ".pvtp")
        micromacro::detail::throw_input_error(who, ": ", path.string(), " must end in .pvtp (the summary ParaView opens)");
}
}  // namespace vtk_detail

/// The particles of the whole scene `run` steps, as pieces and their summary at `path` (.pvtp),
/// with the frame's own numbers (`values`, as io::ParticleFrame::values). A collective call.
template <class Sim>
void write_particles(DistributedRun<Sim>& run, const std::filesystem::path& path,
                     std::vector<std::pair<std::string, double>> values = {}) {
    vtk_detail::require_summary_name(path, "mpi::write_particles");
    run.refresh_ghosts();  // the owned particles' contact forces read the ghosts' velocities
    auto frame = io::particle_frame(run.local());
    const std::size_t n = run.owned();
    frame.keep_first(n);
    frame.id.resize(n);
    for (std::size_t i = 0; i < n; ++i) frame.id[i] = static_cast<long long>(run.global_id(i));
    frame.values = std::move(values);
    vtk_detail::write_pieces(run, path, io::particle_data(frame), "mpi::write_particles");
}

/// The force network of the whole scene `run` steps, as pieces and their summary at `path`
/// (.pvtp), the serial contact file's lines and arrays (io::contact_data): each contact once, in
/// the piece of the rank that counts it as mpi::average does (a wall contact its particle's owner,
/// a pair the owner of its partner of smaller global id). A piece's points are its own particles'
/// centres and the partners' ends. A collective call.
template <class Sim>
void write_contacts(DistributedRun<Sim>& run, const std::filesystem::path& path) {
    vtk_detail::require_summary_name(path, "mpi::write_contacts");
    run.refresh_ghosts();  // the contact forces read the ghosts' velocities
    auto s = take_snapshot(run.local());
    const std::size_t owned = run.owned();
    std::erase_if(s.contacts, [&](const auto& c) {
        const std::size_t counter = c.wall || run.global_id(c.i) < run.global_id(c.j) ? c.i : c.j;
        return counter >= owned;
    });
    s.position.resize(owned);  // a counted contact's first particle is an owned one (the owned come first)
    vtk_detail::write_pieces(run, path, io::contact_data(s), "mpi::write_contacts");
}

}  // namespace micromacro::mpi
