// Coarse-graining kernels (the library's and one defined here): each integrates to one, the grid integral of every field reproduces
// the box average exactly, and a homogeneous lattice gives a uniform field equal to its box value.
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <numbers>

#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(physics_coarse_graining)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;

namespace {
// Midpoint-rule integral of the kernel over the cube [-R, R]^dim with n points per axis.
template <int dim, class Kernel>
double integral(const Kernel& kernel, double R, int n) {
    std::array<int, dim> count;
    count.fill(n);
    const auto g = mm::Grid<dim>::covering(mm::Vec<dim>::Constant(-R), mm::Vec<dim>::Constant(R), count);
    double sum = 0.0;
    for (std::size_t x = 0; x < g.size(); ++x) sum += kernel.template value<dim>(g.point(x).norm());
    return sum * g.cell_volume();
}

/// A kernel written outside the library, as a user adds one: the cone A (1 - r/c) for r < c,
/// A = 3 / (pi c^dim) in 2D and 3D.
struct ConeKernel {
    double width;  // c (m)
    double support() const { return width; }
    template <int dim>
    double value(double r) const {
        return r < width ? 3.0 / (std::numbers::pi * std::pow(width, dim)) * (1.0 - r / width) : 0.0;
    }
};
static_assert(mm::CoarseGrainingKernel<ConeKernel>);
}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(kernels_integrate_to_one, D, Dims) {
    constexpr int dim = D::value;
    const int n = dim == 2 ? 400 : 120;
    BOOST_TEST(std::abs(integral<dim>(mm::GaussianKernel{1e-3}, 8e-3, n) - 1.0) < 1e-6);
    BOOST_TEST(std::abs(integral<dim>(mm::LucyKernel{2e-3}, 2e-3, n) - 1.0) < (dim == 2 ? 1e-4 : 1e-3));
    BOOST_TEST(mm::LucyKernel{2e-3}.value<dim>(2e-3) == 0.0);  // compact support
    BOOST_TEST(std::abs(integral<dim>(ConeKernel{2e-3}, 2e-3, n) - 1.0) < (dim == 2 ? 1e-4 : 1e-3));
}

// Summed over the grid (times the cell volume, over the box volume) every field equals the
// whole-box average of the same packing: fabric, stress, stiffness, volume fraction, both rules,
// the library's kernels and one defined here, to round-off.
BOOST_AUTO_TEST_CASE_TEMPLATE(grid_sum_reproduces_box_average, D, Dims) {
    constexpr int dim = D::value;
    const double L = dim == 2 ? 0.03 : 0.01;
    const auto p = random_packing<dim>(dim == 2 ? 500 : 400, 0.5e-3, 1.5e-3, L, 12, true, true);
    mm::PackingSnapshot<dim> s;
    s.domain = periodic_box<dim>(L);
    s.position = p.x;
    s.radius = p.r;
    mm::detect_contacts(s, k, 0.2 * k);
    for (auto& c : s.contacts) c.tangential_force = 0.1 * c.normal_force * (mm::Vec<dim>::UnitX() - c.normal * c.normal[0]);
    std::array<int, dim> n;
    n.fill(dim == 2 ? 24 : 10);
    const auto grid = mm::Grid<dim>::covering(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant(L), n);
    for (auto rule : {mm::SelectionRule::contact_point, mm::SelectionRule::particle_centre}) {
        mm::AveragingOptions o;
        o.rule = rule;
        const auto box = mm::average(s, mm::Region<dim>::whole(s), o);
        auto check = [&](const auto& kernel) {
            const auto f = mm::coarse_grain(s, grid, kernel, o);
            const double w = grid.cell_volume() / box.volume;
            double nu = 0.0;
            mm::Tensor2<dim> F = mm::Tensor2<dim>::Zero(), S = F;
            mm::Tensor4<dim> C;
            for (std::size_t x = 0; x < grid.size(); ++x) {
                nu += w * f.volume_fraction[x];
                F += w * f.fabric[x];
                S += w * (f.stress_normal[x] + f.stress_tangential[x]);
                C += w * (f.stiffness_normal[x] + f.stiffness_tangential[x]);
            }
            BOOST_TEST(std::abs(nu - box.volume_fraction) < 1e-12 * box.volume_fraction);
            BOOST_TEST((F - box.fabric).norm() < 1e-12 * box.fabric.norm());
            BOOST_TEST((S - box.stress).norm() < 1e-12 * box.stress.norm());
            const auto Cbox = box.stiffness_normal + box.stiffness_tangential;
            BOOST_TEST((C.matrix() - Cbox.matrix()).norm() < 1e-12 * Cbox.matrix().norm());
            // A smooth field: not all the weight in a few cells.
            std::size_t filled = 0;
            for (const auto& fx : f.fabric) filled += fx.trace() > 0.0;
            BOOST_TEST(filled == grid.size());
        };
        const double d = mm::mean_diameter(s);
        BOOST_TEST(std::abs(d - 2e-3) < 0.1e-3);  // radii uniform in [0.5, 1.5] mm
        check(mm::GaussianKernel{1.0 * d});
        check(mm::LucyKernel{2.0 * d});
        check(ConeKernel{2.0 * d});
    }
}

// A triangular lattice is homogeneous: with a kernel wider than the spacing the fields are
// uniform and equal to the box values (C_1111 = 3 sqrt(3)/4 k, tr F = 6 nu).
BOOST_AUTO_TEST_CASE(lattice_fields_are_uniform) {
    const double l = 2e-3, h = std::sqrt(3.0) * l;
    mm::PackingSnapshot<2> s;
    s.domain = mm::Domain<2>::fully_periodic({0, 0}, {12 * l, 8 * h});  // twice the kernel support
    for (int i = 0; i < 12; ++i)
        for (int j = 0; j < 8; ++j) {
            s.position.push_back({i * l, j * h});
            s.position.push_back({(i + 0.5) * l, (j + 0.5) * h});
        }
    s.radius.assign(s.position.size(), 0.5 * l * (1 + 1e-14));
    mm::detect_contacts(s, k, 0.0);
    const auto grid = mm::Grid<2>::covering({0, 0}, {12 * l, 8 * h}, {24, 24});
    const auto f = mm::coarse_grain(s, grid, mm::GaussianKernel{1.5 * l});
    double worst = 0.0;
    for (std::size_t x = 0; x < grid.size(); ++x)
        worst = std::max(worst, std::abs(f.stiffness_normal[x](0, 0, 0, 0) / (3 * std::sqrt(3.0) / 4 * k) - 1.0));
    BOOST_TEST_MESSAGE("max relative deviation of C_1111 from 3 sqrt(3)/4 k over the grid: " << worst);
    BOOST_TEST(worst < 1e-5);  // what remains is the Gaussian cut at 4 w
}

BOOST_AUTO_TEST_SUITE_END()
