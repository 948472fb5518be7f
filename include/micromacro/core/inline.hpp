#pragma once
// The per-contact functions (the contact laws, Simulation::respond) must be inlined into the
// one pair loop: a call there costs a tenth of the step (measured with callgrind on the 3D
// frictional benchmark, where GCC's size heuristics stopped inlining CundallStrack::force).
// The same for Domain's separation and wrap in the particle pass (perf: an out-of-line wrap
// took a fifth of the pass's samples when the pass became a member template).
// MICROMACRO_COLD marks the opposite: a rare branch's work kept out of that loop, so that it
// neither takes registers nor instruction cache from the common path.
#if defined(__GNUC__) || defined(__clang__)
#define MICROMACRO_INLINE [[gnu::always_inline]] inline
#define MICROMACRO_COLD [[gnu::cold, gnu::noinline]]
#else
#define MICROMACRO_INLINE inline
#define MICROMACRO_COLD
#endif
