#pragma once
// The stability limits the engine checks before it runs: the time step of a contact's stiffest
// two-body oscillation, and whether stored coordinates resolve the overlaps. Free functions, so
// that a program can check its own options against the same numbers the engine will use.
#include <cmath>
#include <cstddef>
#include <limits>

#include "micromacro/core/error.hpp"
#include "micromacro/integrators/integrators.hpp"

namespace micromacro {

/// A scene's largest stable time step and the oscillation that sets it (what a refusal names).
struct StabilityLimit {
    enum class Cause { none, normal_spring, tangential_spring, drag, stress_wall };
    double seconds = std::numeric_limits<double>::infinity();
    Cause cause = Cause::none;
    std::size_t wall = 0;  ///< the stress-controlled wall, where it sets the limit

    /// Takes `candidate` where it is the tighter limit.
    void tighten(double candidate, Cause why, std::size_t which_wall = 0) {
        if (candidate < seconds) seconds = candidate, cause = why, wall = which_wall;
    }
};

/// The largest stable dt of a contact's normal spring and dashpot between bodies of combined
/// inverse mass `inverse_mass` (1/m_i + 1/m_j; 1/m for a particle on a wall), integrated by
/// `Integrator`, with a drag of the bodies' own (background damping) decaying their relative
/// velocity at `drag_rate` (1/s) besides.
template <class Integrator>
double normal_time_step_limit(double stiffness, double damping, double inverse_mass, double drag_rate = 0.0) {
    return Integrator::stability_limit(std::sqrt(stiffness * inverse_mass), 0.5 * (damping * inverse_mass + drag_rate));
}
/// The same for a normal model with constant stiffness() and damping().
template <class Integrator, class NormalLaw>
double normal_time_step_limit(const NormalLaw& normal, double inverse_mass) {
    return normal_time_step_limit<Integrator>(normal.stiffness(), normal.damping(), inverse_mass);
}

/// The same for a contact's tangential spring and dashpot: `mobility` is the combined tangential
/// mobility of the contact point, the sum over both partners of 1/m + a^2/I with rotation
/// (3.5/m for a sphere, 3/m for a disk) and of 1/m without.
template <class Integrator>
double tangential_time_step_limit(double stiffness, double damping, double mobility, double drag_rate = 0.0) {
    return Integrator::stability_limit(std::sqrt(stiffness * mobility), 0.5 * (damping * mobility + drag_rate));
}
/// The same for a tangential model with constant stiffness() and damping().
template <class Integrator, class TangentialLaw>
double tangential_time_step_limit(const TangentialLaw& tangential, double mobility) {
    return tangential_time_step_limit<Integrator>(tangential.stiffness(), tangential.damping(), mobility);
}

/// A stress-controlled wall of mass `wall_mass` and damping `wall_damping` on one contact of
/// normal stiffness `stiffness` with a particle of inverse mass `particle_inverse_mass`: the wall moves by
/// semi-implicit Euler (Walls::move).
inline double stress_wall_time_step_limit(double stiffness, double wall_mass, double wall_damping, double particle_inverse_mass) {
    const double inverse_mass = 1.0 / wall_mass + particle_inverse_mass;
    return SymplecticEuler::stability_limit(std::sqrt(stiffness * inverse_mass), 0.5 * wall_damping / wall_mass);
}

/// Refuses coordinates whose spacing `resolution` (one unit in the last place at the farthest
/// particle or wall) exceeds 1e-6 of the smallest radius: overlaps of 1e-4 of a radius (the
/// paper's are 2e-4 of the mean) would then be resolved to worse than 1%. `epsilon` is the
/// storage type's machine epsilon, `float_storage` whether it is float (for the message).
inline void check_position_resolution(double resolution, double smallest_radius, double epsilon, bool float_storage) {
    if (resolution > 1e-6 * smallest_radius)
        detail::throw_input_error("coordinates up to ", resolution / epsilon, " m from the origin are resolved to ", resolution,
                                  " m in ", float_storage ? "float" : "double", ", more than 1e-6 of the smallest radius ",
                                  smallest_radius, " m: overlaps would lose their digits; move the origin into the packing",
                                  float_storage ? ", store in double" : "", ", or call allow_coarse_positions(true) to accept it");
}

}  // namespace micromacro
