#pragma once
// The biaxial experiment's scene over MPI ranks (biaxial_mpi): SerialScene's interface
// (scene.hpp) on a micromacro::mpi::DistributedRun. Every call is collective: every rank makes it
// with the same arguments and gets the same answer. The experiment switches its walls, law and
// damping on the whole scene, gathered on every rank (whole()), and the run continues from it
// (continue_from), as the serial scene's next step would (tests/mpi/biaxial_box.cpp).
#include <cstddef>
#include <optional>
#include <vector>

#include <mpi.h>

#include <micromacro/micromacro.hpp>
#include <micromacro/mpi/averaging.hpp>
#include <micromacro/mpi/checkpoint.hpp>
#include <micromacro/mpi/distributed_run.hpp>
#include <micromacro/mpi/energy.hpp>

namespace biaxial {

template <class Sim>
class DistributedScene {
public:
    static constexpr int dim = Sim::dimension;
    static constexpr bool distributed = true;
    using Run = micromacro::mpi::DistributedRun<Sim>;

    /// Splits `whole` (the same prepared scene on every rank: built, or loaded from a state) over
    /// the ranks of `comm`, `threads` threads each. `whole` is the engine whole() fills later.
    DistributedScene(MPI_Comm comm, Sim& whole, int threads) : comm_(comm), whole_(whole), threads_(threads) {
        continue_from(whole);
    }

    void run(std::size_t steps) { run_->run(steps); }
    double time() const { return run_->time(); }
    std::size_t steps_done() const { return run_->steps_done(); }
    const auto& walls() const { return run_->local().walls(); }  // every rank's are the same
    const micromacro::Domain<dim>& box() const { return run_->box(); }
    micromacro::EnergyState energy() { return micromacro::mpi::energy(*run_); }
    micromacro::EnergyBooks books() { return micromacro::mpi::books(*run_); }
    micromacro::PackingSnapshot<dim> snapshot() { return micromacro::mpi::local_snapshot(*run_); }
    std::size_t owned() const { return run_->owned(); }
    micromacro::MicroMacro<dim> average(const micromacro::PackingSnapshot<dim>&, const micromacro::Region<dim>& region) {
        return micromacro::mpi::average(*run_, region);
    }
    void add_up(std::vector<double>& values) const {
        micromacro::mpi::check(MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_SUM, comm_),
                               "MPI_Allreduce (biaxial sums)");
    }
    /// The whole scene gathered into the engine given at construction, on every rank.
    Sim& whole() {
        whole_ = micromacro::mpi::whole_scene(*run_);
        return whole_;
    }
    /// Splits `whole` over the ranks afresh, with its present forces (evaluated again first if its
    /// law changed since its last evaluation, as SerialScene::continue_from).
    void continue_from(Sim& whole) {
        if (!whole.prepared()) whole.prepare();
        run_.reset();
        run_.emplace(comm_, whole, Run::Start::resume);
        run_->set_threads(threads_);
    }
    Run& distributed_run() { return *run_; }

private:
    MPI_Comm comm_;
    Sim& whole_;
    int threads_;
    std::optional<Run> run_;
};

}  // namespace biaxial
