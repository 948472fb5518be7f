// The anisotropy coefficients (averaging/anisotropy.hpp) against constructed distributions whose
// coefficients are known exactly, and the stress-force-fabric relation, exact where every branch
// has one length. 2D: contacts at equally spaced angles (their sums of cos 2k theta vanish up to
// the harmonics the products reach); 3D: the icosahedron's 12 vertices, a spherical 5-design (the
// mean of any polynomial of degree 5 or less over them is its mean over the sphere).
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(physics_anisotropy)  // the file's cases, run as the CTest test of this file's name

using namespace mmtest;

namespace {
constexpr double pi = std::numbers::pi;

mm::ContactRecord<2> contact_at(double theta, double fn, double ft) {
    mm::ContactRecord<2> c;
    c.normal = mm::Vec<2>(std::cos(theta), std::sin(theta));
    c.normal_force = fn;
    c.tangential_force = ft * mm::Vec<2>(-std::sin(theta), std::cos(theta));
    return c;
}

// E = (1 + a_c cos 2(th - th0)) / pi over [0, pi), f_n = f0 (1 + a_n cos 2(th - th0)),
// f_t = -f0 a_t sin 2(th - th0), on 36 equally spaced angles.
mm::Anisotropy<2> coaxial(double a_c, double a_n, double a_t, double theta0, double f0 = 3.0) {
    mm::AnisotropySums<2> sums;
    const int m = 36;
    for (int k = 0; k < m; ++k) {
        const double th = (k + 0.5) * pi / m, u = 2.0 * (th - theta0);
        sums.add(contact_at(th, f0 * (1.0 + a_n * std::cos(u)), -f0 * a_t * std::sin(u)), 1.0 + a_c * std::cos(u));
    }
    return mm::finish_anisotropy(sums);
}

// The 12 vertices of an icosahedron, unit length.
std::vector<mm::Vec<3>> icosahedron() {
    const double g = std::numbers::phi;
    std::vector<mm::Vec<3>> v;
    for (double s : {-1.0, 1.0})
        for (double t : {-1.0, 1.0}) {
            v.emplace_back(0.0, s, t * g);
            v.emplace_back(s, t * g, 0.0);
            v.emplace_back(t * g, 0.0, s);
        }
    for (auto& x : v) x.normalize();
    return v;
}

// A random symmetric deviatoric 3x3 tensor of magnitude about `size`.
mm::Tensor2<3> random_deviator(std::mt19937_64& rng, double size) {
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    mm::Tensor2<3> a;
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j) a(i, j) = a(j, i) = size * U(rng);
    return mm::deviator<3>(a);
}
}  // namespace

// Each coefficient alone is returned exactly, with its direction.
BOOST_AUTO_TEST_CASE(fourier_coefficients_one_at_a_time_2d) {
    const double th0 = 0.3;
    const auto c = coaxial(0.4, 0.0, 0.0, th0);
    BOOST_TEST(std::abs(c.a_c - 0.4) < 1e-14);
    BOOST_TEST(std::abs(c.theta_c - th0) < 1e-13);
    BOOST_TEST(std::abs(c.a_n) < 1e-14);
    const auto n = coaxial(0.0, 0.3, 0.0, th0);
    BOOST_TEST(std::abs(n.a_n - 0.3) < 1e-14);
    BOOST_TEST(std::abs(n.theta_n - th0) < 1e-13);
    BOOST_TEST(std::abs(n.a_c) < 1e-14);
    BOOST_TEST(std::abs(n.mean_normal_force - 3.0) < 1e-14);
    const auto t = coaxial(0.0, 0.0, 0.2, th0);
    BOOST_TEST(std::abs(t.a_t - 0.2) < 1e-14);
    BOOST_TEST(std::abs(t.theta_t - th0) < 1e-13);
    BOOST_TEST(std::abs(t.a_n) < 1e-14);
}

// All three at once: the mean normal force is f0 (1 + a_c a_n / 2), so the tensor forms return
// a_n' = (a_c + a_n) / (1 + a_c a_n / 2) - a_c and a_t' = a_t / (1 + a_c a_n / 2), a_c exactly:
// the products of the coefficients the second-order forms leave out, computed here exactly.
BOOST_AUTO_TEST_CASE(fourier_coefficients_together_2d) {
    const double ac = 0.4, an = 0.3, at = 0.2, th0 = -0.7;
    const auto a = coaxial(ac, an, at, th0);
    const double d = 1.0 + 0.5 * ac * an;
    BOOST_TEST(std::abs(a.a_c - ac) < 1e-14);
    BOOST_TEST(std::abs(a.a_n - ((ac + an) / d - ac)) < 1e-14);
    BOOST_TEST(std::abs(a.a_t - at / d) < 1e-14);
    BOOST_TEST(std::abs(a.mean_normal_force - 3.0 * d) < 1e-13);
    for (double theta : {a.theta_c, a.theta_n, a.theta_t}) BOOST_TEST(std::abs(theta - th0) < 1e-13);
    // The rebuilt stress ratio along th0: (a_c + a_n' + a_t') / 2.
    const mm::Vec<2> e(std::cos(th0), std::sin(th0));
    BOOST_TEST(std::abs(e.dot(a.stress_ratio() * e) - 0.5 * (ac + (ac + an) / d - ac + at / d)) < 1e-14);
}

// 3D: the tensors of E, f_n and f_t (f_t = (2/3) f0 (a n - (n . a n) n)) on the icosahedron's
// directions, each alone, returned exactly for random deviatoric tensors.
BOOST_AUTO_TEST_CASE(tensor_coefficients_3d) {
    std::mt19937_64 rng(7);
    const auto dirs = icosahedron();
    for (int trial = 0; trial < 5; ++trial) {
        const mm::Tensor2<3> a = random_deviator(rng, 0.2);
        const double f0 = 2.5;
        mm::AnisotropySums<3> fabric, normal, tangential;
        for (const auto& n : dirs) {
            mm::ContactRecord<3> c;
            c.normal = n;
            c.normal_force = f0;
            fabric.add(c, 1.0 + n.dot(a * n));
            c.normal_force = f0 * (1.0 + n.dot(a * n));
            normal.add(c, 1.0);
            c.normal_force = f0;
            c.tangential_force = 2.0 / 3.0 * f0 * (a * n - n.dot(a * n) * n);
            tangential.add(c, 1.0);
        }
        const auto ac = mm::finish_anisotropy(fabric), an = mm::finish_anisotropy(normal), at = mm::finish_anisotropy(tangential);
        BOOST_TEST((ac.contact - a).norm() < 1e-14);
        BOOST_TEST(ac.normal_force.norm() < 1e-14);
        BOOST_TEST((an.normal_force - a).norm() < 1e-14);
        BOOST_TEST(an.contact.norm() < 1e-14);
        BOOST_TEST((at.tangential_force - a).norm() < 1e-14);
        BOOST_TEST(std::abs(ac.a_c - std::sqrt(1.5 * a.squaredNorm())) < 1e-14);
    }
}

// The stress-force-fabric relation is exact where every branch has one length: contacts of
// random normals and random forces (no equilibrium needed) in a periodic box, averaged by
// average() and anisotropy() over the whole box, both selection rules.
BOOST_AUTO_TEST_CASE_TEMPLATE(stress_force_fabric_with_equal_branches, D, Dims) {
    constexpr int dim = D::value;
    std::mt19937_64 rng(11);
    std::normal_distribution<double> N(0.0, 1.0);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    mm::PackingSnapshot<dim> s;
    const double L = 0.02, l = 2e-3;
    s.domain = mm::Domain<dim>::fully_periodic(mm::Vec<dim>::Zero(), mm::Vec<dim>::Constant(L));
    for (int p = 0; p < 2; ++p) {
        s.position.push_back(mm::Vec<dim>::Constant(0.25 * L + 0.5 * L * p));
        s.radius.push_back(0.5 * l);
    }
    for (int q = 0; q < 200; ++q) {
        mm::ContactRecord<dim> c;
        c.i = 0;
        c.j = 1;
        mm::Vec<dim> n;
        for (int d = 0; d < dim; ++d) n[d] = N(rng) + (d == 0 ? 1.5 : 0.0);  // orientations gathered about axis 1
        c.normal = n.normalized();
        c.branch = l * c.normal;
        for (int d = 0; d < dim; ++d) c.point[d] = L * U(rng);
        c.share_i = 0.5;
        c.normal_force = 1.0 + 2.0 * U(rng) * std::abs(c.normal[dim - 1]);  // stronger along the last axis
        mm::Vec<dim> t;
        for (int d = 0; d < dim; ++d) t[d] = 0.3 * N(rng);
        c.tangential_force = t - t.dot(c.normal) * c.normal;
        s.contacts.push_back(c);
    }
    for (auto rule : {mm::SelectionRule::contact_point, mm::SelectionRule::particle_centre}) {
        mm::AveragingOptions o;
        o.rule = rule;
        const auto m = mm::average(s, mm::Region<dim>::whole(s), o);
        const auto a = mm::anisotropy(s, mm::Region<dim>::whole(s), o);
        const mm::Tensor2<dim> ratio = mm::deviator<dim>(0.5 * (m.stress + m.stress.transpose())) / m.pressure;
        BOOST_TEST(ratio.norm() > 0.1);  // a real anisotropy
        BOOST_TEST((a.stress_ratio() - ratio).norm() < 1e-13 * ratio.norm());
        BOOST_TEST(a.contacts == 200.0);
    }
}

BOOST_AUTO_TEST_SUITE_END()
