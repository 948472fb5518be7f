#pragma once
// Whether two codes that evaluate the same expressions agree (a packet loop and the scalar loop it
// stands in for): to the bit in a build without fused multiply-adds (MICROMACRO_FMA=OFF), where
// each computes the same roundings; with them, within round-off of the scale, since the compiler
// fuses each its own way.
#include <cmath>
#include <cstring>

#include <micromacro/core/dim_traits.hpp>

namespace mmtest {

/// a and b equal to the bit without fused multiply-adds (with `either_zero_sign`, +0 and -0
/// alike), else within round_off * scale.
inline bool same_bits(double a, double b, [[maybe_unused]] double scale, [[maybe_unused]] double round_off,
                      [[maybe_unused]] bool either_zero_sign = false) {
#ifdef MICROMACRO_FP_CONTRACT
    return std::abs(a - b) <= round_off * scale;
#else
    return std::memcmp(&a, &b, sizeof a) == 0 || (either_zero_sign && a == 0.0 && b == 0.0);
#endif
}

/// The same for every component.
template <int dim>
bool same_bits(const micromacro::Vec<dim>& a, const micromacro::Vec<dim>& b, double scale, double round_off,
               bool either_zero_sign = false) {
    for (int k = 0; k < dim; ++k)
        if (!same_bits(a[k], b[k], scale, round_off, either_zero_sign)) return false;
    return true;
}

}  // namespace mmtest
