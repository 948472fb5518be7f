#pragma once
// Eight doubles at a time in one AVX-512 register, where the compiler targets AVX-512: the lanes
// in which the pair loop evaluates eight contacts at once (engine/packet_pair_loop.hpp), and
// how numbers stored one particle or one record after another are brought into lanes and back.
// Vectors and records come by loads and transposes: gathering and scattering them number by
// number cost more than the lanes save on the CPUs measured (docs/performance.md); single
// numbers (radii, 2D spins) by a gather each.
//
// The arithmetic on lanes is written with the compiler's vector operators (a + b, a * b), so
// that it rounds and fuses as the scalar code beside it does under the build's -ffp-contract:
// without fused multiply-adds a lane computes what the scalar expression of the same shape
// computes, to the bit.
#include <cstdint>
#include <limits>
#include <type_traits>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/inline.hpp"

// The compiler targets AVX-512: __AVX512F__, or, in the project's builds, __AVX512VL__ (they
// hide __AVX512F__ from Eigen with -U__AVX512F__ and keep the instructions; CMakeLists.txt).
#if defined(__AVX512F__) || defined(__AVX512VL__)
#include <immintrin.h>
#define MICROMACRO_PACKETS 1
#endif

#ifdef MICROMACRO_PACKETS
namespace micromacro::packets {

using Lane = __m512d;    ///< eight doubles, one per contact
using Mask = __mmask8;   ///< one bit per lane
constexpr int width = 8;

/// Every lane a. (set_pd, not set1_pd: GCC 12's set1 passes an undefined vector that
/// -Wmaybe-uninitialized reports.)
MICROMACRO_INLINE Lane broadcast(double a) { return _mm512_set_pd(a, a, a, a, a, a, a, a); }
MICROMACRO_INLINE Lane zeros() { return _mm512_setzero_pd(); }

/// Three lanes: a 3-vector per contact.
struct Lanes3 {
    Lane x, y, z;
};
MICROMACRO_INLINE Lanes3 operator+(const Lanes3& a, const Lanes3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
MICROMACRO_INLINE Lanes3 operator-(const Lanes3& a, const Lanes3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
MICROMACRO_INLINE Lanes3 operator*(Lane s, const Lanes3& a) { return {s * a.x, s * a.y, s * a.z}; }
MICROMACRO_INLINE Lanes3 operator*(const Lanes3& a, Lane s) { return {a.x * s, a.y * s, a.z * s}; }
/// a . b as Eigen sums a 3-vector's products: (x + y) + z.
MICROMACRO_INLINE Lane dot(const Lanes3& a, const Lanes3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
/// a x b, each component as Eigen writes it.
MICROMACRO_INLINE Lanes3 cross(const Lanes3& a, const Lanes3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/// Two lanes: a 2-vector per contact.
struct Lanes2 {
    Lane x, y;
};
MICROMACRO_INLINE Lanes2 operator+(const Lanes2& a, const Lanes2& b) { return {a.x + b.x, a.y + b.y}; }
MICROMACRO_INLINE Lanes2 operator-(const Lanes2& a, const Lanes2& b) { return {a.x - b.x, a.y - b.y}; }
MICROMACRO_INLINE Lanes2 operator*(Lane s, const Lanes2& a) { return {s * a.x, s * a.y}; }
MICROMACRO_INLINE Lanes2 operator*(const Lanes2& a, Lane s) { return {a.x * s, a.y * s}; }
MICROMACRO_INLINE Lane dot(const Lanes2& a, const Lanes2& b) { return a.x * b.x + a.y * b.y; }
/// A vector per contact in dim dimensions.
template <int dim>
using LanesOf = std::conditional_t<dim == 2, Lanes2, Lanes3>;

/// The lanes of `when` where m is set, else of `otherwise`.
MICROMACRO_INLINE Lane select(Mask m, Lane when, Lane otherwise) { return _mm512_mask_blend_pd(m, otherwise, when); }
MICROMACRO_INLINE Lanes3 select(Mask m, const Lanes3& when, const Lanes3& otherwise) {
    return {select(m, when.x, otherwise.x), select(m, when.y, otherwise.y), select(m, when.z, otherwise.z)};
}
MICROMACRO_INLINE Mask less(Lane a, Lane b) { return _mm512_cmp_pd_mask(a, b, _CMP_LT_OQ); }
MICROMACRO_INLINE Mask greater(Lane a, Lane b) { return _mm512_cmp_pd_mask(a, b, _CMP_GT_OQ); }
MICROMACRO_INLINE Mask greater_equal(Lane a, Lane b) { return _mm512_cmp_pd_mask(a, b, _CMP_GE_OQ); }

/// Domain::separation's minimum image on one axis, in the lanes of `valid`: d -+ L where
/// |d| >= L/2 (`half` infinite on an open axis), as Domain::nearest_image does for wrapped
/// positions, which are less than a period apart. Returns the lanes that were a period or more
/// apart: for those the caller needs Domain::separation itself.
MICROMACRO_INLINE Mask nearest_image(Lane& d, Lane half, Lane period, Mask valid) {
    const Lane size = _mm512_abs_pd(d);
    const Mask image = greater_equal(size, half) & valid;
    if (!image) [[likely]]
        return 0;
    const Lane sign = _mm512_castsi512_pd(_mm512_set1_epi64(std::numeric_limits<std::int64_t>::min()));
    d = _mm512_mask_sub_pd(d, image, d, _mm512_or_pd(_mm512_and_pd(d, sign), period));  // d - copysign(L, d)
    return greater_equal(size, period) & image;
}

/// t times the sign of s (+-1), lane by lane: what n t is in Domain's n = +-1 images (exact).
MICROMACRO_INLINE Lane times_sign_of(Lane t, Lane s) {
    const Lane sign = _mm512_castsi512_pd(_mm512_set1_epi64(std::numeric_limits<std::int64_t>::min()));
    return _mm512_xor_pd(t, _mm512_and_pd(s, sign));
}

namespace detail {
/// The first three numbers at p, as doubles, in the low three of four (the fourth zero): a
/// masked load, which reads nothing past the vector's end.
MICROMACRO_INLINE __m256d load_three(const double* p) { return _mm256_maskz_loadu_pd(0x7, p); }
MICROMACRO_INLINE __m256d load_three(const float* p) { return _mm256_cvtps_pd(_mm_maskz_loadu_ps(0x7, p)); }
}  // namespace detail

/// The 3-vectors base[index(l)] of eight particles in lanes l (index: lane -> particle): four
/// of them per pair of 256-bit halves, then an 8 x 4 transpose (four unpacks and three permutes).
template <class Real, class IndexOf>
MICROMACRO_INLINE Lanes3 load_by(const Vec<3, Real>* base, IndexOf index) {
    const auto at = [&](int l) { return detail::load_three(base[index(l)].data()); };
    const auto pair = [&](int a, int b) { return _mm512_maskz_insertf64x4(0xFF, _mm512_castpd256_pd512(at(a)), at(b), 1); };
    const Lane a01 = pair(0, 1), a23 = pair(2, 3), a45 = pair(4, 5), a67 = pair(6, 7);
    // lo0 = [x0 x2 z0 z2 x1 x3 z1 z3], hi0 = [y0 y2 0 0 y1 y3 0 0], and the same for 4-7.
    const Lane lo0 = _mm512_maskz_unpacklo_pd(0xFF, a01, a23), hi0 = _mm512_maskz_unpackhi_pd(0xFF, a01, a23);
    const Lane lo1 = _mm512_maskz_unpacklo_pd(0xFF, a45, a67), hi1 = _mm512_maskz_unpackhi_pd(0xFF, a45, a67);
    const __m512i first = _mm512_set_epi64(13, 9, 12, 8, 5, 1, 4, 0), third = _mm512_set_epi64(15, 11, 14, 10, 7, 3, 6, 2);
    return {_mm512_permutex2var_pd(lo0, first, lo1), _mm512_permutex2var_pd(hi0, first, hi1), _mm512_permutex2var_pd(lo0, third, lo1)};
}
/// The 2-vectors base[index(l)] of eight particles in lanes l: four to a register, then two
/// permutes.
template <class Real, class IndexOf>
MICROMACRO_INLINE Lanes2 load_by(const Vec<2, Real>* base, IndexOf index) {
    const auto at = [&](int l) {
        if constexpr (sizeof(Real) == sizeof(double)) return _mm_loadu_pd(base[index(l)].data());
        else return _mm_cvtps_pd(_mm_castpd_ps(_mm_load_sd(reinterpret_cast<const double*>(base[index(l)].data()))));
    };
    const auto four = [&](int l) {
        const __m256d low = _mm256_insertf128_pd(_mm256_castpd128_pd256(at(l)), at(l + 1), 1);
        const __m256d high = _mm256_insertf128_pd(_mm256_castpd128_pd256(at(l + 2)), at(l + 3), 1);
        return _mm512_maskz_insertf64x4(0xFF, _mm512_castpd256_pd512(low), high, 1);  // [x y x y x y x y]
    };
    const Lane a = four(0), b = four(4);
    return {_mm512_permutex2var_pd(a, _mm512_set_epi64(14, 12, 10, 8, 6, 4, 2, 0), b),
            _mm512_permutex2var_pd(a, _mm512_set_epi64(15, 13, 11, 9, 7, 5, 3, 1), b)};
}
/// The same from eight indices in memory.
template <int dim, class Real>
MICROMACRO_INLINE LanesOf<dim> load(const Vec<dim, Real>* base, const std::uint32_t* index) {
    return load_by(base, [index](int l) { return index[l]; });
}

/// The numbers base[index[l]] in lanes l (a gather: two per packet cost less than building the
/// lanes from eight loads each).
template <class Real>
MICROMACRO_INLINE Lane load_numbers(const Real* base, __m256i index) {
    if constexpr (sizeof(Real) == sizeof(double)) return _mm512_mask_i32gather_pd(zeros(), 0xFF, index, base, 8);
    else return _mm512_maskz_cvtps_pd(0xFF, _mm256_mmask_i32gather_ps(_mm256_setzero_ps(), 0xFF, index, base, 4));
}
template <class Real>
MICROMACRO_INLINE Lane load_numbers(const Real* base, const std::uint32_t* index) {
    return load_numbers(base, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(index)));
}

/// Rows to columns: rows[r] holds eight numbers; afterwards rows[c] holds the c-th number of
/// each of the eight rows, row r in lane r. Three rounds of eight shuffles.
MICROMACRO_INLINE void transpose(Lane* rows) {
    Lane t[8], u[8];
    for (int a = 0; a < 4; ++a) {
        t[2 * a] = _mm512_maskz_unpacklo_pd(0xFF, rows[2 * a], rows[2 * a + 1]);
        t[2 * a + 1] = _mm512_maskz_unpackhi_pd(0xFF, rows[2 * a], rows[2 * a + 1]);
    }
    // 0x88: 128-bit lanes 0 and 2 of each operand; 0xDD: lanes 1 and 3.
    for (int a = 0; a < 2; ++a) {
        u[4 * a] = _mm512_maskz_shuffle_f64x2(0xFF, t[4 * a], t[4 * a + 2], 0x88);
        u[4 * a + 1] = _mm512_maskz_shuffle_f64x2(0xFF, t[4 * a + 1], t[4 * a + 3], 0x88);
        u[4 * a + 2] = _mm512_maskz_shuffle_f64x2(0xFF, t[4 * a], t[4 * a + 2], 0xDD);
        u[4 * a + 3] = _mm512_maskz_shuffle_f64x2(0xFF, t[4 * a + 1], t[4 * a + 3], 0xDD);
    }
    for (int c = 0; c < 4; ++c) {
        rows[c] = _mm512_maskz_shuffle_f64x2(0xFF, u[c], u[c + 4], 0x88);
        rows[c + 4] = _mm512_maskz_shuffle_f64x2(0xFF, u[c], u[c + 4], 0xDD);
    }
}

}  // namespace micromacro::packets
#endif
