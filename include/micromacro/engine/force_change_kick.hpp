#pragma once
// The one formula of the force-change kick, v + h/m (F - F_old), for the particle passes
// (engine/particle_pass.hpp, engine/packet_particle_pass.hpp): the kick on its own, the closing
// kick merged into the kick-drift pass and its lanes all evaluate this expression, so that they
// give the same bits (without fused multiply-adds).
#include "micromacro/core/inline.hpp"

namespace micromacro::detail {

/// v + h/m (F - F_old), or its rotational twin; U a vector, angular velocity or lanes of them,
/// Scale h/m as a number or in lanes.
template <class U, class Scale>
MICROMACRO_INLINE U force_change_kick(const U& v, const Scale& h_over_mass, const U& now, const U& before) {
    return U(v + h_over_mass * (now - before));
}

}  // namespace micromacro::detail
