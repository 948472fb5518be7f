#pragma once
// What the throughput benchmarks time, serial (throughput) and over MPI ranks (throughput_mpi):
// the generated lattice or a packing file, in its box, and the contact duration that sets the
// time step, found the same way by both so that their figures compare.
#include <cmath>
#include <cstddef>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include <micromacro/contact/collision.hpp>
#include <micromacro/core/domain.hpp>
#include <micromacro/core/error.hpp>
#include <micromacro/io/packing_files.hpp>
#include <micromacro/particles/particles.hpp>

#include "lattice.hpp"

namespace benchmark {

template <int dim>
struct TimedParticles {
    std::vector<micromacro::Vec<dim>> x;
    std::vector<double> r;
    micromacro::Domain<dim> domain;
};

/// The lattice of `particles` (lattice.hpp) when `packing` is empty, else the packing file: CSV as
/// analyze_packing reads it or a LAMMPS dump, its box and periodic axes settled as analyze_packing
/// settles them (`box` and `periodic` as its --box and --periodic; empty: the file's).
template <int dim>
TimedParticles<dim> timed_particles(const std::string& packing, micromacro::io::PackingFormat format, const std::vector<double>& box,
                                    const std::string& periodic, std::size_t particles) {
    TimedParticles<dim> p;
    if (packing.empty()) {
        double L = 0;
        fill_lattice<dim>(p.x, p.r, L, particles, 1);
        p.domain = micromacro::Domain<dim>::fully_periodic(micromacro::Vec<dim>::Zero(), micromacro::Vec<dim>::Constant(L));
    } else {
        auto f = micromacro::io::read_packing<dim>(packing, format);
        p.domain = micromacro::io::packing_domain<dim>(f, box, periodic);
        p.x = std::move(f.position);
        p.r = std::move(f.radius);
    }
    return p;
}

/// t_c (Eq. 22) of two particles of the mean radius of `r` at `density`, as in the paper and the
/// biaxial example; a density that gives no finite positive mass is refused by its option.
inline double mean_contact_duration(const std::vector<double>& r, double density, double k, double gamma_n) {
    const double mean_radius = std::accumulate(r.begin(), r.end(), 0.0) / double(r.size());
    const double mean_mass = micromacro::sphere_mass(density, mean_radius);
    if (!(std::isfinite(mean_mass) && mean_mass > 0.0))
        micromacro::detail::throw_input_error("--density ", density, " kg/m^3 gives a particle of the mean radius ", mean_radius,
                                              " m a mass of ", mean_mass, " kg; give a density that makes it finite and > 0 (2000 for glass)");
    return micromacro::contact_duration(k, gamma_n, 0.5 * mean_mass);
}

}  // namespace benchmark
