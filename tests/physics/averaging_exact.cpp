// The micro-macro averages against exact answers: lattices (fabric, stiffness), the 2D identities
// between normal and tangential stiffness, and invariance under rotation, renumbering and
// periodic doubling.
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(physics_averaging_exact)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;

namespace {
constexpr double pi = std::numbers::pi;

// A periodic lattice: `cell` positions repeated n times along each axis with the given periods.
// Radii are half the nearest distance l, enlarged by 1e-14 so that touching counts as contact.
template <int dim>
mm::PackingSnapshot<dim> lattice(const std::vector<mm::Vec<dim>>& cell, const mm::Vec<dim>& period, int n, double l,
                                 double kt = 0.0) {
    mm::PackingSnapshot<dim> s;
    s.domain = mm::Domain<dim>::fully_periodic(mm::Vec<dim>::Zero(), period * n);
    int total = 1;
    for (int d = 0; d < dim; ++d) total *= n;
    for (int t = 0; t < total; ++t) {
        mm::Vec<dim> shift;
        for (int d = 0, u = t; d < dim; ++d, u /= n) shift[d] = (u % n) * period[d];
        for (const auto& c : cell) {
            s.position.push_back(c + shift);
            s.radius.push_back(0.5 * l * (1.0 + 1e-14));
        }
    }
    mm::detect_contacts(s, k, kt);
    return s;
}

double rel(double a, double b) { return std::abs(a - b) / std::abs(b); }

template <int dim>
void check_both_rules(const mm::PackingSnapshot<dim>& s, auto&& check) {
    for (auto rule : {mm::SelectionRule::contact_point, mm::SelectionRule::particle_centre}) {
        mm::AveragingOptions o;
        o.rule = rule;
        check(mm::average(s, mm::Region<dim>::whole(s), o));
    }
}

// Off-diagonal and odd entries must vanish: all entries not in `allowed` are below 1e-12 k.
template <int dim>
void check_zero_except(const mm::Tensor4<dim>& C, double scale, auto&& allowed) {
    for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b)
            for (int c = 0; c < dim; ++c)
                for (int d = 0; d < dim; ++d)
                    if (!allowed(a, b, c, d)) BOOST_TEST(std::abs(C(a, b, c, d)) < 1e-12 * scale);
}
}  // namespace

// Triangular lattice of equal disks, spacing l, normal springs, from Eq. 9 summed by hand:
// C_1111 = C_2222 = 3 sqrt(3)/4 k, C_1122 = C_1212 = sqrt(3)/4 k, odd entries zero,
// tr F = 6 nu with nu = pi / (2 sqrt 3). With k_t the identities below fix C^t.
BOOST_AUTO_TEST_CASE(triangular_lattice) {
    const double l = 2e-3;
    const auto s = lattice<2>({{0, 0}, {0.5 * l, 0.5 * std::sqrt(3.0) * l}}, {l, std::sqrt(3.0) * l}, 6, l, 0.2 * k);
    BOOST_TEST(s.contacts.size() == 3u * s.size());
    check_both_rules(s, [&](const mm::MicroMacro<2>& m) {
        const auto& C = m.stiffness_normal;
        BOOST_TEST(rel(C(0, 0, 0, 0), 3 * std::sqrt(3.0) / 4 * k) < 1e-12);
        BOOST_TEST(rel(C(1, 1, 1, 1), 3 * std::sqrt(3.0) / 4 * k) < 1e-12);
        BOOST_TEST(rel(C(0, 0, 1, 1), std::sqrt(3.0) / 4 * k) < 1e-12);
        BOOST_TEST(rel(C(0, 1, 0, 1), std::sqrt(3.0) / 4 * k) < 1e-12);
        BOOST_TEST(std::abs(C(0, 0, 0, 1)) < 1e-12 * k);
        BOOST_TEST(std::abs(C(0, 1, 1, 1)) < 1e-12 * k);
        BOOST_TEST(rel(m.volume_fraction, pi / (2 * std::sqrt(3.0))) < 1e-12);
        BOOST_TEST(rel(m.contact_number_density, 6 * m.volume_fraction) < 1e-12);
        BOOST_TEST(rel(m.coordination, 6.0) < 1e-15);
        BOOST_TEST(rel(m.g2, 1.0) < 1e-12);
        BOOST_TEST(m.fabric_deviator < 1e-12);  // isotropic
        // Tangential: C^t_1111 = C^t_2222 = alpha C^n_1122, C^t_1212 = alpha C^n_1111, ...
        const auto& T = m.stiffness_tangential;
        BOOST_TEST(rel(T(0, 0, 0, 0), 0.2 * C(0, 0, 1, 1)) < 1e-12);
        BOOST_TEST(rel(T(0, 1, 0, 1), 0.2 * C(0, 0, 0, 0)) < 1e-12);
        BOOST_TEST(rel(T(0, 0, 1, 1), -0.2 * C(0, 0, 1, 1)) < 1e-12);
    });
}

// Square lattice: every contact along an axis: C_1111 = C_2222 = k, every other normal entry 0;
// tangential C^t_1212 = C^t_2121 = k_t and nothing else; tr F = 4 nu, nu = pi/4.
BOOST_AUTO_TEST_CASE(square_lattice) {
    const double l = 2e-3, kt = 0.2 * k;
    const auto s = lattice<2>({{0, 0}}, {l, l}, 5, l, kt);
    check_both_rules(s, [&](const mm::MicroMacro<2>& m) {
        BOOST_TEST(rel(m.stiffness_normal(0, 0, 0, 0), k) < 1e-12);
        BOOST_TEST(rel(m.stiffness_normal(1, 1, 1, 1), k) < 1e-12);
        check_zero_except(m.stiffness_normal, k, [](int a, int b, int c, int d) { return a == b && b == c && c == d; });
        BOOST_TEST(rel(m.stiffness_tangential(0, 1, 0, 1), kt) < 1e-12);
        BOOST_TEST(rel(m.stiffness_tangential(1, 0, 1, 0), kt) < 1e-12);
        check_zero_except(m.stiffness_tangential, k, [](int a, int b, int c, int d) { return a == c && b == d && a != b; });
        BOOST_TEST(rel(m.volume_fraction, pi / 4) < 1e-12);
        BOOST_TEST(rel(m.contact_number_density, 4 * m.volume_fraction) < 1e-12);
    });
}

// Simple cubic, spacing l: 3 contacts per particle (one per axis), volume l^3 per particle:
// C_aaaa = k l^2 / l^3 = k / l, every other entry 0; tr F = 6 nu, nu = pi/6.
BOOST_AUTO_TEST_CASE(simple_cubic_lattice) {
    const double l = 2e-3;
    const auto s = lattice<3>({{0, 0, 0}}, {l, l, l}, 4, l);
    check_both_rules(s, [&](const mm::MicroMacro<3>& m) {
        for (int a = 0; a < 3; ++a) BOOST_TEST(rel(m.stiffness_normal(a, a, a, a), k / l) < 1e-12);
        check_zero_except(m.stiffness_normal, k / l, [](int a, int b, int c, int d) { return a == b && b == c && c == d; });
        BOOST_TEST(rel(m.volume_fraction, pi / 6) < 1e-12);
        BOOST_TEST(rel(m.contact_number_density, 6 * m.volume_fraction) < 1e-12);
        BOOST_TEST(rel(m.coordination, 6.0) < 1e-15);
    });
}

// Face-centred cubic, cube side A = sqrt(2) l, 4 particles per cube, volume l^3/sqrt(2) per
// particle, 6 contacts per particle along (1,1,0)/sqrt 2 and its permutations and sign changes:
//   C_1111 = sqrt(2)/l^3 k l^2 sum n_1^4       = sqrt(2)/l k (4 x 1/4) = sqrt(2) k / l,
//   C_1122 = C_1212 = sqrt(2)/l k sum n_1^2 n_2^2 = sqrt(2)/l k (2 x 1/4) = k / (sqrt(2) l),
// entries with an odd count of any index vanish; tr F = 12 nu, nu = pi / (3 sqrt 2).
BOOST_AUTO_TEST_CASE(face_centred_cubic_lattice) {
    const double l = 2e-3, A = std::sqrt(2.0) * l;
    const auto s = lattice<3>({{0, 0, 0}, {0.5 * A, 0.5 * A, 0}, {0.5 * A, 0, 0.5 * A}, {0, 0.5 * A, 0.5 * A}}, {A, A, A}, 3, l);
    BOOST_TEST(s.contacts.size() == 6u * s.size());
    check_both_rules(s, [&](const mm::MicroMacro<3>& m) {
        const auto& C = m.stiffness_normal;
        for (int a = 0; a < 3; ++a) BOOST_TEST(rel(C(a, a, a, a), std::sqrt(2.0) * k / l) < 1e-12);
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                if (a != b) {
                    BOOST_TEST(rel(C(a, a, b, b), k / (std::sqrt(2.0) * l)) < 1e-12);
                    BOOST_TEST(rel(C(a, b, a, b), k / (std::sqrt(2.0) * l)) < 1e-12);
                }
        check_zero_except(C, k / l, [](int a, int b, int c, int d) {
            int count[3] = {0, 0, 0};
            ++count[a], ++count[b], ++count[c], ++count[d];
            return count[0] % 2 == 0 && count[1] % 2 == 0 && count[2] % 2 == 0;
        });
        BOOST_TEST(rel(m.volume_fraction, pi / (3 * std::sqrt(2.0))) < 1e-12);
        BOOST_TEST(rel(m.contact_number_density, 12 * m.volume_fraction) < 1e-12);
        // The Kelvin matrix of a cubic crystal has the eigenvalues c11 + 2 c12 (bulk, once),
        // c11 - c12 (twice) and 2 c44 (three times); here c12 = c44 = c11 / 2, so ascending:
        // c11/2, c11/2, c11, c11, c11, 2 c11.
        const auto ev = C.kelvin_eigenvalues();
        const double c11 = std::sqrt(2.0) * k / l, c12 = k / (std::sqrt(2.0) * l);
        BOOST_TEST(rel(ev[0], c11 - c12) < 1e-12);
        BOOST_TEST(rel(ev[1], c11 - c12) < 1e-12);
        for (int e = 2; e < 5; ++e) BOOST_TEST(rel(ev[e], 2 * c12) < 1e-12);
        BOOST_TEST(rel(ev[5], c11 + 2 * c12) < 1e-12);
    });
}

// Exact in 2D for any packing, since there t_b t_d = delta_bd - n_b n_d (Eq. 9), with alpha = k_t/k:
// C^t_1111 = C^t_2222 = alpha C^n_1122; C^t_1122 = -alpha C^n_1122; C^t_1212 = alpha C^n_1111;
// C^t_2121 = alpha C^n_2222; C^t_1222 = alpha C^n_1112 = -C^t_1112; C^t_1121 = alpha C^n_1222 = -C^t_2122;
// and C^n has full minor and major symmetry with C^n_1122 = C^n_1212.
BOOST_AUTO_TEST_CASE(stiffness_identities_2d) {
    const double alpha = 0.2;
    const auto p = random_packing<2>(1500, 0.5e-3, 1.5e-3, 0.06, 4, true, true);
    mm::PackingSnapshot<2> s;
    s.domain = periodic_box<2>(0.06);
    s.position = p.x;
    s.radius = p.r;
    mm::detect_contacts(s, k, alpha * k);
    BOOST_TEST_REQUIRE(s.contacts.size() > 1000u);
    for (auto rule : {mm::SelectionRule::contact_point, mm::SelectionRule::particle_centre}) {
        mm::AveragingOptions o;
        o.rule = rule;
        const auto m = mm::average(s, mm::Region<2>::box({0.01, 0.015}, {0.045, 0.05}), o);
        const auto& N = m.stiffness_normal;
        const auto& T = m.stiffness_tangential;
        const double scale = N(0, 0, 0, 0);
        auto same = [&](double a, double b) { return std::abs(a - b) <= 1e-12 * scale; };
        BOOST_TEST(same(T(0, 0, 0, 0), alpha * N(0, 0, 1, 1)));
        BOOST_TEST(same(T(1, 1, 1, 1), alpha * N(0, 0, 1, 1)));
        BOOST_TEST(same(T(0, 0, 1, 1), -alpha * N(0, 0, 1, 1)));
        BOOST_TEST(same(T(0, 1, 0, 1), alpha * N(0, 0, 0, 0)));
        BOOST_TEST(same(T(1, 0, 1, 0), alpha * N(1, 1, 1, 1)));
        BOOST_TEST(same(T(0, 1, 1, 1), alpha * N(0, 0, 0, 1)));
        BOOST_TEST(same(T(0, 0, 0, 1), -T(0, 1, 1, 1)));
        BOOST_TEST(same(T(0, 0, 1, 0), alpha * N(0, 1, 1, 1)));
        BOOST_TEST(same(T(1, 0, 1, 1), -T(0, 0, 1, 0)));
        BOOST_TEST(same(N(0, 0, 1, 1), N(0, 1, 0, 1)));
        BOOST_TEST(same(N(0, 1, 0, 0), N(0, 0, 0, 1)));  // minor symmetry
        BOOST_TEST(same(N(0, 1, 1, 1), N(1, 1, 0, 1)));  // major symmetry
        BOOST_TEST(std::abs(N(0, 0, 0, 1)) > 1e-6 * scale);  // odd entries present: a real test of the signs
    }
}

// Rattlers: particles with fewer than dim + 1 contacts, found repeatedly. A square lattice (4
// contacts each, l = 2 mm) with two extra particles in one cell: A touches the two lower sites
// of the cell and B, B touches only A. B is a rattler at once; without B, A has two contacts and
// becomes one too. Excluding both leaves the lattice's coordination 4.
BOOST_AUTO_TEST_CASE(rattlers_are_found_iteratively) {
    const double l = 2e-3;
    auto s = lattice<2>({{0, 0}}, {l, l}, 4, l);  // 16 particles, 32 contacts
    const mm::Vec<2> corner = s.position[0];
    s.position.push_back(corner + mm::Vec<2>(1e-3, 0.8e-3));  // A: 1.2806 mm from both lower sites
    s.radius.push_back(0.3e-3);
    s.position.push_back(corner + mm::Vec<2>(1e-3, 1.1999e-3));  // B: just touching A
    s.radius.push_back(0.1e-3);
    mm::detect_contacts(s, k, 0.0);
    BOOST_TEST_REQUIRE(s.contacts.size() == 35u);
    mm::AveragingOptions keep, drop;
    drop.exclude_rattlers = true;
    const auto all = mm::average(s, mm::Region<2>::whole(s), keep);
    const auto without = mm::average(s, mm::Region<2>::whole(s), drop);
    BOOST_TEST(all.rattlers == 2u);
    BOOST_TEST(without.rattlers == 2u);
    BOOST_TEST(std::abs(all.coordination - 2.0 * 35 / 18) < 1e-12);  // every contact, every particle
    BOOST_TEST(std::abs(without.coordination - 4.0) < 1e-12);        // the lattice alone
    BOOST_TEST(without.contacts == 32u);
    // The jamming coordination whatever the option: the lattice's 4 in both averages.
    BOOST_TEST(std::abs(all.coordination_without_rattlers - 4.0) < 1e-12);
    BOOST_TEST(without.coordination_without_rattlers == without.coordination);
}

// The rattlers of a random overlapping packing against the definition applied literally: sweep
// over the particles, removing any with fewer than dim + 1 contacts to particles not yet
// removed, until a sweep removes none. The packing is loose enough (about dim + 1 contacts on
// average) that removals cascade, which the check asserts too.
BOOST_AUTO_TEST_CASE_TEMPLATE(rattlers_match_the_repeated_sweep, D, Dims) {
    constexpr int dim = D::value;
    for (unsigned seed = 1; seed <= 5; ++seed) {
        mm::PackingSnapshot<dim> s;
        const int n = 400;
        const double L = 0.02;
        s.domain = mm::Domain<dim>::fully_periodic(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant(L));
        std::mt19937_64 rng(seed);
        std::uniform_real_distribution<double> U(0.0, 1.0);
        // Radii for a mean coordination of about dim + 1 at this number density.
        const double a = dim == 2 ? 0.57e-3 : 1.55e-3;
        for (int p = 0; p < n; ++p) {
            mm::Vec<dim> x;
            for (int d = 0; d < dim; ++d) x[d] = L * U(rng);
            s.position.push_back(x);
            s.radius.push_back(a * (0.8 + 0.4 * U(rng)));
        }
        mm::detect_contacts(s, k, 0.0);
        std::vector<char> removed(n, 0);
        std::size_t at_once = 0;  // rattlers before any removal
        for (bool changed = true, first = true; changed; first = false) {
            changed = false;
            std::vector<int> count(n, 0);
            for (const auto& c : s.contacts)
                if (!removed[c.i] && !removed[c.j]) ++count[c.i], ++count[c.j];
            for (int p = 0; p < n; ++p)
                if (!removed[p] && count[p] < dim + 1) {
                    removed[p] = 1;
                    changed = true;
                    at_once += first;
                }
        }
        const auto rattler = mm::detail::find_rattlers(s);
        const auto total = static_cast<std::size_t>(std::count(removed.begin(), removed.end(), 1));
        BOOST_TEST(total > at_once);  // the removals cascaded
        BOOST_TEST(total < std::size_t(n));  // and a load-bearing part remains
        BOOST_TEST((rattler == removed), "seed " << seed << ": " << std::count(rattler.begin(), rattler.end(), 1)
                                                  << " rattlers found, " << total << " by the sweep");
        // The coordination without rattlers: twice the contacts the sweep kept over the particles it kept.
        std::size_t kept = 0;
        for (const auto& c : s.contacts) kept += !removed[c.i] && !removed[c.j];
        const auto m = mm::average(s, mm::Region<dim>::whole(s));
        BOOST_TEST(m.coordination_without_rattlers == 2.0 * double(kept) / double(n - total), boost::test_tools::tolerance(1e-14));
    }
}

// The kinetic stress is 1/V sum m v (x) v over the particles inside; the sliding option removes
// exactly the sliding contacts from C^t and reports their weighted fraction.
BOOST_AUTO_TEST_CASE_TEMPLATE(kinetic_stress_and_sliding_contacts, D, Dims) {
    constexpr int dim = D::value;
    using V = mm::Vec<dim>;
    const double l = 2e-3;
    auto s = lattice<dim>({V::Zero()}, V::Constant(l), 4, l, 0.2 * k);
    s.mass.assign(s.size(), 0.0);
    s.velocity.assign(s.size(), V::Zero());
    s.mass[3] = 2.0;
    s.velocity[3] = V::Constant(0.5);
    s.mass[7] = 3.0;
    s.velocity[7][0] = -1.0;
    mm::AveragingOptions o;
    o.kinetic_stress = true;
    const auto m = mm::average(s, mm::Region<dim>::whole(s), o);
    const mm::Tensor2<dim> expected = (2.0 * V::Constant(0.5) * V::Constant(0.5).transpose() +
                                       3.0 * V::UnitX() * V::UnitX().transpose()) / m.volume;
    BOOST_TEST((m.stress_kinetic - expected).norm() < 1e-14 * expected.norm());

    for (std::size_t q = 0; q < s.contacts.size(); q += 3) s.contacts[q].sliding = true;
    std::size_t sliding = 0;
    mm::Tensor4<dim> removed;
    for (std::size_t q = 0; q < s.contacts.size(); q += 3) {
        ++sliding;
        removed.add_tangential(s.contacts[q].kt * s.contacts[q].branch.squaredNorm() / m.volume, s.contacts[q].normal);
    }
    mm::AveragingOptions x;
    x.exclude_sliding_from_tangential_stiffness = true;
    const auto all = mm::average(s, mm::Region<dim>::whole(s));
    const auto elastic = mm::average(s, mm::Region<dim>::whole(s), x);
    BOOST_TEST(std::abs(all.sliding_fraction - double(sliding) / s.contacts.size()) < 1e-15);
    BOOST_TEST((all.stiffness_tangential.matrix() - elastic.stiffness_tangential.matrix() - removed.matrix()).norm() <
               1e-12 * all.stiffness_tangential.matrix().norm());
    BOOST_TEST((all.stiffness_normal.matrix() - elastic.stiffness_normal.matrix()).norm() == 0.0);
}

BOOST_AUTO_TEST_SUITE_END()
