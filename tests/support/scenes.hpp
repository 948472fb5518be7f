#pragma once
// Test-wide helpers: the dimensions every physics test runs in, and random packings.
#include <cmath>
#include <random>
#include <tuple>
#include <type_traits>
#include <vector>

#include <micromacro/micromacro.hpp>

namespace mmtest {

namespace mm = micromacro;

template <int d>
using Dim = std::integral_constant<int, d>;
using Dims = std::tuple<Dim<2>, Dim<3>>;

// Paper parameters (PAPER-NOTES section 3).
inline constexpr double rho = 2000.0, k = 1e5, gamma0 = 0.1, a_mean = 1e-3;

/// The cube [0, L)^dim, periodic on every axis.
template <int dim>
mm::Domain<dim> periodic_box(double L) {
    return mm::Domain<dim>::fully_periodic(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant(L));
}

/// Non-overlapping random particles in [0, L]^dim with radii uniform in [a_min, a_max]
/// (random sequential placement; gives up on a particle after many tries).
template <int dim>
struct RandomPacking {
    std::vector<mm::Vec<dim>> x;
    std::vector<double> r;
};

template <int dim>
RandomPacking<dim> random_packing(std::size_t n, double a_min, double a_max, double L, unsigned seed,
                                  bool allow_overlap = false, bool periodic = false) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    RandomPacking<dim> p;
    const mm::Domain<dim> domain = periodic ? periodic_box<dim>(L) : mm::Domain<dim>();
    for (std::size_t tries = 0; p.x.size() < n && tries < 1000 * n; ++tries) {
        const double a = a_min + (a_max - a_min) * U(rng);
        mm::Vec<dim> c;
        for (int k2 = 0; k2 < dim; ++k2) c[k2] = periodic ? L * U(rng) : a + (L - 2 * a) * U(rng);
        bool free = true;
        if (!allow_overlap)
            for (std::size_t j = 0; j < p.x.size() && free; ++j)
                free = domain.separation(c, p.x[j]).norm() > a + p.r[j];
        if (free) {
            p.x.push_back(c);
            p.r.push_back(a);
        }
    }
    return p;
}

}  // namespace mmtest
