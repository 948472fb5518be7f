#pragma once
// Square roots and their reciprocals of a block of numbers, the pair loop's distances and
// inverse distances. Both operations are correctly rounded in IEEE arithmetic, so every way of
// computing them gives the same bits; this one takes them as wide as the CPU allows.
#include <array>
#include <cstddef>

#include <Eigen/Core>

// The compiler targets AVX-512: __AVX512F__, or, in the project's builds, __AVX512VL__ (they
// hide __AVX512F__ from Eigen with -U__AVX512F__ and keep the instructions; CMakeLists.txt).
#if defined(__AVX512F__) || defined(__AVX512VL__)
#include <immintrin.h>
#define MICROMACRO_ROOTS_AVX512 1
#endif

namespace micromacro::detail {

/// root[k] = sqrt(square[k]) and inverse[k] = 1 / root[k] for k < count. With AVX-512 eight at
/// a time, in whole packets: the entries from count to the next multiple of 8 are computed too,
/// from whatever `square` holds there (so it must be initialised; the arrays' capacity is a
/// multiple of 8). Masking the last packet instead ran the 3D pair loop 0.98x on a CPU with
/// 512-bit units (its masked stores, presumably); the 512-bit packets themselves gave it 1.03x
/// (docs/performance.md). Without AVX-512, Eigen's packets, two or four at a time.
template <std::size_t capacity>
inline void roots_and_reciprocals(const std::array<double, capacity>& square, std::array<double, capacity>& root,
                                  std::array<double, capacity>& inverse, std::size_t count) {
    static_assert(capacity % 8 == 0, "whole packets of eight");
#ifdef MICROMACRO_ROOTS_AVX512
    // maskz_sqrt and set_pd, not sqrt and set1_pd: GCC 12's versions of those pass an undefined
    // vector that -Wmaybe-uninitialized reports.
    const __m512d one = _mm512_set_pd(1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0);
    for (std::size_t k = 0; k < count; k += 8) {
        const __m512d r = _mm512_maskz_sqrt_pd(0xFF, _mm512_loadu_pd(square.data() + k));
        _mm512_storeu_pd(root.data() + k, r);
        _mm512_storeu_pd(inverse.data() + k, _mm512_div_pd(one, r));
    }
#else
    using Column = Eigen::Array<double, Eigen::Dynamic, 1>;
    Eigen::Map<Column> r(root.data(), count), i(inverse.data(), count);
    r = Eigen::Map<const Column>(square.data(), count).sqrt();
    i = r.inverse();
#endif
}

}  // namespace micromacro::detail
