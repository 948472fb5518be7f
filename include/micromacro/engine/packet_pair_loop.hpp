#pragma once
// The pair loop of FrictionalLinear eight contacts at a time, in 2D and 3D, where the compiler
// targets AVX-512 (core/packets.hpp): the same three passes per block of candidates as the
// scalar loop (engine/pair_loop.hpp), each on packets of eight. The first pass finds the
// touching pairs in lanes and packs them into the block (compress); the force pass brings their
// velocities, spins and spring records into lanes by loads and transposes, evaluates the law on
// them (contact/frictional_packet.hpp), writes the springs back, and leaves each contact's force
// and torque arm in the block; a last scalar loop adds those to the particles in the list's
// order, as the scalar loop does, so that every particle's sum runs through its contacts in the
// same order and a run is the same on any number of threads. docs/performance.md has what it
// gains ("What made it fast").
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

#include "micromacro/contact/frictional_packet.hpp"
#include "micromacro/core/domain.hpp"
#include "micromacro/core/energy.hpp"
#include "micromacro/core/index.hpp"
#include "micromacro/core/packets.hpp"
#include "micromacro/engine/pair_force_sums.hpp"

namespace micromacro::detail {

/// Whether the pair loop of this scene runs on packets: FrictionalLinear (with rotation), where
/// the compiler targets AVX-512.
template <int dim, bool rotation, class Law>
constexpr bool packet_pair_loop_applies =
#ifdef MICROMACRO_PACKETS
    rotation && std::is_same_v<Law, FrictionalLinear>;
#else
    false;
#endif

#ifdef MICROMACRO_PACKETS
/// The block of candidates the packet loop works on: the touching ones packed, by position in
/// the block (at), particles (first, second), separation and its square, distance and inverse,
/// and the two radii (gathered once, in the first pass: 1.05x); the positions of those that do
/// not touch (apart); and what the force pass leaves for the sums (out: force, torque arm and
/// the books' three terms). Room for whole packets past the block's end: compressed stores
/// write eight lanes. Zeroed once: lanes past a block's last contact read these as particle 0,
/// or as an earlier block's particles.
struct PacketBlock {
    static constexpr std::size_t size = 128, room = size + packets::width;
    alignas(64) double sx[room] = {}, sy[room] = {}, sz[room] = {}, sq[room] = {}, distance[room] = {}, inverse[room] = {};
    alignas(64) double rad_i[room] = {}, rad_j[room] = {};
    alignas(64) double shift[3][room] = {};  // a moving cell's image shifts x_i - x_j - d (PacketBlock::sx...)
    alignas(64) std::uint32_t at[room] = {}, first[room] = {}, second[room] = {}, apart[room] = {};
    alignas(64) double out[10][room];  // force, arm, the books' three terms, the cell's power
};

/// The force pass over a block's `count` touching contacts, eight at a time: kinematics as
/// pair_loop's, the law (contact/frictional_packet.hpp), the springs written back. Lanes past
/// count repeat the last contact's record address, so that they read a record of this block;
/// nothing of theirs is stored, nor of a pair whose centres coincide (the scalar loop skips it;
/// the engine reports it). A function of its own: inlined into the loop, its registers and the
/// first pass's spilled each other (0.96x on the lattice of scripts/vs_lammps.sh).
template <bool track, int dim, class Real>
[[gnu::noinline]] void packet_forces(const FrictionalLinear& law, double dt, PacketBlock& block, std::size_t count,
                                     std::size_t b0, const Domain<dim>& domain, const Vec<dim, Real>* v,
                                     const Angular<dim, Real>* w, TangentialSpring<dim>* history) {
    namespace pk = packets;
    using pk::Lane;
    using pk::Mask;
    using Lanes = pk::LanesOf<dim>;
    auto& [sx, sy, sz, sq, distance, inverse, rad_i, rad_j, shift, at, first, second, apart, out] = block;
    for (std::size_t k0 = 0; k0 < count; k0 += pk::width) {
        const int lanes = int(std::min<std::size_t>(pk::width, count - k0));
        // The records' positions in the block by one load, the last contact's in the lanes past
        // count (written as at[min(l, lanes - 1)], GCC gathered them: 6% of the pass's samples).
        alignas(32) std::uint32_t slot[8];
        _mm256_store_si256(reinterpret_cast<__m256i*>(slot),
                           _mm256_mask_loadu_epi32(_mm256_set1_epi32(int(at[k0 + std::size_t(lanes - 1)])),
                                                   Mask((1u << lanes) - 1), at + k0));
        TangentialSpring<dim>* records[8];
        for (int l = 0; l < pk::width; ++l) records[l] = &history[b0 + slot[l]];
        const std::uint32_t* is = first + k0;
        const std::uint32_t* js = second + k0;
        const Lane ri = _mm512_load_pd(rad_i + k0), rj = _mm512_load_pd(rad_j + k0);
        const Lane inv = _mm512_load_pd(inverse + k0);
        pk::Kinematics<dim> c;
        Lanes dv = pk::load(v, is) - pk::load(v, js);
        const bool moving = domain.moving();
        Lanes image_velocity{};
        if (moving) [[unlikely]] {  // j's image moves with the cell: pair_velocity_difference in lanes
            Lane d[dim], image[dim];
            for (int a = 0; a < dim; ++a) d[a] = _mm512_load_pd(shift[a] + k0);
            const auto& L = domain.velocity_gradient();
            for (int a = 0; a < dim; ++a) {
                image[a] = pk::broadcast(L(a, 0)) * d[0];
                for (int b = 1; b < dim; ++b) image[a] = image[a] + pk::broadcast(L(a, b)) * d[b];
            }
            if constexpr (dim == 2) image_velocity = pk::Lanes2{image[0], image[1]};
            else image_velocity = pk::Lanes3{image[0], image[1], image[2]};
            dv = dv - image_velocity;
        }
        // contact_point_velocity (Eq. 25): n x (a_i w_i + a_j w_j)
        if constexpr (dim == 2) {
            c.normal = {_mm512_load_pd(sx + k0) * inv, _mm512_load_pd(sy + k0) * inv};
            const Lane spin = ri * pk::load_numbers(w, is) + rj * pk::load_numbers(w, js);
            c.relative_velocity = dv + pk::Lanes2{c.normal.y * spin, -c.normal.x * spin};
        } else {
            c.normal = {_mm512_load_pd(sx + k0) * inv, _mm512_load_pd(sy + k0) * inv, _mm512_load_pd(sz + k0) * inv};
            c.relative_velocity = dv + pk::cross(c.normal, ri * pk::load(w, is) + rj * pk::load(w, js));
        }
        c.overlap = (ri + rj) - _mm512_load_pd(distance + k0);
        c.normal_velocity = pk::dot(c.normal, dv);
        pk::Springs<dim> h = pk::load_springs(records);
        const pk::Response<dim> resp = pk::frictional_force<track>(law, c, dt, h);
        const Mask stored = Mask((1u << lanes) - 1) & _mm512_cmp_pd_mask(_mm512_load_pd(sq + k0), pk::zeros(), _CMP_NEQ_UQ);
        pk::store_springs(h, records, stored);
        const Lanes force = resp.normal * c.normal + resp.tangential;  // respond()
        _mm512_store_pd(out[0] + k0, force.x);
        _mm512_store_pd(out[1] + k0, force.y);
        if constexpr (dim == 2) {
            _mm512_store_pd(out[3] + k0, c.normal.x * resp.tangential.y - c.normal.y * resp.tangential.x);  // n x f_t
        } else {
            const pk::Lanes3 arm = pk::cross(c.normal, resp.tangential);
            _mm512_store_pd(out[2] + k0, force.z);
            _mm512_store_pd(out[3] + k0, arm.x);
            _mm512_store_pd(out[4] + k0, arm.y);
            _mm512_store_pd(out[5] + k0, arm.z);
        }
        if constexpr (track) {
            _mm512_store_pd(out[6] + k0, resp.viscous * c.normal_velocity * pk::broadcast(dt));
            _mm512_store_pd(out[7] + k0, resp.dissipated_viscous);
            _mm512_store_pd(out[8] + k0, resp.dissipated_sliding);
            if (moving) [[unlikely]]  // the cell's power through the contact, as in scalar_pair_loop
                _mm512_store_pd(out[9] + k0, pk::dot(force, image_velocity));
        }
    }
}

/// The pair loop over candidates [begin, end) on packets; the arguments and the result as for
/// pair_loop (engine/pair_loop.hpp), which calls it and then completes the opened contacts.
/// `In` is its ContactLoopInput.
template <bool track, bool periodic, bool weighed, int dim, class In>
void packet_pair_loop(const In& in, const Domain<dim>& domain, const FrictionalLinear& law, double dt, std::size_t begin,
                      std::size_t end, Vec<dim>* f, Angular<dim>* torque, EnergyBooks& books, IndexPair& coincident,
                      Index owned_end, std::vector<Spill<dim, true>>& spill, std::vector<std::size_t>& opened_contacts) {
    namespace pk = packets;
    using pk::Lane;
    using pk::Mask;
    const auto* x = in.x;
    const auto* v = in.v;
    const auto* w = in.w;
    const auto* r = in.r;
    const IndexPair* pair = in.pair;
    TangentialSpring<dim>* history = in.history;
    PacketBlock block_arrays;
    auto& [sx, sy, sz, sq, distance, inverse, rad_i, rad_j, shift, at, first, second, apart, out] = block_arrays;
    constexpr std::size_t block = PacketBlock::size;
    const Lane one = pk::broadcast(1.0);
    Lane period[dim], half[dim], tilt[dim][dim];
    const bool tilted = domain.tilted();
    for (int a = 0; a < dim; ++a) {
        const double length = domain.hi()[a] - domain.lo()[a];
        period[a] = pk::broadcast(length);
        half[a] = pk::broadcast(domain.periodic(a) ? 0.5 * length : std::numeric_limits<double>::infinity());
        for (int i = 0; i < a; ++i) tilt[i][a] = pk::broadcast(domain.tilt(i, a));
    }
    const __m256i lane = _mm256_set_epi32(7, 6, 5, 4, 3, 2, 1, 0);
    EnergyBooks account = books;
    const bool moving = domain.moving();
    for (std::size_t b0 = begin; b0 < end; b0 += block) {
        const std::size_t b1 = std::min(end, b0 + block);
        std::size_t count = 0, open = 0;
        // First pass: Domain::separation and the touch test of the scalar loop, in lanes.
        for (std::size_t p0 = b0; p0 < b1; p0 += pk::width) {
            const int lanes = int(std::min<std::size_t>(pk::width, b1 - p0));
            const Mask valid = Mask((1u << lanes) - 1);
            for (int l = 0; l < lanes; ++l) __builtin_prefetch(&history[p0 + l], 1);
            const __m512i pairs = _mm512_maskz_loadu_epi64(valid, pair + p0);  // {i, j}: i in the low half
            const __m256i is = _mm512_maskz_cvtepi64_epi32(0xFF, pairs),
                          js = _mm512_maskz_cvtepi64_epi32(0xFF, _mm512_maskz_srli_epi64(0xFF, pairs, 32));
            const IndexPair* here = pair + p0;  // lanes past the block's end read the packet's first pair
            const auto xi = pk::load_by(x, [&](int l) { return here[l < lanes ? l : 0].i; });
            const auto xj = pk::load_by(x, [&](int l) { return here[l < lanes ? l : 0].j; });
            Lane d[dim], raw[dim];
            d[0] = xi.x - xj.x;
            d[1] = xi.y - xj.y;
            if constexpr (dim == 3) d[2] = xi.z - xj.z;
            for (int a = 0; a < dim; ++a) raw[a] = d[a];
            if constexpr (periodic) {
                // Domain::separation in lanes. In a sheared cell from the last axis down: an image
                // across axis a moves the lower axes by its tilts, n t with n = +-1 the image's side.
                Mask far = 0;
                if (!tilted) [[likely]] {
                    for (int a = 0; a < dim; ++a) far |= pk::nearest_image(d[a], half[a], period[a], valid);
                } else {
                    for (int a = dim - 1; a >= 0; --a) {
                        const Lane before = d[a];
                        far |= pk::nearest_image(d[a], half[a], period[a], valid);
                        const Mask image = pk::greater_equal(_mm512_abs_pd(before), half[a]) & valid;
                        if (image)
                            for (int i = 0; i < a; ++i)
                                d[i] = _mm512_mask_sub_pd(d[i], image, d[i], pk::times_sign_of(tilt[i][a], before));
                    }
                }
                if (far) [[unlikely]] {  // a period or more apart: Domain::separation itself, lane by lane
                    alignas(64) double e[dim][8] = {};
                    for (int l = 0; l < lanes; ++l) {
                        const Vec<dim> s = domain.separation(convert<double>(x[here[l].i]), convert<double>(x[here[l].j]));
                        for (int a = 0; a < dim; ++a) e[a][l] = s[a];
                    }
                    for (int a = 0; a < dim; ++a) d[a] = _mm512_load_pd(e[a]);
                }
            }
            Lane dist_sq = d[0] * d[0] + d[1] * d[1];
            if constexpr (dim == 3) dist_sq = dist_sq + d[2] * d[2];
            const Lane ri = pk::load_numbers(r, is), rj = pk::load_numbers(r, js), reach = ri + rj;
            const Mask touches = pk::less(dist_sq, reach * reach) & valid, not_touching = Mask(~touches & valid);
            const __m256i position = _mm256_add_epi32(_mm256_set1_epi32(int(p0 - b0)), lane);
            _mm512_storeu_pd(sx + count, _mm512_maskz_compress_pd(touches, d[0]));
            _mm512_storeu_pd(sy + count, _mm512_maskz_compress_pd(touches, d[1]));
            if constexpr (dim == 3) _mm512_storeu_pd(sz + count, _mm512_maskz_compress_pd(touches, d[2]));
            _mm512_storeu_pd(sq + count, _mm512_maskz_compress_pd(touches, dist_sq));
            _mm512_storeu_pd(rad_i + count, _mm512_maskz_compress_pd(touches, ri));
            _mm512_storeu_pd(rad_j + count, _mm512_maskz_compress_pd(touches, rj));
            if (moving) [[unlikely]]  // the image shifts, for the image velocities of packet_forces
                for (int a = 0; a < dim; ++a) _mm512_storeu_pd(shift[a] + count, _mm512_maskz_compress_pd(touches, raw[a] - d[a]));
            _mm256_storeu_si256(reinterpret_cast<__m256i*>(at + count), _mm256_maskz_compress_epi32(touches, position));
            _mm256_storeu_si256(reinterpret_cast<__m256i*>(first + count), _mm256_maskz_compress_epi32(touches, is));
            _mm256_storeu_si256(reinterpret_cast<__m256i*>(second + count), _mm256_maskz_compress_epi32(touches, js));
            _mm256_storeu_si256(reinterpret_cast<__m256i*>(apart + open), _mm256_maskz_compress_epi32(not_touching, position));
            count += std::size_t(__builtin_popcount(touches));
            open += std::size_t(__builtin_popcount(not_touching));
        }
        for (std::size_t k = 0; k < open; ++k) {  // the contact opened, if it was one
            TangentialSpring<dim>& h = history[b0 + apart[k]];
            if (law.touched(h)) [[unlikely]]
                opened_contacts.push_back(b0 + apart[k]);
            else
                h = TangentialSpring<dim>{};
        }
        if (count == 0) continue;
        for (std::size_t k = 0; k < count; k += pk::width) {  // whole packets: past count, zeros or an earlier block's
            const Lane root = _mm512_maskz_sqrt_pd(0xFF, _mm512_load_pd(sq + k));
            _mm512_store_pd(distance + k, root);
            _mm512_store_pd(inverse + k, one / root);
        }
        packet_forces<track, dim>(law, dt, block_arrays, count, b0, domain, v, w, history);
        // The sums, in the list's order (engine/pair_force_sums.hpp and respond()'s books): i's
        // sums held while its run of partners lasts (the list takes each i's partners together; j
        // is never i, so no other contact of the run writes i's sums meanwhile).
        Index current = first[0];
        Vec<dim> fi = f[current];
        Angular<dim> ti = torque[current];
        double ri = double(r[current]);
        for (std::size_t k = 0; k < count; ++k) {
            const Index i = first[k], j = second[k];
            if (sq[k] == 0.0) [[unlikely]] {
                coincident = pair[b0 + at[k]];
                continue;
            }
            if (i != current) {
                f[current] = fi;
                torque[current] = ti;
                current = i;
                fi = f[i];
                ti = torque[i];
                ri = double(r[i]);
            }
            if constexpr (track) {
                const double weight = weighed && std::max(i, j) >= in.first_ghost ? 0.5 : 1.0;
                account.dissipated_normal -= weight * out[6][k];
                account.dissipated_tangential += weight * out[7][k];
                account.dissipated_sliding += weight * out[8][k];
            }
            Vec<dim> force;
            Angular<dim> arm;
            if constexpr (dim == 2) {
                force = Vec<2>(out[0][k], out[1][k]);
                arm = out[3][k];
            } else {
                force = Vec<3>(out[0][k], out[1][k], out[2][k]);
                arm = Vec<3>(out[3][k], out[4][k], out[5][k]);
            }
            fi += force;
            ti -= Angular<dim>(ri * arm);  // torque on i is (-a_i n) x f_t
            add_partner_force<dim, true>(j, force, arm, double(r[j]), f, torque, owned_end, spill);
        }
        f[current] = fi;
        torque[current] = ti;
        // The cell's power through each contact (packet_forces), added in the list's order as
        // scalar_pair_loop adds it; a loop of its own: inside the one above its sum went through
        // memory for each contact (0.87x in a sheared 2D cell). Only a contact with a moving image
        // (across the cell's boundary, a few percent) has power; the others' exact zeros, which
        // leave the sum as it is to the bit, are skipped eight at a time, so that the sum's chain
        // of additions runs over the few (the chain over all was most of a sheared cell's cost).
        if constexpr (track && periodic)
            if (moving) [[unlikely]] {
                double cell_work = account.work_by_cell;
                for (std::size_t k0 = 0; k0 < count; k0 += pk::width) {
                    const Mask in_block = count - k0 >= std::size_t(pk::width) ? Mask(0xFF) : Mask((1u << (count - k0)) - 1);
                    unsigned powered = _mm512_cmp_pd_mask(_mm512_load_pd(out[9] + k0), pk::zeros(), _CMP_NEQ_UQ) & in_block;
                    for (; powered != 0; powered &= powered - 1) {
                        const std::size_t k = k0 + std::size_t(__builtin_ctz(powered));
                        if (sq[k] == 0.0) [[unlikely]] continue;
                        const double weight = weighed && std::max(first[k], second[k]) >= in.first_ghost ? 0.5 : 1.0;
                        cell_work += weight * out[9][k] * dt;
                    }
                }
                account.work_by_cell = cell_work;
            }
    }
    books = account;
}
#endif

}  // namespace micromacro::detail
