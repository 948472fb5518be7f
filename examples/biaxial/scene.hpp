#pragma once
// The running scene as the biaxial experiment's phases see it: what they step, measure and
// average. SerialScene is one process's engine; distributed_scene.hpp gives the same over MPI
// ranks (biaxial_mpi), so that the preparation, the loading and the time series' rows are one
// code for both.
#include <cstddef>
#include <vector>

#include <micromacro/micromacro.hpp>

namespace biaxial {

/// The whole scene in this process's engine.
template <class Sim>
class SerialScene {
public:
    static constexpr int dim = Sim::dimension;
    static constexpr bool distributed = false;

    /// Steps `sim` (prepared first if it is not).
    explicit SerialScene(Sim& sim) : sim_(sim) { continue_from(sim); }

    void run(std::size_t steps) { sim_.run(steps); }
    double time() const { return sim_.time(); }
    std::size_t steps_done() const { return sim_.steps_done(); }
    const auto& walls() const { return sim_.walls(); }
    /// The whole scene's box (its periodic axes; walls bound the rest).
    const micromacro::Domain<dim>& box() const { return sim_.domain(); }
    micromacro::EnergyState energy() { return sim_.energy(); }
    micromacro::EnergyBooks books() { return sim_.books(); }
    /// The particles and contacts this process holds, its own first (here all of them).
    micromacro::PackingSnapshot<dim> snapshot() { return micromacro::take_snapshot(sim_); }
    /// How many of the snapshot's particles are this process's own (the first ones).
    std::size_t owned() const { return sim_.particles().size(); }
    /// The average over `region` of the whole scene; `s` is this process's snapshot().
    micromacro::MicroMacro<dim> average(const micromacro::PackingSnapshot<dim>& s, const micromacro::Region<dim>& region) {
        return micromacro::average(s, region);
    }
    /// Each number summed over the processes (one process: as it is).
    void add_up(std::vector<double>&) const {}
    /// The whole scene as one engine (to save it, or to change its walls, law and damping).
    Sim& whole() { return sim_; }
    /// Continues from `whole` after whole() was changed (its walls, law or damping): the same
    /// engine here, its forces evaluated again now if the change asks for it (as its next step
    /// would), so that a row taken before that step reports them.
    void continue_from(Sim& whole) {
        if (!whole.prepared()) whole.prepare();
    }

private:
    Sim& sim_;
};

}  // namespace biaxial
