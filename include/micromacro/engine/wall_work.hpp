#pragma once
// The energy books' account of the walls: the work they do on the particles and what a
// stress-controlled wall's damper dissipates, between the last two force evaluations.
#include <variant>
#include <vector>

#include "micromacro/core/domain.hpp"
#include "micromacro/core/energy.hpp"
#include "micromacro/walls/motion.hpp"

namespace micromacro::detail {

/// Books the walls' work since `last` (trapezoid in the wall force) into `books` and moves
/// `last` on to the present evaluation. A driven wall's work is that of the force these
/// particles put on it; a stress-controlled wall's pressure work and damper are the wall's own,
/// booked only where `counts_walls` (one process of a distributed run).
template <int dim, class WallSet>
void book_wall_work(const WallSet& walls, const Domain<dim>& domain, std::vector<WallBook>& last_books, EnergyBooks& books,
                    bool counts_walls = true) {
    last_books.resize(walls.size());
    for (std::size_t w = 0; w < walls.size(); ++w) {
        const auto& wall = walls[w];
        auto& last = last_books[w];
        const double push = wall.load();  // < 0: the particles push it back
        const double moved = wall.offset - last.offset;
        if (const auto* s = std::get_if<StressControlled>(&wall.motion)) {
            // The wall is part of the system: the pressure does work, its damper dissipates.
            const double area = walls.area(wall, domain);
            if (counts_walls) {
                books.work_by_walls += s->pressure * 0.5 * (area + last.area) * moved;
                books.dissipated_walls += s->damping * s->damped_speed(wall.speed) * moved;
            }
            last.area = area;
        } else {
            // A driven wall does work -F_wall . displacement on the particles.
            books.work_by_walls -= 0.5 * (push + last.push) * moved;
        }
        last.offset = wall.offset;
        last.push = push;
    }
}

}  // namespace micromacro::detail
