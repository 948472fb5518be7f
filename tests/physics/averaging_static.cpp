// Averages of relaxed (static) packings: contact stress against wall stress, the affine probe,
// and invariance under rotation, renumbering and periodic doubling.
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <numeric>

#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(physics_averaging_static)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;

namespace {
template <int dim>
double nu_dense() {
    return dim == 2 ? 0.86 : 0.66;
}
const mm::SelectionRule rules[] = {mm::SelectionRule::contact_point, mm::SelectionRule::particle_centre};
}  // namespace

// Walls on the last axis, periodic otherwise. In static equilibrium the virial of the whole box
// equals the wall stress exactly (up to the residual motion), and a slab spanning the periodic
// axes carries the same normal stress at every height; the inner 80% agrees within 2%.
BOOST_AUTO_TEST_CASE_TEMPLATE(contact_stress_equals_wall_stress, D, Dims) {
    constexpr int dim = D::value;
    const auto s = relaxed_packing<dim>(1000, nu_dense<dim>(), 1);
    const double wall = mm::wall_stress(s)(dim - 1, dim - 1);
    BOOST_TEST_REQUIRE(wall > 0.0);
    for (auto rule : rules) {
        mm::AveragingOptions o;
        o.rule = rule;
        const auto whole = mm::average(s, mm::Region<dim>::whole(s), o);
        const auto inner = mm::average(s, mm::Region<dim>::inner(s, 0.1), o);
        BOOST_TEST_MESSAGE(dim << "D rule " << int(rule) << ": whole/wall " << whole.stress(dim - 1, dim - 1) / wall
                               << ", inner/wall " << inner.stress(dim - 1, dim - 1) / wall);
        BOOST_TEST(std::abs(whole.stress(dim - 1, dim - 1) / wall - 1.0) < 1e-4);
        BOOST_TEST(std::abs(inner.stress(dim - 1, dim - 1) / wall - 1.0) < 0.02);
        // Normal plus tangential parts make the stress; the tangential part is small but present.
        BOOST_TEST(std::abs(inner.stress_tangential(dim - 1, dim - 1)) < 0.2 * wall);
        BOOST_TEST(inner.stress_tangential.norm() > 0.0);
    }
}

// All axes walled, frictionless: every diagonal component of the whole-box virial equals the
// stress of its walls.
BOOST_AUTO_TEST_CASE_TEMPLATE(whole_box_virial_equals_all_wall_stresses, D, Dims) {
    constexpr int dim = D::value;
    const auto s = relaxed_packing<dim>(400, dim == 2 ? 0.88 : 0.68, 2, dim, 0.0);
    const auto wall = mm::wall_stress(s);
    for (auto rule : rules) {
        mm::AveragingOptions o;
        o.rule = rule;
        const auto whole = mm::average(s, mm::Region<dim>::whole(s), o);
        for (int a = 0; a < dim; ++a) {
            BOOST_TEST_REQUIRE(wall(a, a) > 0.0);
            BOOST_TEST(std::abs(whole.stress(a, a) / wall(a, a) - 1.0) < 1e-4);
        }
    }
}

// The affine probe: the stress change of a small affine strain equals C : eps plus the geometric
// terms Eq. 9 drops (of relative size overlap / l), up to O(eps^2).
BOOST_AUTO_TEST_CASE_TEMPLATE(affine_probe_matches_stiffness, D, Dims) {
    constexpr int dim = D::value;
    const auto s = relaxed_packing<dim>(600, nu_dense<dim>(), 3);
    mm::Tensor2<dim> shape = mm::Tensor2<dim>::Zero();
    for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b) shape(a, b) = 0.3 + 0.1 * a - 0.2 * b + (a == b ? 1.0 : 0.0);
    shape = 0.5 * (shape + shape.transpose()).eval();
    double mean_overlap_ratio = 0.0;
    for (const auto& c : s.contacts) mean_overlap_ratio += c.overlap / c.branch.norm() / s.contacts.size();
    const auto region = mm::Region<dim>::inner(s, 0.1);
    double previous_error = 1.0;
    for (double eps : {1e-5, 1e-6, 1e-7}) {
        const auto r = mm::affine_response(s, region, mm::Tensor2<dim>(eps * shape));
        const double scale = r.predicted.norm();
        const double neglected = (r.stress_change - r.predicted).norm() / scale;
        const double error = (r.stress_change - r.predicted - r.geometric).norm() / scale;
        BOOST_TEST_MESSAGE(dim << "D eps " << eps << ": |d sigma - C:eps| / |C:eps| = " << neglected
                               << " (mean overlap / l = " << mean_overlap_ratio << "), with the geometric terms "
                               << error);
        BOOST_TEST(neglected < 3.0 * mean_overlap_ratio);  // what Eq. 9 neglects is of order overlap / l
        BOOST_TEST(error < 20.0 * eps);                    // the rest is second order
        if (eps < 1e-5) BOOST_TEST(error < 0.2 * previous_error);  // and shrinks with eps
        previous_error = error;
    }
    // Without contact forces (a lattice at zero overlap) the geometric term is absent: the match is O(eps).
    mm::PackingSnapshot<dim> lattice;
    const double l = 2e-3;
    lattice.domain = mm::Domain<dim>::fully_periodic(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant(4 * l));
    for (int t = 0; t < (dim == 2 ? 16 : 64); ++t) {
        mm::Vec<dim> x;
        for (int d = 0, u = t; d < dim; ++d, u /= 4) x[d] = (u % 4 + 0.5) * l;
        lattice.position.push_back(x);
        lattice.radius.push_back(0.5 * l * (1 + 1e-14));
    }
    mm::detect_contacts(lattice, k, 0.2 * k);
    for (auto& c : lattice.contacts) c.normal_force = 0.0;
    const auto r = mm::affine_response(lattice, mm::Region<dim>::whole(lattice), mm::Tensor2<dim>(1e-8 * shape));
    BOOST_TEST((r.stress_change - r.predicted).norm() < 1e-6 * r.predicted.norm());
}

// The probe with relaxation. A Bravais lattice deforms affinely, so relaxing changes nothing
// (ratio 1); a disordered packing relaxes non-affinely and the affine response is an upper
// bound (Voigt): 0 < ratio <= 1.
BOOST_AUTO_TEST_CASE_TEMPLATE(relaxed_probe, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    V diagonal;
    for (int a = 0; a < dim; ++a) diagonal[a] = 1e-4 * (1.0 + 0.5 * a);
    const mm::Tensor2<dim> eps = diagonal.asDiagonal();
    {
        const double l = 2e-3, a = 0.5 * l * 1.01;  // prestressed: overlap 1% of l
        mm::Simulation<dim, mm::FrictionalLinear, mm::NoWalls, mm::VelocityVerlet, mm::LinkedCells, mm::BackgroundDamping> sim(
            mm::FrictionalLinear{mm::LinearSpringDashpot(k, gamma0), mm::CundallStrack(0.2 * k, 0.2 * gamma0, 0.5)},
            periodic_box<dim>(5 * l), {}, {}, {}, mm::BackgroundDamping(1e-3, 1e-10));
        for (int t = 0; t < (dim == 2 ? 25 : 125); ++t) {
            V x;
            for (int d = 0, u = t; d < dim; ++d, u /= 5) x[d] = (u % 5 + 0.5) * l;
            sim.particles().add(x, a, mm::sphere_mass(rho, a));
        }
        sim.set_time_step(mm::contact_duration(k, gamma0, mm::sphere_mass(rho, a) / 2) / 50);
        const auto r = mm::relaxed_response(sim, eps, 0.0);
        BOOST_TEST_MESSAGE(dim << "D lattice: ratio " << r.ratio << " after " << r.relaxation_steps << " steps");
        BOOST_TEST(std::abs(r.ratio - 1.0) < 1e-9);
        BOOST_TEST((r.relaxed_change - r.affine_change).norm() < 1e-9 * r.affine_change.norm());
    }
    {
        auto sim = relaxed_simulation<dim>(600, nu_dense<dim>(), 5);
        const auto r = mm::relaxed_response(sim, eps);
        BOOST_TEST_MESSAGE(dim << "D disordered: affine/predicted " << (r.affine_change.cwiseProduct(eps)).sum() /
                                                                          (r.predicted.cwiseProduct(eps)).sum()
                               << ", relaxed/affine ratio " << r.ratio << " after " << r.relaxation_steps << " steps");
        BOOST_TEST(r.ratio > 0.0);
        BOOST_TEST(r.ratio <= 1.0);
        BOOST_TEST(r.relaxation_steps > 0u);
    }
}

// Rotating the packing rotates F and sigma as rank-2 and C as rank-4 tensors; renumbering the
// particles changes nothing; a periodic packing doubled along an axis has the same averages.
BOOST_AUTO_TEST_CASE_TEMPLATE(invariances, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    using M = mm::Tensor2<dim>;
    const double L = dim == 2 ? 0.03 : 0.012;
    const auto p = random_packing<dim>(dim == 2 ? 600 : 800, 0.5e-3, 1.5e-3, L, 9, true, true);
    // Synthetic tangential forces f_t = 0.1 f_n (n.g) (1 - n n) g: odd in n (so the force on j
    // is minus the force on i whichever partner is called i) and rotating with g.
    const V g = V::Ones().normalized();
    auto make = [&](const std::vector<V>& x, const std::vector<double>& r, mm::Domain<dim> domain, const V& dir) {
        mm::PackingSnapshot<dim> s;
        s.domain = domain;
        s.position = x;
        s.radius = r;
        mm::detect_contacts(s, k, 0.2 * k);
        for (auto& c : s.contacts) {
            const V& n = c.normal;
            c.tangential_force = 0.1 * c.normal_force * n.dot(dir) * (dir - n * n.dot(dir));
        }
        return s;
    };
    auto close = [](const auto& a, const auto& b, double scale) { return (a - b).norm() <= 1e-11 * scale; };
    const auto base_snapshot = make(p.x, p.r, periodic_box<dim>(L), g);
    const auto base = mm::average(base_snapshot, mm::Region<dim>::whole(base_snapshot));

    // Rotation: the periodic packing, unwrapped as an open cluster, rotated about its centre; a
    // region that holds everything (same volume before and after).
    M R;
    if constexpr (dim == 2) R = Eigen::Rotation2Dd(0.4).toRotationMatrix();
    else R = Eigen::AngleAxisd(0.4, V(1, -2, 2).normalized()).toRotationMatrix();
    std::vector<V> rotated;
    for (const auto& x : p.x) rotated.push_back(R * (x - V::Constant(0.5 * L)));
    const auto open = make(p.x, p.r, mm::Domain<dim>(), g);
    const auto turned = make(rotated, p.r, mm::Domain<dim>(), R * g);
    const auto big = mm::Region<dim>::box(V::Constant(-2 * L), V::Constant(2 * L));
    const auto a0 = mm::average(open, big), a1 = mm::average(turned, big);
    BOOST_TEST(a0.contacts == a1.contacts);
    BOOST_TEST(close(a1.fabric, M(R * a0.fabric * R.transpose()), a0.fabric.norm()));
    BOOST_TEST(close(a1.stress, M(R * a0.stress * R.transpose()), a0.stress.norm()));
    BOOST_TEST(close(a1.stiffness_normal.matrix(), a0.stiffness_normal.rotated(R).matrix(), a0.stiffness_normal.matrix().norm()));
    BOOST_TEST(close(a1.stiffness_tangential.matrix(), a0.stiffness_tangential.rotated(R).matrix(),
                     a0.stiffness_tangential.matrix().norm()));

    // Renumbering.
    std::vector<std::size_t> order(p.x.size());
    std::iota(order.begin(), order.end(), 0);
    std::reverse(order.begin(), order.end());
    std::rotate(order.begin(), order.begin() + 31, order.end());
    std::vector<V> x2;
    std::vector<double> r2;
    for (auto i : order) {
        x2.push_back(p.x[i]);
        r2.push_back(p.r[i]);
    }
    const auto renumbered_snapshot = make(x2, r2, periodic_box<dim>(L), g);
    const auto renumbered = mm::average(renumbered_snapshot, mm::Region<dim>::whole(renumbered_snapshot));
    BOOST_TEST(renumbered.contacts == base.contacts);
    BOOST_TEST(close(renumbered.fabric, base.fabric, base.fabric.norm()));
    BOOST_TEST(close(renumbered.stress, base.stress, base.stress.norm()));
    BOOST_TEST(close(renumbered.stiffness_normal.matrix(), base.stiffness_normal.matrix(), base.stiffness_normal.matrix().norm()));

    // Periodic doubling along axis 0.
    std::vector<V> x3 = p.x;
    std::vector<double> r3 = p.r;
    for (std::size_t i = 0; i < p.x.size(); ++i) {
        V shifted = p.x[i];
        shifted[0] += L;
        x3.push_back(shifted);
        r3.push_back(p.r[i]);
    }
    V hi = V::Constant(L);
    hi[0] = 2 * L;
    const auto doubled_snapshot = make(x3, r3, mm::Domain<dim>::fully_periodic(V::Zero(), hi), g);
    const auto doubled = mm::average(doubled_snapshot, mm::Region<dim>::whole(doubled_snapshot));
    BOOST_TEST(doubled.contacts == 2 * base.contacts);
    BOOST_TEST(std::abs(doubled.volume_fraction - base.volume_fraction) < 1e-12);
    BOOST_TEST(std::abs(doubled.coordination - base.coordination) < 1e-12);
    BOOST_TEST(close(doubled.fabric, base.fabric, base.fabric.norm()));
    BOOST_TEST(close(doubled.stress, base.stress, base.stress.norm()));
    BOOST_TEST(close(doubled.stiffness_normal.matrix(), base.stiffness_normal.matrix(), base.stiffness_normal.matrix().norm()));
    BOOST_TEST(close(doubled.stiffness_tangential.matrix(), base.stiffness_tangential.matrix(),
                     base.stiffness_tangential.matrix().norm()));
}

BOOST_AUTO_TEST_SUITE_END()
