#pragma once
// The benchmarks' generated packing: a square (2D) or simple cubic (3D) lattice of equal 1 mm
// particles in a periodic box, pressed together by 1e-4 of a diameter and jittered by 1e-5 of it,
// so every particle keeps its 4 (2D) or 6 (3D) contacts and the packing stays static.
#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

#include <micromacro/core/dim_traits.hpp>
#include <micromacro/core/error.hpp>

namespace benchmark {

/// n particles (positions x, radii r) on the lattice, in the periodic cube [0, L)^dim.
template <int dim>
void fill_lattice(std::vector<micromacro::Vec<dim>>& x, std::vector<double>& r, double& L, std::size_t n, unsigned seed) {
    // Each periodic axis must hold two interaction ranges (2.2 spacings with the default skin): a
    // lattice 3 particles wide, full.
    const std::size_t fewest = dim == 2 ? 9 : 27;
    if (n < fewest)
        micromacro::detail::throw_input_error("--particles ", n, " is too few: the periodic box needs a full lattice at least 3 ",
                                              "particles wide, ", fewest, " in ", dim, "D; use --particles ", fewest, " or more");
    const int per_side = static_cast<int>(std::ceil(std::pow(double(n), 1.0 / dim) - 1e-9));
    const double spacing = 2e-3;
    L = per_side * spacing;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    for (std::size_t i = 0; i < n; ++i) {
        micromacro::Vec<dim> p;
        for (int a = 0, t = static_cast<int>(i); a < dim; ++a, t /= per_side) p[a] = (t % per_side + 0.5) * spacing + 2e-8 * U(rng);
        x.push_back(p);
        r.push_back(0.5 * spacing * 1.0001);  // overlap 1e-4 of a diameter with the lattice neighbours
    }
}

}  // namespace benchmark
