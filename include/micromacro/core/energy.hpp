#pragma once
// Energy bookkeeping. Stored energies (kinetic, elastic, gravitational) are computed from the
// state on demand; what leaves or enters the system is accumulated step by step in the books.
// Conservation: kinetic + potential + dissipated - work_in stays at its initial value, up to
// the integrator's error (second order in dt for both built-in integrators).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace micromacro {

/// Accumulated since the simulation was prepared.
struct EnergyBooks {
    double dissipated_normal = 0;      ///< normal dashpots (gamma_0)
    double dissipated_tangential = 0;  ///< tangential dashpots (gamma_t), while sticking
    double dissipated_sliding = 0;     ///< Coulomb sliding
    double dissipated_background = 0;  ///< background damping (Eq. 30) and the other damping policies
    double dissipated_walls = 0;       ///< damping of stress-controlled walls (gamma_w)
    double work_by_walls = 0;          ///< done on the system by moving walls and wall pressure
    double work_by_deformation = 0;    ///< energy put in by imposed affine deformations
    /// done by a moving periodic cell (Domain::set_velocity_gradient): by the contacts across its
    /// boundary, whose images move at the image velocity, and on a particle that crosses it and
    /// takes its image's velocity
    double work_by_cell = 0;

    /// Adds another account entry by entry (e.g. the threads' shares of one evaluation).
    void add(const EnergyBooks& o) {
        dissipated_normal += o.dissipated_normal;
        dissipated_tangential += o.dissipated_tangential;
        dissipated_sliding += o.dissipated_sliding;
        dissipated_background += o.dissipated_background;
        dissipated_walls += o.dissipated_walls;
        work_by_walls += o.work_by_walls;
        work_by_deformation += o.work_by_deformation;
        work_by_cell += o.work_by_cell;
    }

    /// Adds the mean of two evaluations' bookings (trapezoid rule), `a` the later. Rates times dt
    /// are booked so; Coulomb sliding is booked as what the step ending at `a` dissipated, wholly
    /// at `a` (see CundallStrack::force).
    void add_mean(const EnergyBooks& a, const EnergyBooks& b) {
        dissipated_normal += 0.5 * (a.dissipated_normal + b.dissipated_normal);
        dissipated_tangential += 0.5 * (a.dissipated_tangential + b.dissipated_tangential);
        dissipated_sliding += a.dissipated_sliding;
        dissipated_background += 0.5 * (a.dissipated_background + b.dissipated_background);
        dissipated_walls += 0.5 * (a.dissipated_walls + b.dissipated_walls);
        work_by_walls += 0.5 * (a.work_by_walls + b.work_by_walls);
        work_by_deformation += 0.5 * (a.work_by_deformation + b.work_by_deformation);
        work_by_cell += 0.5 * (a.work_by_cell + b.work_by_cell);
    }

    double work_in() const { return work_by_walls + work_by_deformation + work_by_cell; }

    double dissipated() const {
        return dissipated_normal + dissipated_tangential + dissipated_sliding + dissipated_background +
               dissipated_walls;
    }
};

namespace detail {
/// A wall as the books saw it at the last evaluation.
struct WallBook {
    double offset = 0, push = 0, area = 0;
};
}  // namespace detail

/// An engine's books as its next evaluation continues them: the sums so far, the last
/// evaluation's bookings (the trapezoid's first half, see BasicSimulation::close_step_books), the
/// walls as last booked, and the energy the books opened with. What an engine that takes over a
/// scene mid-run starts from (BasicSimulation::continue_books; mpi::DistributedRun).
struct OpenBooks {
    EnergyBooks books, last_evaluation;
    std::vector<detail::WallBook> walls;
    double initial_energy = 0;

    /// Nothing booked, the walls where they stand: what another process continues from while one
    /// takes these books over.
    OpenBooks without_bookings() const {
        OpenBooks o{{}, {}, walls, 0.0};
        for (auto& w : o.walls) w.push = 0.0;
        return o;
    }
};

/// Energies of the current state.
struct EnergyState {
    double kinetic_translational = 0;
    double kinetic_rotational = 0;
    double kinetic_walls = 0;  ///< stress-controlled walls have mass
    double elastic_normal = 0;
    double elastic_tangential = 0;
    double gravitational = 0;

    double kinetic() const { return kinetic_translational + kinetic_rotational + kinetic_walls; }
    double potential() const { return elastic_normal + elastic_tangential + gravitational; }
    double total() const { return kinetic() + potential(); }
};

/// kinetic + potential + dissipated - work_in - initial, relative to the initial energy (or to
/// the work put in, if that is larger): how far the books are from closing.
inline double energy_residual(const EnergyState& now, const EnergyBooks& books, double initial_energy) {
    const double total = now.total() + books.dissipated() - books.work_in();
    const double scale = std::max({std::abs(initial_energy), std::abs(books.work_in()), std::numeric_limits<double>::min()});
    return (total - initial_energy) / scale;
}

}  // namespace micromacro
