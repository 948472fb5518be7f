#pragma once
// FrictionalLinear (the linear spring-dashpot with the Cundall-Strack spring, Eq. 21-29) for
// eight contacts at once, one per lane, in 2D and 3D: LinearSpringDashpot::force and
// CundallStrack::force_along_line (2D) and force_in_plane (3D) written again on lanes
// (core/packets.hpp), expression for expression, so that without fused multiply-adds each lane
// gives the scalar law's bits (tests/unit/packets.cpp compares the two on every branch: new,
// sticking, sliding, the static/dynamic hysteresis, tension). The engine's pair loop takes this
// form of the law where the compiler targets AVX-512 (engine/packet_pair_loop.hpp). A change to
// the scalar law must be made here too; the test fails until it is.
#include <cstdint>
#include <type_traits>

#include "micromacro/contact/contact_law.hpp"
#include "micromacro/contact/tangential_history.hpp"
#include "micromacro/core/packets.hpp"

#ifdef MICROMACRO_PACKETS
namespace micromacro::packets {

/// What the law sees of eight contacts (ContactKinematics without the radii and masses, which
/// this law does not use).
template <int dim>
struct Kinematics {
    LanesOf<dim> normal;
    Lane overlap, normal_velocity;
    LanesOf<dim> relative_velocity;
};

/// Eight spring records (TangentialSpring<dim>) in lanes. A record is 2 dim + 1 8-byte words:
/// the spring, the advance (vectors in 3D, components along the tangent in 2D) and a last word
/// holding trial (a float) and the flags sliding, touching and fresh, one byte each
/// (tests/unit/packets.cpp checks the layout).
template <int dim>
struct Springs;
template <>
struct Springs<2> {
    Lane spring, ahead;
    __m512i word;  ///< the last word of each record
};
template <>
struct Springs<3> {
    Lanes3 spring, ahead;
    __m512i word;
};
static_assert(sizeof(TangentialSpring<3>) == 7 * sizeof(double), "a 3D spring record is seven words");
static_assert(sizeof(TangentialSpring<2>) == 3 * sizeof(double), "a 2D spring record is three words");
constexpr int sliding_bit = 32, touching_bit = 40, fresh_bit = 48;

/// The records at records[0..7] into lanes: each read whole (a masked load of its words), then
/// transposed.
template <int dim>
MICROMACRO_INLINE Springs<dim> load_springs(TangentialSpring<dim>* const* records) {
    constexpr Mask words = dim == 2 ? 0x7 : 0x7F;
    Lane rows[8];
    for (int l = 0; l < width; ++l) rows[l] = _mm512_maskz_loadu_pd(words, reinterpret_cast<const double*>(records[l]));
    transpose(rows);
    if constexpr (dim == 2) return {rows[0], rows[1], _mm512_castpd_si512(rows[2])};
    else return {{rows[0], rows[1], rows[2]}, {rows[3], rows[4], rows[5]}, _mm512_castpd_si512(rows[6])};
}

/// The lanes set in `m` back into their records.
template <int dim>
MICROMACRO_INLINE void store_springs(const Springs<dim>& s, TangentialSpring<dim>* const* records, Mask m) {
    constexpr Mask words = dim == 2 ? 0x7 : 0x7F;
    Lane rows[8];
    if constexpr (dim == 2) {
        rows[0] = s.spring;
        rows[1] = s.ahead;
        rows[2] = _mm512_castsi512_pd(s.word);
        for (int k = 3; k < 8; ++k) rows[k] = zeros();
    } else {
        Lane r[8] = {s.spring.x, s.spring.y, s.spring.z, s.ahead.x, s.ahead.y, s.ahead.z, _mm512_castsi512_pd(s.word), zeros()};
        for (int k = 0; k < 8; ++k) rows[k] = r[k];
    }
    transpose(rows);
    for (int l = 0; l < width; ++l)
        if (m >> l & 1) _mm512_mask_storeu_pd(reinterpret_cast<double*>(records[l]), words, rows[l]);
}

/// The flags of the last word after an evaluation: touching, sliding where `sliding`, fresh
/// where it was not touching before; trial as given.
MICROMACRO_INLINE __m512i flags_after(__m512i word, Mask sliding, Mask touching) {
    word = _mm512_or_si512(word, _mm512_set1_epi64(std::int64_t{1} << touching_bit));
    word = _mm512_mask_or_epi64(word, sliding, word, _mm512_set1_epi64(std::int64_t{1} << sliding_bit));
    return _mm512_mask_or_epi64(word, Mask(~touching), word, _mm512_set1_epi64(std::int64_t{1} << fresh_bit));
}

/// CundallStrack::time_in_contact in every lane: overlap / approach speed, at most dt; 0 unless
/// approaching.
MICROMACRO_INLINE Lane time_in_contact(Lane overlap, Lane normal_velocity, double dt) {
    const Lane approach = -normal_velocity, zero = zeros();
    const Mask approaching = less(normal_velocity, zero), recent = less(overlap, approach * broadcast(dt));
    return select(approaching, select(recent, _mm512_maskz_div_pd(recent & approaching, overlap, approach), broadcast(dt)), zero);
}

/// float(magnitude) in the low half of each lane's word where m is set.
MICROMACRO_INLINE __m512i with_trial(__m512i word, Mask m, Lane magnitude) {
    return _mm512_mask_mov_epi64(word, m, _mm512_maskz_cvtepu32_epi64(0xFF, _mm256_castps_si256(_mm512_maskz_cvtpd_ps(0xFF, magnitude))));
}

MICROMACRO_INLINE Mask flag(const __m512i& word, int bit) { return _mm512_test_epi64_mask(word, _mm512_set1_epi64(std::int64_t{0xff} << bit)); }

/// The force of eight contacts, as ContactResponse gives one: the normal force along n (with
/// its viscous part for the books), the tangential force, and with `track` what the tangential
/// part dissipated (TangentialForce's two numbers).
template <int dim>
struct Response {
    Lane normal, viscous;
    LanesOf<dim> tangential;
    Lane dissipated_viscous, dissipated_sliding;
};

/// LinearSpringDashpot::force in every lane: the normal force and its viscous part.
template <int dim>
MICROMACRO_INLINE Response<dim> normal_part(const FrictionalLinear& law, const Kinematics<dim>& c) {
    Response<dim> out;
    const Lane elastic = broadcast(law.normal.stiffness()) * c.overlap;
    out.viscous = broadcast(-law.normal.damping()) * c.normal_velocity;
    out.normal = elastic + out.viscous;
    return out;
}

/// FrictionalLinear::force<track> in 3D in every lane, advancing the springs h (see
/// CundallStrack::force_in_plane for the time stepping and the Coulomb rule).
template <bool track>
MICROMACRO_INLINE Response<3> frictional_force(const FrictionalLinear& law, const Kinematics<3>& c, double dt, Springs<3>& h) {
    const Lanes3& n = c.normal;
    const Lane zero = zeros(), vn = c.normal_velocity, overlap = c.overlap;
    const double kt = law.tangential.stiffness(), gamma_t = law.tangential.damping();
    Response<3> out = normal_part<3>(law, c);
    // CundallStrack::force_in_plane
    const Mask touching = flag(h.word, touching_bit), was_sliding = flag(h.word, sliding_bit);
    const Lanes3 vt = c.relative_velocity - n * vn;                                          // Eq. 24
    const Lanes3 base = select(touching, h.ahead, Lanes3{zero, zero, zero});
    const Lane span = select(touching, broadcast((2.0 / 3.0) * dt), time_in_contact(overlap, vn, dt));
    const Lanes3 spring = base - n * dot(n, base) + span * vt;                               // Eq. 23, 27
    const Lanes3 motion = select(touching, spring - h.spring, broadcast(dt) * vt);
    const Lanes3 trial = broadcast(-kt) * spring - broadcast(gamma_t) * vt;                  // Eq. 26
    const Lane fn = select(less(out.normal, zero), zero, out.normal);
    const Lane trial_sq = dot(trial, trial), static_limit = broadcast(law.tangential.mu_static()) * fn,
               dynamic_limit = broadcast(law.tangential.mu_dynamic()) * fn;
    const Mask sliding = greater(trial_sq, static_limit * static_limit) |
                         (was_sliding & greater_equal(trial_sq, dynamic_limit * dynamic_limit) & greater_equal(dot(vt, h.spring), zero));
    out.tangential = trial;
    Lanes3 kept = spring;
    out.dissipated_viscous = zero;
    out.dissipated_sliding = zero;
    if constexpr (track) out.dissipated_viscous = select(sliding, zero, broadcast(gamma_t) * dot(vt, vt) * broadcast(dt));
    __m512i word = _mm512_and_si512(h.word, _mm512_set1_epi64(0xffffffff));  // trial kept unless sliding
    if (sliding) [[unlikely]] {
        const Lane magnitude = _mm512_maskz_sqrt_pd(sliding, trial_sq);
        const Mask positive = greater(magnitude, zero) & sliding;
        const Lanes3 t{_mm512_maskz_div_pd(positive, trial.x, magnitude), _mm512_maskz_div_pd(positive, trial.y, magnitude),
                       _mm512_maskz_div_pd(positive, trial.z, magnitude)};
        const Lanes3 force = dynamic_limit * t;                                              // Eq. 29
        const Lanes3 at_limit = -(dynamic_limit / broadcast(kt)) * t;                        // Eq. 28
        if constexpr (track) {
            const Lanes3 stored = h.spring - n * dot(n, h.spring);                           // Eq. 23
            const Lane half_kt = broadcast(0.5 * kt);
            const Lane work = broadcast(0.5) * dot(broadcast(kt) * stored - force, spring - stored) -
                              (half_kt * dot(at_limit, at_limit) - half_kt * dot(h.spring, h.spring));
            out.dissipated_sliding = select(sliding, work, zero);
        }
        out.tangential = select(sliding, force, trial);
        kept = select(sliding, at_limit, spring);
        word = with_trial(word, sliding, magnitude);
    }
    h.spring = kept;
    h.ahead = kept + broadcast(1.0 / 3.0) * motion;
    h.word = flags_after(word, sliding, touching);
    return out;
}

/// FrictionalLinear::force<track> in 2D in every lane: CundallStrack::force_along_line, the
/// spring a component along the tangent t = (-n_y, n_x).
template <bool track>
MICROMACRO_INLINE Response<2> frictional_force(const FrictionalLinear& law, const Kinematics<2>& c, double dt, Springs<2>& h) {
    const Lanes2& n = c.normal;
    const Lane zero = zeros(), vn = c.normal_velocity, overlap = c.overlap;
    const double kt = law.tangential.stiffness(), gamma_t = law.tangential.damping();
    Response<2> out = normal_part<2>(law, c);
    const Mask touching = flag(h.word, touching_bit), was_sliding = flag(h.word, sliding_bit);
    const Lanes2 t{-n.y, n.x};
    const Lane vt = dot(t, c.relative_velocity);                                                // Eq. 24
    const Lane spring = select(touching, h.ahead + broadcast((2.0 / 3.0) * dt) * vt,            // Eq. 23, 27
                               time_in_contact(overlap, vn, dt) * vt);
    const Lane motion = select(touching, spring - h.spring, broadcast(dt) * vt);
    const Lane trial = broadcast(-kt) * spring - broadcast(gamma_t) * vt;                       // Eq. 26
    const Lane fn = select(less(out.normal, zero), zero, out.normal);
    const Lane magnitude = _mm512_abs_pd(trial), static_limit = broadcast(law.tangential.mu_static()) * fn,
               dynamic_limit = broadcast(law.tangential.mu_dynamic()) * fn;
    const Mask sliding = greater(magnitude, static_limit) |
                         (was_sliding & greater_equal(magnitude, dynamic_limit) & greater_equal(vt * h.spring, zero));
    Lane along = trial, kept = spring;
    out.dissipated_viscous = zero;
    out.dissipated_sliding = zero;
    if constexpr (track) out.dissipated_viscous = select(sliding, zero, broadcast(gamma_t) * vt * vt * broadcast(dt));
    __m512i word = _mm512_and_si512(h.word, _mm512_set1_epi64(0xffffffff));  // trial kept unless sliding
    if (sliding) [[unlikely]] {
        const Lane direction = select(greater(trial, zero), broadcast(1.0), select(less(trial, zero), broadcast(-1.0), zero));
        const Lane force = dynamic_limit * direction;                                           // Eq. 29
        if constexpr (track) {
            const Lane stored = h.spring;
            const Lane work = broadcast(0.5) * (broadcast(kt) * stored - force) * (spring - stored) -
                              broadcast(0.5) * (force * force / broadcast(kt) - broadcast(kt) * stored * stored);
            out.dissipated_sliding = select(sliding, work, zero);
        }
        along = select(sliding, force, trial);
        kept = select(sliding, -force / broadcast(kt), spring);                                 // Eq. 28
        word = with_trial(word, sliding, magnitude);
    }
    out.tangential = along * t;
    h.spring = kept;
    h.ahead = kept + broadcast(1.0 / 3.0) * motion;
    h.word = flags_after(word, sliding, touching);
    return out;
}

}  // namespace micromacro::packets
#endif
