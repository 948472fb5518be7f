#pragma once
// Energy bookkeeping. Stored energies (kinetic, elastic, gravitational) are computed from the
// state on demand; what leaves or enters the system is accumulated step by step in the books.
// Conservation: kinetic + potential + dissipated - work_in stays at its initial value, up to
// the integrator's error (second order in dt for both built-in integrators).
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

    /// Adds another account entry by entry (e.g. the threads' shares of one evaluation).
    void add(const EnergyBooks& o) {
        dissipated_normal += o.dissipated_normal;
        dissipated_tangential += o.dissipated_tangential;
        dissipated_sliding += o.dissipated_sliding;
        dissipated_background += o.dissipated_background;
        dissipated_walls += o.dissipated_walls;
        work_by_walls += o.work_by_walls;
        work_by_deformation += o.work_by_deformation;
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
    }

    double work_in() const { return work_by_walls + work_by_deformation; }

    double dissipated() const {
        return dissipated_normal + dissipated_tangential + dissipated_sliding + dissipated_background +
               dissipated_walls;
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

}  // namespace micromacro
