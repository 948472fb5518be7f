#pragma once
// The walls' side of the force evaluation: which particles are wall candidates, the relative
// velocity of a particle's contact point on a wall, and the one wall loop (the wall is an
// infinite-mass partner and collects the opposite force).
#include <cstddef>
#include <limits>
#include <vector>

#include "micromacro/contact/geometry.hpp"
#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/energy.hpp"
#include "micromacro/core/index.hpp"
#include "micromacro/core/inline.hpp"
#include "micromacro/engine/contact_response.hpp"
#include "micromacro/engine/pair_loop.hpp"
#include "micromacro/walls/shape.hpp"

namespace micromacro::detail {

/// Every (particle, wall) closer than its radius plus `skin`, in particle order.
template <int dim, class Real, class WallSet>
void find_wall_candidates(const std::vector<Vec<dim, Real>>& x, const std::vector<Real>& r, const WallSet& walls, double skin,
                          std::vector<IndexPair>& out) {
    for (Index i = 0; i < x.size(); ++i)
        for (Index w = 0; w < walls.size(); ++w)
            if (walls[w].distance(convert<double>(x[i])) < double(r[i]) + skin) out.push_back({i, w});
}

/// v_ij of Eq. 25 for particle i on a wall whose surface normal at the contact is n: its contact
/// point's velocity relative to the wall's.
template <bool rotation, int dim, class Real, class History, class WallT>
MICROMACRO_INLINE Vec<dim> wall_point_velocity(const ContactLoopInput<dim, Real, History>& in, Index i, const WallT& wall,
                                               const Vec<dim>& n) {
    Vec<dim> vr = convert<double>(in.v[i]) - wall.velocity();
    if constexpr (rotation) vr += DimTraits<dim>::cross(n, Angular<dim>(double(in.r[i]) * convert<double>(in.w[i])));
    return vr;
}

/// The kinematics of particle i on `wall`, its centre at `point` against the surface (the wall
/// is a body of infinite radius and mass).
template <bool rotation, int dim, class Real, class History, class WallT>
MICROMACRO_INLINE ContactKinematics<dim> wall_kinematics(const ContactLoopInput<dim, Real, History>& in, Index i, const WallT& wall,
                                                         const WallPoint<dim>& point, double dt) {
    const Vec<dim>& n = point.normal;
    const Vec<dim> vr = wall_point_velocity<rotation>(in, i, wall, n);
    return {{n, double(in.r[i]) - point.distance, n.dot(vr), vr}, in.r[i], std::numeric_limits<double>::infinity(),
            in.inverse_mass[i], 0.0, dt};
}

/// One wall candidate's part of its wall's force: what the particle received (the wall takes the
/// opposite; zero where the candidate does not touch), in the wall loop's order.
template <int dim>
struct WallTerm {
    Index particle;
    Index wall;
    Vec<dim> force;
};

/// The wall loop over the wall candidates of `in`: the law on each touching one (the normal
/// part only on a frictionless wall), what the law adds for one that opened (see
/// ContactLawIn::opening_force), and each wall's force, the opposite of what its particles
/// receive. With `keep_terms`, `terms` gets each candidate's part as well (a loop of its own: the
/// serial engine's stays as it was).
template <bool track, bool rotation, bool keep_terms, int dim, class Real, class Law, class History, class WallSet>
void wall_forces(const ContactLoopInput<dim, Real, History>& in, std::size_t count, WallSet& walls, const Law& law, double dt,
                 Vec<dim>* f, [[maybe_unused]] Angular<dim>* torque, EnergyBooks& books,
                 [[maybe_unused]] std::vector<WallTerm<dim>>& terms) {
    using V = Vec<dim>;
    using A = Angular<dim>;
    using T = DimTraits<dim>;
    for (auto& wall : walls) wall.force = V::Zero();
    if constexpr (keep_terms) terms.resize(count);
    for (std::size_t c = 0; c < count; ++c) {
        const auto [i, w] = in.pair[c];
        if constexpr (keep_terms) terms[c] = {i, w, V::Zero()};
        auto& wall = walls[w];
        const WallPoint<dim> point = wall.nearest(convert<double>(in.x[i]));
        const double a = in.r[i];
        if (point.distance >= a) {
            if constexpr (Law::has_history) {
                History& h = in.history[c];
                if (law.touched(h)) [[unlikely]] {  // opened in the last step
                    const V force = law.opening_force(wall_kinematics<rotation>(in, i, wall, point, dt), h);
                    f[i] += force;
                    wall.force -= force;
                    if constexpr (keep_terms) terms[c].force = force;
                    if constexpr (rotation) torque[i] -= A(a * T::cross(point.normal, force));
                }
                h = History{};
            }
            continue;
        }
        [[maybe_unused]] NoHistory none;
        History& h = [&]() -> History& {
            if constexpr (Law::has_history) return in.history[c];
            else return none;
        }();
        const auto resp = respond<track>(law, wall_kinematics<rotation>(in, i, wall, point, dt), h, books, wall.frictionless);
        f[i] += resp.force;
        wall.force -= resp.force;
        if constexpr (keep_terms) terms[c].force = resp.force;
        if constexpr (rotation) torque[i] -= A(a * T::cross(point.normal, resp.tangential));
    }
}

}  // namespace micromacro::detail
