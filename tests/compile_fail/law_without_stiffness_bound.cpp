// A contact law must bound its stiffness for the engine's stable time step: one without
// stiffness_bound is refused with the concept's name, not deep in the time-step check.
// expect-error: the contact law does not satisfy ContactLawModel
#include <micromacro/micromacro.hpp>

namespace mm = micromacro;

struct SoftRepulsion {  // a linear repulsion, force and state only
    static constexpr bool has_tangential = false, has_history = false, needs_rotation = false;
    template <int dim>
    using History = mm::NoHistory;
    double k = 1e5;
    template <bool track, int dim>
    mm::ContactForce<dim> force(const mm::ContactKinematics<dim>& c, History<dim>&) const {
        return {normal_force(c), {}};
    }
    template <int dim>
    mm::NormalForce normal_force(const mm::ContactKinematics<dim>& c) const { return {k * c.overlap, 0.0}; }
    template <int dim>
    mm::ContactState<dim> state(const mm::ContactKinematics<dim>& c, const History<dim>*) const {
        mm::ContactState<dim> s;
        s.normal = normal_force(c);
        return s;
    }
};
static_assert(mm::ContactLawModel<mm::FrictionalLinear> && mm::ContactLawModel<mm::HertzMindlin>);
static_assert(!mm::ContactLawModel<SoftRepulsion>);

int main() {
    mm::Simulation<2, SoftRepulsion> sim(SoftRepulsion{});
    return static_cast<int>(sim.particles().size());
}
