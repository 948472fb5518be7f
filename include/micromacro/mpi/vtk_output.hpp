#pragma once
// VTK output of a scene run over MPI ranks: each rank writes its own particles as one piece
// (a .vtp file, the serial particle file's arrays, with the particles' global ids), and rank 0
// writes the summary (.pvtp) that ParaView opens as one data set, also within a .pvd series
// (io::PvdCollection). A piece is complete before the summary names it; a rank that cannot
// write fails every rank with the message.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <mpi.h>

#include "micromacro/core/error.hpp"
#include "micromacro/io/vtk.hpp"
#include "micromacro/mpi/communicator.hpp"
#include "micromacro/mpi/distributed_run.hpp"

namespace micromacro::mpi {

/// The piece of rank `rank` for the summary `path` (x.pvtp -> x_<rank>.vtp beside it).
inline std::filesystem::path piece_path(const std::filesystem::path& path, int rank) {
    return path.parent_path() / (path.stem().string() + "_" + std::to_string(rank) + ".vtp");
}

/// The particles of the whole scene `run` steps, as pieces and their summary at `path` (.pvtp),
/// with the frame's own numbers (`values`, as io::ParticleFrame::values). A collective call.
template <class Sim>
void write_particles(DistributedRun<Sim>& run, const std::filesystem::path& path,
                     std::vector<std::pair<std::string, double>> values = {}) {
    if (path.extension() != ".pvtp")
        micromacro::detail::throw_input_error("mpi::write_particles: ", path.string(),
                                              " must end in .pvtp (the summary ParaView opens)");
    run.refresh_ghosts();  // the owned particles' contact forces read the ghosts' velocities
    auto frame = io::particle_frame(run.local());
    const std::size_t n = run.owned();
    frame.keep_first(n);
    frame.id.resize(n);
    for (std::size_t i = 0; i < n; ++i) frame.id[i] = static_cast<long long>(run.global_id(i));
    frame.values = std::move(values);
    const int rank = run.comm().rank();
    const auto data = io::particle_data(frame);
    std::string failure;
    try {
        io::detail::write_polydata(data, piece_path(path, rank));
    } catch (const std::exception& e) {
        failure = e.what();
    }
    int failed = failure.empty() ? 0 : 1, any = 0;
    check(MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, run.comm().comm()), "MPI_Allreduce (VTK pieces)");
    if (any)
        micromacro::detail::throw_input_error("mpi::write_particles: a piece of ", path.string(), " was not written",
                                              failure.empty() ? std::string(" (on another rank)") : ": " + failure);
    if (rank == 0) {
        int ranks = 1;
        check(MPI_Comm_size(run.comm().comm(), &ranks), "MPI_Comm_size");
        std::vector<std::string> pieces;
        for (int r = 0; r < ranks; ++r) pieces.push_back(piece_path(path, r).filename().string());
        try {
            io::write_piece_summary(data, pieces, path);
        } catch (const std::exception& e) {
            failure = e.what();
        }
    }
    failed = failure.empty() ? 0 : 1;
    check(MPI_Bcast(&failed, 1, MPI_INT, 0, run.comm().comm()), "MPI_Bcast (VTK summary)");
    if (failed)
        micromacro::detail::throw_input_error("mpi::write_particles: the summary ", path.string(), " was not written",
                                              failure.empty() ? std::string(" (on rank 0)") : ": " + failure);
}

}  // namespace micromacro::mpi
