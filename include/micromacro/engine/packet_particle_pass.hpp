#pragma once
// The kick-drift pass (engine/particle_pass.hpp) eight particles at a time, for double storage
// where the compiler targets AVX-512 (core/packets.hpp). The pass treats each coordinate alike,
// so eight particles' vectors are read as they lie in memory, dim registers of eight numbers
// each, with no transposes: the per-particle numbers (inverse mass, inverse moment of inertia)
// are spread over their particle's dim numbers by a permutation, and the periodic box's bounds
// are laid out in the same pattern. Only the squared displacements are regrouped by particle,
// to sum each particle's dim squares. Wrapping a position and separations a period or more
// long, which happen to a handful of particles in a step, go through Domain itself. Without
// fused multiply-adds the same bits as the scalar pass (tests/unit/packet_particle_pass.cpp).
#include <algorithm>
#include <cstddef>
#include <limits>
#include <type_traits>
#include <utility>

#include <Eigen/Core>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/domain.hpp"
#include "micromacro/core/inline.hpp"
#include "micromacro/core/packets.hpp"
#include "micromacro/core/parallel.hpp"
#include "micromacro/engine/force_change_kick.hpp"

namespace micromacro::detail {

/// What a kick-drift pass reports: the largest and the summed squared displacements from the
/// references, and the kinetic energy the particles that crossed a moving cell's boundary gained
/// by taking their images' velocities (Domain::wrap; the cell's work, EnergyBooks::work_by_cell).
struct DriftTotals {
    double max_move_sq = 0.0, sum_move_sq = 0.0, wrap_energy = 0.0;
};

/// The kinetic energy a particle of inverse mass inv_m gains when its velocity changes from
/// `before` to `after` (nothing for one of infinite mass).
template <int dim>
double kinetic_change(const Vec<dim>& before, const Vec<dim>& after, double inv_m) {
    return inv_m > 0.0 ? 0.5 * (after.squaredNorm() - before.squaredNorm()) / inv_m : 0.0;
}

/// Whether the kick-drift pass runs on packets: double storage, where the compiler targets
/// AVX-512.
template <class Real>
constexpr bool packet_particle_pass_applies =
#ifdef MICROMACRO_PACKETS
    std::is_same_v<Real, double>;
#else
    false;
#endif

#ifdef MICROMACRO_PACKETS
/// How eight particles' dim-vectors lie in dim registers: which particle (spread) and which
/// axis each of the 8 dim numbers belongs to, and the box's bounds in that pattern.
template <int dim>
struct PacketLayout {
    __m512i spread[dim];  ///< register r, lane l: the particle of number 8 r + l
    packets::Lane lo[dim], hi[dim], half[dim], period[dim];
    packets::Mask periodic[dim];
    /// Where particle l's x, y and z are: lanes of registers 0 and 1 taken together, and in 3D
    /// the last particles' lanes of register 2 (see squares; 2D has no z).
    __m512i x_of, y_of, z_of;

    explicit PacketLayout(const Domain<dim>& domain) {
        alignas(64) long long particle[dim][8];
        alignas(64) double lo_at[dim][8], hi_at[dim][8], half_at[dim][8], period_at[dim][8];
        for (int r = 0; r < dim; ++r) {
            periodic[r] = 0;
            for (int l = 0; l < 8; ++l) {
                const int number = 8 * r + l, axis = number % dim;
                particle[r][l] = number / dim;
                const double length = domain.hi()[axis] - domain.lo()[axis];
                lo_at[r][l] = domain.lo()[axis];
                hi_at[r][l] = domain.hi()[axis];
                // In a tilted box an image moves the lower axes too: every lane past half a period
                // is then sent to Domain::separation (nearest_image's "a period or more apart").
                period_at[r][l] = domain.tilted() ? 0.5 * length : length;
                half_at[r][l] = domain.periodic(axis) ? 0.5 * length : std::numeric_limits<double>::infinity();
                if (domain.periodic(axis)) periodic[r] = packets::Mask(periodic[r] | (1u << l));
            }
            spread[r] = _mm512_load_si512(particle[r]);
            lo[r] = _mm512_load_pd(lo_at[r]);
            hi[r] = _mm512_load_pd(hi_at[r]);
            half[r] = _mm512_load_pd(half_at[r]);
            period[r] = _mm512_load_pd(period_at[r]);
        }
        // Number a of particle l is number dim l + a of the eight: in 2D lanes 2 l + a of the
        // pair of registers; in 3D 3 l + a, the last two or three of them in register 2.
        if constexpr (dim == 2) {
            x_of = _mm512_set_epi64(14, 12, 10, 8, 6, 4, 2, 0);
            y_of = _mm512_set_epi64(15, 13, 11, 9, 7, 5, 3, 1);
            z_of = x_of;
        } else {
            x_of = _mm512_set_epi64(5, 2, 15, 12, 9, 6, 3, 0);    // lanes 6, 7 from register 2
            y_of = _mm512_set_epi64(6, 3, 0, 13, 10, 7, 4, 1);    // lanes 5-7 from register 2
            z_of = _mm512_set_epi64(7, 4, 1, 14, 11, 8, 5, 2);    // lanes 5-7 from register 2
        }
    }

    /// The per-particle numbers of eight particles spread over register r's numbers.
    MICROMACRO_INLINE packets::Lane spread_over(packets::Lane per_particle, int r) const {
        return _mm512_maskz_permutexvar_pd(0xFF, spread[r], per_particle);
    }

    /// The sum of each particle's squares, in lanes l: (x^2 + y^2) + z^2, as Eigen sums a
    /// squared norm.
    MICROMACRO_INLINE packets::Lane squares(const packets::Lane* s) const {
        using packets::Lane;
        const Lane x = _mm512_permutex2var_pd(s[0], x_of, s[1]);
        const Lane y = _mm512_permutex2var_pd(s[0], y_of, s[1]);
        if constexpr (dim == 2) {
            return x + y;
        } else {
            const Lane z = _mm512_permutex2var_pd(s[0], z_of, s[1]);
            return (_mm512_mask_permutexvar_pd(x, 0xC0, x_of, s[2]) + _mm512_mask_permutexvar_pd(y, 0xE0, y_of, s[2])) +
                   _mm512_mask_permutexvar_pd(z, 0xE0, z_of, s[2]);
        }
    }
};

/// kick_drift_pass over the first 8 floor(n / 8) particles, eight at a time; the arguments and
/// the result as kick_drift_pass's, which calls it and does the rest.
template <bool periodic, bool rotation, bool keeps_previous_forces, int dim, class Arrays>
DriftTotals packet_kick_drift_pass(const Arrays& a, const Domain<dim>& box, double h_before, double dt,
                                                 double h_after, double h_closing, [[maybe_unused]] int threads) {
    namespace pk = packets;
    using pk::Lane;
    using pk::Mask;
    constexpr int rows = dim;                           // registers per eight particles' vectors
    constexpr int spin_rows = dim == 2 ? 1 : 3;         // and per eight particles' spins
    double* x = a.x->data();
    double* v = a.v->data();
    double* f = a.f->data();
    const double* inv_m = a.inv_m;
    [[maybe_unused]] double* w = nullptr;
    [[maybe_unused]] double* torque = nullptr;
    [[maybe_unused]] const double* inv_I = a.inv_I;
    [[maybe_unused]] double* f_old = nullptr;
    [[maybe_unused]] double* torque_old = nullptr;
    const double* reference = a.reference->data();
    if constexpr (rotation) {
        w = reinterpret_cast<double*>(a.w);
        torque = reinterpret_cast<double*>(a.torque);
    }
    if constexpr (keeps_previous_forces) {
        f_old = a.f_old->data();
        if constexpr (rotation) torque_old = reinterpret_cast<double*>(a.torque_old);
    }
    const Domain<dim> domain = box;  // a local copy, as in kick_drift_pass
    const PacketLayout<dim> layout(domain);
    const std::size_t count = a.n / 8;
    const double h_spin = h_before + h_after;
    double max_move_sq = 0.0, sum_move_sq = 0.0, wrap_energy = 0.0;
    // One share of the packets per thread, its largest and summed displacements in lanes until
    // the end (firstprivate: see kick_drift_pass).
    MICROMACRO_OMP(omp parallel num_threads(threads) reduction(max : max_move_sq) reduction(+ : sum_move_sq, wrap_energy)
                       firstprivate(x, v, f, inv_m, w, torque, inv_I, f_old, torque_old, reference, domain, layout, h_before,
                                    dt, h_after, h_closing, h_spin) if (threads > 1))
    {
        const int shares = thread_count(), t = thread_number();
        Lane largest = pk::zeros(), sum = pk::zeros();
        for (std::size_t p = share_begin(count, t, shares), end = share_begin(count, t + 1, shares); p < end; ++p) {
            const std::size_t at = 8 * dim * p;  // the packet's first number in the vector arrays
            const Lane inverse_masses = _mm512_loadu_pd(inv_m + 8 * p);
            Lane position[rows];
            for (int r = 0; r < rows; ++r) {
                const std::size_t k = at + 8 * std::size_t(r);
                const Lane inv_mass = layout.spread_over(inverse_masses, r), force = _mm512_loadu_pd(f + k);
                Lane velocity = _mm512_loadu_pd(v + k);
                if constexpr (keeps_previous_forces) {
                    if (h_closing != 0.0)
                        velocity = force_change_kick(velocity, pk::broadcast(h_closing) * inv_mass, force, _mm512_loadu_pd(f_old + k));
                    _mm512_storeu_pd(f_old + k, pk::zeros());
                }
                const Lane acceleration = inv_mass * force;
                velocity = velocity + pk::broadcast(h_before) * acceleration;
                position[r] = _mm512_loadu_pd(x + k) + pk::broadcast(dt) * velocity;
                velocity = velocity + pk::broadcast(h_after) * acceleration;
                _mm512_storeu_pd(v + k, velocity);
                if constexpr (!keeps_previous_forces) _mm512_storeu_pd(f + k, pk::zeros());
            }
            if constexpr (periodic) {
                Mask outside = 0;
                for (int r = 0; r < rows; ++r)
                    outside |= (pk::less(position[r], layout.lo[r]) | pk::greater_equal(position[r], layout.hi[r])) &
                                layout.periodic[r];
                if (outside) [[unlikely]] {  // Domain::wrap, particle by particle (with its velocity in a moving cell)
                    alignas(64) double numbers[8 * dim];
                    for (int r = 0; r < rows; ++r) _mm512_store_pd(numbers + 8 * r, position[r]);
                    for (int l = 0; l < 8; ++l) {
                        Vec<dim> xl = Eigen::Map<const Vec<dim>>(numbers + dim * l);
                        Eigen::Map<Vec<dim>> vl(v + at + dim * std::size_t(l));
                        Vec<dim> velocity = vl;
                        if (domain.wrap(xl, velocity)) wrap_energy += kinetic_change<dim>(vl, velocity, inv_m[8 * p + std::size_t(l)]);
                        vl = velocity;
                        Eigen::Map<Vec<dim>>(numbers + dim * l) = xl;
                    }
                    for (int r = 0; r < rows; ++r) position[r] = _mm512_load_pd(numbers + 8 * r);
                }
            }
            Lane move[rows];
            Mask far = 0;
            for (int r = 0; r < rows; ++r) {
                const std::size_t k = at + 8 * std::size_t(r);
                _mm512_storeu_pd(x + k, position[r]);
                move[r] = position[r] - _mm512_loadu_pd(reference + k);
                if constexpr (periodic) far |= pk::nearest_image(move[r], layout.half[r], layout.period[r], 0xFF);
            }
            if constexpr (periodic) {
                if (far) [[unlikely]] {  // a period or more from the reference: Domain::separation itself
                    alignas(64) double numbers[8 * dim];
                    for (int l = 0; l < 8; ++l) {
                        const std::size_t i = 8 * p + std::size_t(l);
                        const Vec<dim> xi = Eigen::Map<const Vec<dim>>(x + dim * i), ri = Eigen::Map<const Vec<dim>>(reference + dim * i);
                        Eigen::Map<Vec<dim>>(numbers + dim * l) = domain.separation(xi, ri);
                    }
                    for (int r = 0; r < rows; ++r) move[r] = _mm512_load_pd(numbers + 8 * r);
                }
            }
            Lane squared[rows];
            for (int r = 0; r < rows; ++r) squared[r] = move[r] * move[r];
            const Lane move_sq = layout.squares(squared);
            // A NaN drops out of the maximum (max_pd returns its second operand when one is NaN), as
            // in the scalar pass; the sum keeps it.
            largest = _mm512_maskz_max_pd(0xFF, move_sq, largest);
            sum = sum + move_sq;
            if constexpr (rotation) {
                const Lane inverse_inertias = _mm512_loadu_pd(inv_I + 8 * p);
                for (int r = 0; r < spin_rows; ++r) {
                    const std::size_t k = 8 * spin_rows * p + 8 * std::size_t(r);
                    const Lane inv_inertia = dim == 2 ? inverse_inertias : layout.spread_over(inverse_inertias, r);
                    const Lane moment = _mm512_loadu_pd(torque + k);
                    Lane spin = _mm512_loadu_pd(w + k);
                    if constexpr (keeps_previous_forces) {
                        if (h_closing != 0.0)
                            spin = force_change_kick(spin, pk::broadcast(h_closing) * inv_inertia, moment, _mm512_loadu_pd(torque_old + k));
                        _mm512_storeu_pd(torque_old + k, pk::zeros());
                    }
                    _mm512_storeu_pd(w + k, spin + (pk::broadcast(h_spin) * inv_inertia) * moment);
                    if constexpr (!keeps_previous_forces) _mm512_storeu_pd(torque + k, pk::zeros());
                }
            }
        }
        alignas(64) double lanes[2][8];
        _mm512_store_pd(lanes[0], largest);
        _mm512_store_pd(lanes[1], sum);
        for (int l = 0; l < 8; ++l) {
            max_move_sq = lanes[0][l] > max_move_sq ? lanes[0][l] : max_move_sq;
            sum_move_sq += lanes[1][l];
        }
    }
    return {max_move_sq, sum_move_sq, wrap_energy};
}
#endif

}  // namespace micromacro::detail
