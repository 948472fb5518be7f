#pragma once
// The integrator's passes over the particles: kick, drift, kick in one pass (with the closing
// force-change kick of the step before merged in), and the force-change kick on its own. One
// pass with a third of the memory traffic of three, which is what limits large packings. With
// double storage where the compiler targets AVX-512 the kick-drift pass runs eight particles at a
// time (engine/packet_particle_pass.hpp).
#include <cstddef>
#include <utility>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/domain.hpp"
#include "micromacro/core/inline.hpp"
#include "micromacro/core/parallel.hpp"
#include "micromacro/engine/force_change_kick.hpp"
#include "micromacro/engine/packet_particle_pass.hpp"

namespace micromacro::detail {

/// The stored arrays the particle passes read and write (rotational ones null without rotation,
/// the previous forces null for integrators that do not keep them).
template <int dim, class Real>
struct ParticleArrays {
    Vec<dim, Real>* x;
    Vec<dim, Real>* v;
    Vec<dim>* f;
    const Real* inv_m;
    Angular<dim, Real>* w;
    Angular<dim>* torque;
    const Real* inv_I;
    Vec<dim>* f_old;
    Angular<dim>* torque_old;
    const Vec<dim, Real>* reference;  ///< positions at the last neighbour search
    std::size_t n;
};

/// v += h/m (F - F_old) and w += h/I (T - T_old) for every particle.
template <bool rotation, int dim, class Real>
void kick_force_change_pass(const ParticleArrays<dim, Real>& a, double h, [[maybe_unused]] int threads) {
    Vec<dim, Real>* v = a.v;
    Angular<dim, Real>* w = a.w;
    const std::size_t n = a.n;
    MICROMACRO_OMP(omp parallel for num_threads(threads) schedule(static) if (threads > 1))
    for (std::size_t i = 0; i < n; ++i) {
        v[i] = convert<Real>(force_change_kick(convert<double>(v[i]), h * double(a.inv_m[i]), convert<double>(a.f[i]),
                                               convert<double>(a.f_old[i])));
        if constexpr (rotation)
            w[i] = convert<Real>(force_change_kick(convert<double>(w[i]), h * double(a.inv_I[i]), convert<double>(a.torque[i]),
                                                   convert<double>(a.torque_old[i])));
    }
}

/// kick_drift_pass over particles [first, n), one at a time.
template <bool periodic, bool rotation, bool keeps_previous_forces, int dim, class Real>
DriftTotals scalar_kick_drift_pass(const ParticleArrays<dim, Real>& a, std::size_t first, const Domain<dim>& box,
                                                 double h_before, double dt, double h_after, double h_closing,
                                                 [[maybe_unused]] int threads) {
    using V = Vec<dim>;
    using A = Angular<dim>;
    using SV = Vec<dim, Real>;
    SV* x = a.x;
    SV* v = a.v;
    V* f = a.f;
    const Real* inv_m = a.inv_m;
    [[maybe_unused]] Angular<dim, Real>* w = a.w;
    [[maybe_unused]] A* torque = a.torque;
    [[maybe_unused]] const Real* inv_I = a.inv_I;
    [[maybe_unused]] V* f_old = a.f_old;
    [[maybe_unused]] A* torque_old = a.torque_old;
    const SV* reference = a.reference;
    const std::size_t n = a.n;
    // A local copy: the stores to x and v could alias the caller's box, which the compiler would
    // then reload for every particle.
    const Domain<dim> domain = box;
    double max_move_sq = 0.0, sum_move_sq = 0.0, wrap_energy = 0.0;
    // firstprivate: shared, the scalars and pointers would be read through the outlined
    // function's argument block for every particle (the stores to x, v, w may alias it).
    MICROMACRO_OMP(omp parallel for num_threads(threads) schedule(static) reduction(max : max_move_sq) reduction(+ : sum_move_sq, wrap_energy)
                       firstprivate(x, v, f, inv_m, w, torque, inv_I, f_old, torque_old, reference, domain, h_before, dt,
                                    h_after, h_closing) if (threads > 1))
    for (std::size_t i = first; i < n; ++i) {
        const V fi = convert<double>(f[i]);
        V vi = convert<double>(v[i]);
        [[maybe_unused]] A wi = zero_angular<dim, double>();
        if constexpr (rotation) wi = convert<double>(w[i]);
        if constexpr (keeps_previous_forces) {
            if (h_closing != 0.0) {  // the closing force-change kick (double only, see above)
                vi = force_change_kick(vi, h_closing * double(inv_m[i]), fi, convert<double>(f_old[i]));
                if constexpr (rotation)
                    wi = force_change_kick(wi, h_closing * double(inv_I[i]), convert<double>(torque[i]),
                                           convert<double>(torque_old[i]));
            }
            f_old[i] = V::Zero();  // becomes the force array at the next force evaluation
            if constexpr (rotation) torque_old[i] = zero_angular<dim, double>();
        }
        const V acc = double(inv_m[i]) * fi;
        vi += h_before * acc;
        V xi = convert<double>(x[i]) + dt * vi;
        vi += h_after * acc;
        if constexpr (periodic) {
            const V before = vi;
            if (domain.wrap(xi, vi)) [[unlikely]] wrap_energy += kinetic_change<dim>(before, vi, double(inv_m[i]));
        }
        // The displacement from the stored value, not reloaded from x[i]: wrap() stores
        // coordinates one by one, and a vector load right after them stalls.
        const SV stored = convert<Real>(xi);
        x[i] = stored;
        v[i] = convert<Real>(vi);
        const double move_sq =
            domain.template separation_for<periodic>(convert<double>(stored), convert<double>(reference[i])).squaredNorm();
        // The maximum drops a NaN, and the pair loop treats a NaN pair as not touching, so
        // nothing else would stop the run: the sum catches NaN and infinity. By value, not
        // std::max: its reference result made GCC carry the maximum from particle to particle
        // through memory.
        max_move_sq = move_sq > max_move_sq ? move_sq : max_move_sq;
        sum_move_sq += move_sq;
        if constexpr (rotation) {
            w[i] = convert<Real>(A(wi + (h_before + h_after) * double(inv_I[i]) * convert<double>(torque[i])));
            if constexpr (!keeps_previous_forces) torque[i] = zero_angular<dim, double>();
        }
        if constexpr (!keeps_previous_forces) f[i] = V::Zero();  // read for the last time
    }
    return {max_move_sq, sum_move_sq, wrap_energy};
}

/// Kick by h_before, drift by dt, kick by h_after, with h_closing != 0 first the closing kick of
/// the step before (integrators that keep the previous forces; double storage only, see
/// BasicSimulation::kick_drift_kick). Clears the array the next force evaluation accumulates
/// into once its values are dead. Returns the largest squared displacement from the references
/// and the sum of them all (finite unless a particle blew up), and the kinetic energy of the
/// velocities taken off at a moving cell's boundary (DriftTotals). Eight particles at a time where
/// packet_particle_pass_applies (the last n mod 8 one by one), else one at a time.
template <bool periodic, bool rotation, bool keeps_previous_forces, int dim, class Real>
DriftTotals kick_drift_pass(const ParticleArrays<dim, Real>& a, const Domain<dim>& box, double h_before, double dt,
                            double h_after, double h_closing, int threads) {
    if constexpr (packet_particle_pass_applies<Real>) {
        if (a.n >= 8) {
            const DriftTotals packets = packet_kick_drift_pass<periodic, rotation, keeps_previous_forces>(
                a, box, h_before, dt, h_after, h_closing, threads);
            const DriftTotals rest = scalar_kick_drift_pass<periodic, rotation, keeps_previous_forces>(
                a, a.n - a.n % 8, box, h_before, dt, h_after, h_closing, 1);
            return {rest.max_move_sq > packets.max_move_sq ? rest.max_move_sq : packets.max_move_sq,
                    packets.sum_move_sq + rest.sum_move_sq, packets.wrap_energy + rest.wrap_energy};
        }
    }
    return scalar_kick_drift_pass<periodic, rotation, keeps_previous_forces>(a, 0, box, h_before, dt, h_after, h_closing, threads);
}

}  // namespace micromacro::detail
