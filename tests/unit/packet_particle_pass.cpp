// The kick-drift pass on packets of eight particles (engine/packet_particle_pass.hpp) against the
// scalar pass it stands in for, on the same particles: every position, velocity, spin, cleared
// array, the largest displacement and the sum of them. Without fused multiply-adds
// (MICROMACRO_FMA=OFF) the two agree bit for bit; with them to round-off. The scene has a
// particle count that leaves a partial packet, a box periodic on some axes and open on another,
// particles that leave the box in the drift (wrapped), references across the periodic boundary
// (the minimum image) and one more than a period away, with and without rotation, with and
// without the previous forces and their closing kick, on one thread and two.
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <micromacro/engine/particle_pass.hpp>

#include "support/same_bits.hpp"

BOOST_AUTO_TEST_SUITE(unit_packet_particle_pass)  // the file's cases, run as the CTest test of this file's name

namespace mm = micromacro;
using mm::Vec;

#ifdef MICROMACRO_PACKETS
namespace {

constexpr double side = 10.0, dt = 0.01;

template <int dim>
struct Particles {
    std::vector<Vec<dim>> x, v, f, f_old, reference;
    std::vector<mm::Angular<dim>> w, torque, torque_old;
    std::vector<double> inv_m, inv_I;

    mm::detail::ParticleArrays<dim, double> arrays() {
        return {x.data(), v.data(), f.data(), inv_m.data(), w.data(), torque.data(), inv_I.data(), f_old.data(),
                torque_old.data(), reference.data(), x.size()};
    }
};

template <int dim>
mm::Angular<dim> random_angular(std::mt19937_64& rng, double scale) {
    std::uniform_real_distribution<double> u(-scale, scale);
    if constexpr (dim == 2) return u(rng);
    else return Vec<3>(u(rng), u(rng), u(rng));
}

// 8 * 12 + 5 particles in [0, side)^dim; axis 1 open, the others periodic. Particles 0-3 drift
// out of the box over a periodic face (0 and 1 up, 2 and 3 down), particle 4 over the open
// face; particles 5-9 have references across the periodic boundary, particle 10 one more than a
// period away, particle 11 across the open axis (no image there).
template <int dim>
Particles<dim> particles() {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> unit(0.0, 1.0), sym(-1.0, 1.0);
    const auto random_vec = [&](double scale) {
        Vec<dim> a;
        for (int k = 0; k < dim; ++k) a[k] = scale * sym(rng);
        return a;
    };
    Particles<dim> p;
    const std::size_t n = 8 * 12 + 5;
    for (std::size_t i = 0; i < n; ++i) {
        Vec<dim> xi;
        for (int k = 0; k < dim; ++k) xi[k] = side * unit(rng);
        p.x.push_back(xi);
        p.v.push_back(random_vec(1.0));
        p.f.push_back(random_vec(100.0));
        p.f_old.push_back(random_vec(100.0));
        p.reference.push_back(xi + random_vec(0.05));
        p.w.push_back(random_angular<dim>(rng, 3.0));
        p.torque.push_back(random_angular<dim>(rng, 50.0));
        p.torque_old.push_back(random_angular<dim>(rng, 50.0));
        p.inv_m.push_back(0.5 + 1.5 * unit(rng));
        p.inv_I.push_back(2.0 + 5.0 * unit(rng));
    }
    for (int i = 0; i < 4; ++i) {  // out over periodic faces of axis 0 and of the last axis
        const int axis = i % 2 == 0 ? 0 : dim - 1;
        const bool up = i < 2;
        p.x[i][axis] = up ? side - 1e-4 : 1e-4;
        p.v[i][axis] = up ? 2.0 : -2.0;
        p.reference[i] = p.x[i];
    }
    p.x[4][1] = side - 1e-4;  // out over the open axis: stays out
    p.v[4][1] = 2.0;
    for (int i = 5; i < 10; ++i) p.reference[i][i % 2 == 0 ? 0 : dim - 1] += i % 3 == 0 ? side : -side;
    p.reference[10][0] -= 2.5 * side;
    p.reference[11][1] += 0.9 * side;
    return p;
}

// Equal to the bit without fused multiply-adds, else within 1e-13 of the scale.
template <class T>
bool same(const T& a, const T& b, double scale) {
    return mmtest::same_bits(a, b, scale, 1e-13);
}

template <int dim, class T>
void check_same(const std::vector<T>& a, const std::vector<T>& b, double scale, const char* what) {
    BOOST_TEST_REQUIRE(a.size() == b.size());
    for (std::size_t i = 0; i < a.size(); ++i) BOOST_TEST(same(a[i], b[i], scale), what << " of particle " << i);
}

template <int dim, bool periodic, bool rotation, bool keeps>
void compare(double h_closing, int threads) {
    std::array<bool, dim> axes;
    axes.fill(periodic);
    axes[1] = false;
    const mm::Domain<dim> box(Vec<dim>::Zero(), Vec<dim>::Constant(side), axes);
    Particles<dim> a = particles<dim>(), b = a;
    const double h = 0.5 * dt, closing = keeps ? h_closing : 0.0;
    const auto [max_a, sum_a, wrap_a] =
        mm::detail::scalar_kick_drift_pass<periodic, rotation, keeps>(a.arrays(), 0, box, h, dt, h, closing, 1);
    const auto [max_b, sum_b, wrap_b] = mm::detail::kick_drift_pass<periodic, rotation, keeps>(b.arrays(), box, h, dt, h, closing, threads);
    BOOST_TEST((wrap_a == 0.0 && wrap_b == 0.0));  // a still box changes no velocity
    check_same<dim>(a.x, b.x, side, "position");
    check_same<dim>(a.v, b.v, 10.0, "velocity");
    check_same<dim>(a.f, b.f, 100.0, "force");
    check_same<dim>(a.f_old, b.f_old, 100.0, "previous force");
    check_same<dim>(a.w, b.w, 10.0, "spin");
    check_same<dim>(a.torque, b.torque, 100.0, "torque");
    check_same<dim>(a.torque_old, b.torque_old, 100.0, "previous torque");
    BOOST_TEST(same(max_a, max_b, max_a));
    BOOST_TEST(std::abs(sum_a - sum_b) <= 1e-13 * sum_a);  // summed in another order
    // The largest displacement is the largest of Domain's separations from the references; on
    // the open axis there is no image (particle 11: 9 away).
    double largest = 0.0;
    for (std::size_t i = 0; i < b.x.size(); ++i) largest = std::max(largest, box.separation(b.x[i], b.reference[i]).squaredNorm());
    BOOST_TEST(same(max_b, largest, largest));
    BOOST_TEST(largest > 0.8 * 0.8 * side * side);
    if constexpr (periodic) {  // the drift's leavers wrapped back on the periodic axes
        for (std::size_t i = 0; i < b.x.size(); ++i)
            for (int k = 0; k < dim; ++k)
                if (k != 1) BOOST_TEST((b.x[i][k] >= 0.0 && b.x[i][k] < side), "particle " << i << " axis " << k);
    }
}

template <int dim>
void compare_all(int threads) {
    compare<dim, true, true, true>(0.7 * dt, threads);
    compare<dim, true, true, true>(0.0, threads);
    compare<dim, true, false, true>(0.7 * dt, threads);
    compare<dim, true, true, false>(0.0, threads);
    compare<dim, false, true, true>(0.7 * dt, threads);
    compare<dim, false, false, false>(0.0, threads);
}

// A sheared cell (every axis periodic, the first tilted by the last and moving with it): the
// particles that cross the last axis's faces take their images' velocities, the same in both
// passes, and the energy the passes report is the kinetic energy those velocity changes made,
// computed here from the same pass in the still cell.
template <int dim>
void compare_moving(int threads) {
    std::array<bool, dim> axes;
    axes.fill(true);
    mm::Domain<dim> box(Vec<dim>::Zero(), Vec<dim>::Constant(side), axes);
    box.set_tilt(0, dim - 1, 0.3 * side);
    const mm::Domain<dim> still = box;
    Eigen::Matrix<double, dim, dim> L = Eigen::Matrix<double, dim, dim>::Zero();
    L(0, dim - 1) = 0.5;
    box.set_velocity_gradient(L);
    Particles<dim> a = particles<dim>(), b = a, c = a;
    const double h = 0.5 * dt;
    const auto [max_a, sum_a, wrap_a] = mm::detail::scalar_kick_drift_pass<true, true, true>(a.arrays(), 0, box, h, dt, h, 0.0, 1);
    const auto [max_b, sum_b, wrap_b] = mm::detail::kick_drift_pass<true, true, true>(b.arrays(), box, h, dt, h, 0.0, threads);
    mm::detail::scalar_kick_drift_pass<true, true, true>(c.arrays(), 0, still, h, dt, h, 0.0, 1);
    check_same<dim>(a.x, b.x, side, "position");
    check_same<dim>(a.v, b.v, 10.0, "velocity");
    double expected = 0.0;
    int changed = 0;
    for (std::size_t i = 0; i < c.v.size(); ++i) {
        BOOST_TEST(a.x[i] == c.x[i]);  // the same images: only velocities differ
        if (a.v[i] != c.v[i]) ++changed, expected += 0.5 * (a.v[i].squaredNorm() - c.v[i].squaredNorm()) / a.inv_m[i];
    }
    BOOST_TEST(changed == (dim == 2 ? 3 : 2));  // 1 and 3 cross the last axis's faces (and 4 in 2D, where it is axis 1)
    BOOST_TEST(expected != 0.0);
    BOOST_TEST(same(wrap_a, expected, std::abs(expected)));
    BOOST_TEST(same(wrap_b, expected, std::abs(expected)));
}

}  // namespace

BOOST_AUTO_TEST_CASE(moving_cell_velocities_and_their_energy_match) {
    compare_moving<2>(1);
    compare_moving<3>(2);
}

BOOST_AUTO_TEST_CASE(packet_pass_is_the_scalar_pass_2d) { compare_all<2>(1); }
BOOST_AUTO_TEST_CASE(packet_pass_is_the_scalar_pass_3d) { compare_all<3>(1); }
#ifdef _OPENMP
BOOST_AUTO_TEST_CASE(packet_pass_on_two_threads_is_the_scalar_pass) {
    compare_all<2>(2);
    compare_all<3>(2);
}
#endif

// A blown-up particle: its NaN drops out of the largest displacement, as in the scalar pass,
// and the sum carries it, which is how the engine notices (BasicSimulation::kick_drift_kick).
BOOST_AUTO_TEST_CASE(a_nan_is_in_the_sum_and_not_in_the_largest_displacement) {
    Particles<3> a = particles<3>(), b = a;
    a.f[13][2] = b.f[13][2] = std::numeric_limits<double>::quiet_NaN();
    const mm::Domain<3> box(Vec<3>::Zero(), Vec<3>::Constant(side), {true, false, true});
    const auto [max_a, sum_a, wrap_a] = mm::detail::scalar_kick_drift_pass<true, true, true>(a.arrays(), 0, box, dt, dt, dt, 0.0, 1);
    const auto [max_b, sum_b, wrap_b] = mm::detail::kick_drift_pass<true, true, true>(b.arrays(), box, dt, dt, dt, 0.0, 1);
    BOOST_TEST(std::isfinite(max_b));
    BOOST_TEST(same(max_a, max_b, max_a));
    BOOST_TEST(std::isnan(sum_a));
    BOOST_TEST(std::isnan(sum_b));
}
#endif

// Float storage runs the scalar pass (its conversions are the pass's cost, docs/performance.md).
BOOST_AUTO_TEST_CASE(float_storage_runs_the_scalar_pass) {
    BOOST_TEST(!mm::detail::packet_particle_pass_applies<float>);
#ifdef MICROMACRO_PACKETS
    BOOST_TEST(mm::detail::packet_particle_pass_applies<double>);
#endif
}

BOOST_AUTO_TEST_SUITE_END()
