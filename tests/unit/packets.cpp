// The pair loop on packets of eight (engine/packet_pair_loop.hpp, contact/frictional_packet.hpp)
// against the scalar pair loop it stands in for, on the same candidates: every force, torque,
// spring record, spill, opened contact and book. Without fused multiply-adds (MICROMACRO_FMA=OFF)
// the two agree bit for bit, since each lane evaluates the scalar law's expressions; with them the
// compiler fuses each its own way, and they agree to round-off. The scene has every branch: new
// contacts (approaching or not), sticking and sliding springs, the static/dynamic hysteresis,
// contacts in tension, candidates that do not touch or stopped touching, pairs across the periodic
// boundary and one a whole period off, a pair whose centres coincide, blocks' partial last
// packets, partners of another thread (spills) and ghosts (half weight in the books).
#include <boost/mpl/list.hpp>
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <type_traits>
#include <vector>

#include <micromacro/engine/pair_loop.hpp>
#include <micromacro/neighbors/linked_cells.hpp>

#include "support/same_bits.hpp"

BOOST_AUTO_TEST_SUITE(unit_packets)  // the file's cases, run as the CTest test of this file's name

namespace mm = micromacro;
using mm::Vec;

#ifdef MICROMACRO_PACKETS
namespace {

template <int dim>
using Spring = mm::TangentialSpring<dim>;
template <int dim>
using Spills = std::vector<mm::detail::Spill<dim, true>>;

// k, gamma_n, k_t, gamma_t, mu_s > mu_d (the hysteresis) and dt in one consistent set of units.
const mm::FrictionalLinear law{mm::LinearSpringDashpot(1000.0, 2.0), mm::CundallStrack(300.0, 0.5, 0.5, 0.3)};
constexpr double dt = 1e-3;

template <int dim, class Real>
struct Scene {
    std::vector<Vec<dim, Real>> x, v;
    std::vector<mm::Angular<dim, Real>> w;
    std::vector<Real> r, inverse_mass;
    std::vector<mm::IndexPair> pairs;
    std::vector<Spring<dim>> springs;
    mm::Domain<dim> box;
};

// A jittered lattice (8^3 spheres, 22^2 disks) in a periodic box, most neighbours overlapping,
// some apart; random velocities and spins, a few particles fast enough that their contacts are
// in tension; one particle moved a whole period (its pairs take the full minimum image), one on
// top of another. Springs: a quarter new, the rest touching with
// random springs up to twice the Coulomb limit, sliding or not. `sheared`: the box a moving cell,
// its first axis tilted by about a third of a period along the last and sheared at a rate whose image
// velocities match the particles' speeds (pairs across that boundary see their partners' images move).
template <int dim, class Real>
Scene<dim, Real> scene(bool sheared = false) {
    Scene<dim, Real> s;
    constexpr int side = dim == 3 ? 8 : 22;
    constexpr double spacing = 2.0;
    s.box = mm::Domain<dim>::fully_periodic(Vec<dim>::Zero(), Vec<dim>::Constant(side * spacing));
    if (sheared) {
        s.box.set_tilt(0, dim - 1, spacing * (side / 3));  // whole spacings: the lattice continues across
        Eigen::Matrix<double, dim, dim> L = Eigen::Matrix<double, dim, dim>::Zero();
        L(0, dim - 1) = 0.05 / (side * spacing);
        s.box.set_velocity_gradient(L);
    }
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> jitter(-0.06, 0.06), radius(0.97, 1.03), speed(-0.05, 0.05), spin(-0.1, 0.1), unit(0.0, 1.0);
    for (int a = 0; a < side; ++a)
        for (int b = 0; b < side; ++b)
            for (int c = 0; c < (dim == 3 ? side : 1); ++c) {
                Vec<dim> p, u;
                const int cell[3] = {a, b, c};
                for (int k = 0; k < dim; ++k) {
                    p[k] = (cell[k] + 0.5) * spacing + jitter(rng);
                    u[k] = speed(rng);
                }
                s.x.push_back(p.template cast<Real>());
                s.v.push_back(u.template cast<Real>());
                if constexpr (dim == 2) s.w.push_back(Real(spin(rng)));
                else s.w.push_back(Vec<3>(spin(rng), spin(rng), spin(rng)).cast<Real>());
                s.r.push_back(Real(radius(rng)));
                s.inverse_mass.push_back(Real(1.0 / (1.0 + unit(rng))));
            }
    const std::size_t n = s.x.size();
    s.x[n - 1] = s.x[n - 2];                  // coincident centres
    for (std::size_t i = 10; i < n; i += 37)  // fast particles: their dashpots outpull their springs
        s.v[i] = Vec<dim>::Constant(i % 2 ? 300.0 : -300.0).template cast<Real>();
    mm::LinkedCells().find_pairs<dim, Real>(s.x, s.r, s.box, 0.2, s.pairs);
    s.x[5][0] += Real(side * spacing);  // a period off, after the search (as a particle not yet wrapped)
    const double limit = 0.5 * 1000.0 * 0.05 / 300.0;  // mu_s k overlap / k_t at a typical overlap
    for (std::size_t c = 0; c < s.pairs.size(); ++c) {
        Spring<dim> h;
        if (unit(rng) > 0.25) {
            if constexpr (dim == 2) {
                h.spring = 2.0 * limit * (unit(rng) - 0.5);
                h.ahead = h.spring + 0.1 * limit * (unit(rng) - 0.5);
            } else
                for (int a = 0; a < 3; ++a) {
                    h.spring[a] = 2.0 * limit * (unit(rng) - 0.5);
                    h.ahead[a] = h.spring[a] + 0.1 * limit * (unit(rng) - 0.5);
                }
            h.touching = true;
            h.sliding = unit(rng) < 0.5;
            h.fresh = unit(rng) < 0.2;
            h.trial = float(unit(rng));
        }
        s.springs.push_back(h);
    }
    return s;
}

template <int dim>
struct Result {
    std::vector<Vec<dim>> f;
    std::vector<mm::Angular<dim>> torque;
    std::vector<Spring<dim>> springs;
    mm::EnergyBooks books;
    mm::IndexPair coincident{0, 0};
    Spills<dim> spill;
    std::vector<std::size_t> opened;
};

template <bool packets, bool track, bool weighed, int dim, class Real>
Result<dim> run(const Scene<dim, Real>& s, mm::Index owned_end, mm::Index first_ghost) {
    Result<dim> out;
    out.f.assign(s.x.size(), Vec<dim>::Zero());
    if constexpr (dim == 2) out.torque.assign(s.x.size(), 0.0);
    else out.torque.assign(s.x.size(), Vec<3>::Zero());
    out.springs = s.springs;
    const mm::detail::ContactLoopInput<dim, Real, Spring<dim>> in{s.x.data(), s.v.data(), s.r.data(), s.inverse_mass.data(), s.w.data(),
                                                                  s.pairs.data(), out.springs.data(), first_ghost};
    if constexpr (packets)
        mm::detail::packet_pair_loop<track, true, weighed>(in, s.box, law, dt, 0, s.pairs.size(), out.f.data(), out.torque.data(),
                                                           out.books, out.coincident, owned_end, out.spill, out.opened);
    else
        mm::detail::scalar_pair_loop<track, true, true, weighed>(in, s.box, law, dt, 0, s.pairs.size(), out.f.data(), out.torque.data(),
                                                                 out.books, out.coincident, owned_end, out.spill, out.opened);
    return out;
}

// Equal to the bit without fused multiply-adds (zeros of either sign alike), else within 1e-11
// of the scale.
template <class T>
bool same(const T& a, const T& b, double scale) {
    return mmtest::same_bits(a, b, scale, 1e-11, true);
}
double magnitude(double a) { return std::abs(a); }
template <int dim>
double magnitude(const Vec<dim>& a) { return a.norm(); }

template <int dim, bool track, bool weighed, class Real>
void compare(double owned_share, double ghost_share, bool sheared = false) {
    const Scene<dim, Real> s = scene<dim, Real>(sheared);
    const auto owned_end = mm::Index(owned_share * double(s.x.size())), first_ghost = mm::Index(ghost_share * double(s.x.size()));
    const Result<dim> a = run<false, track, weighed>(s, owned_end, first_ghost);
    const Result<dim> b = run<true, track, weighed>(s, owned_end, first_ghost);
    double force_scale = 0.0, torque_scale = 0.0, spring_scale = 0.0;
    for (std::size_t i = 0; i < a.f.size(); ++i) {
        force_scale = std::max(force_scale, a.f[i].norm());
        torque_scale = std::max(torque_scale, magnitude(a.torque[i]));
    }
    for (const Spring<dim>& h : a.springs) spring_scale = std::max(spring_scale, magnitude(h.ahead));
    BOOST_TEST(force_scale > 0.0);
    BOOST_TEST(torque_scale > 0.0);
    std::size_t force_differ = 0, spring_differ = 0, touching = 0, sliding = 0, fresh = 0;
    for (std::size_t i = 0; i < a.f.size(); ++i)
        force_differ += !same(a.f[i], b.f[i], force_scale) + !same(a.torque[i], b.torque[i], torque_scale);
    for (std::size_t c = 0; c < a.springs.size(); ++c) {
        const Spring<dim>&p = a.springs[c], &q = b.springs[c];
        spring_differ += !same(p.spring, q.spring, spring_scale) || !same(p.ahead, q.ahead, spring_scale) ||
                         !same(double(p.trial), double(q.trial), 1.0) || p.sliding != q.sliding || p.touching != q.touching ||
                         p.fresh != q.fresh;
        touching += p.touching;
        sliding += p.touching && p.sliding;
        fresh += p.touching && p.fresh;
    }
    BOOST_TEST(force_differ == 0u);
    BOOST_TEST(spring_differ == 0u);
    // The scene has what it should: sliding and sticking contacts, new ones, opened ones.
    BOOST_TEST(sliding > touching / 20);
    BOOST_TEST(touching - sliding > touching / 4);
    BOOST_TEST(fresh > 0u);
    std::size_t tension = 0;  // contacts whose normal force pulls (the dashpot outpulls the spring)
    for (const mm::IndexPair& p : s.pairs) {
        const Vec<dim> d = s.box.separation(s.x[p.i].template cast<double>(), s.x[p.j].template cast<double>());
        const double dist = d.norm(), overlap = double(s.r[p.i]) + double(s.r[p.j]) - dist;
        if (!(overlap > 0.0 && dist > 0.0)) continue;
        const Vec<dim> dv = (s.v[p.i] - s.v[p.j]).template cast<double>() -
                            s.box.image_velocity(Vec<dim>(s.x[p.i].template cast<double>() - s.x[p.j].template cast<double>() - d));
        const double vn = (d / dist).dot(dv);
        tension += law.normal.stiffness() * overlap - law.normal.damping() * vn < 0.0;
    }
    BOOST_TEST(tension > 0u);
    BOOST_TEST(a.opened == b.opened);
    BOOST_TEST(!a.opened.empty());
    BOOST_TEST((a.coincident.i == b.coincident.i && a.coincident.j == b.coincident.j));
    BOOST_TEST(a.coincident.j == mm::Index(s.x.size() - 1));
    BOOST_TEST_REQUIRE(a.spill.size() == b.spill.size());
    BOOST_TEST((owned_end < s.x.size()) == !a.spill.empty());
    for (std::size_t k = 0; k < a.spill.size(); ++k) {
        BOOST_TEST(a.spill[k].particle == b.spill[k].particle);
        BOOST_TEST(same(a.spill[k].force, b.spill[k].force, force_scale));
        BOOST_TEST(same(a.spill[k].torque, b.spill[k].torque, torque_scale));
    }
    if constexpr (track) {
        const double scale = std::abs(a.books.dissipated_normal) + std::abs(a.books.dissipated_tangential) +
                             std::abs(a.books.dissipated_sliding);
        BOOST_TEST(a.books.dissipated_tangential > 0.0);
        BOOST_TEST(a.books.dissipated_sliding != 0.0);
        BOOST_TEST(same(a.books.dissipated_normal, b.books.dissipated_normal, scale));
        BOOST_TEST(same(a.books.dissipated_tangential, b.books.dissipated_tangential, scale));
        BOOST_TEST(same(a.books.dissipated_sliding, b.books.dissipated_sliding, scale));
        BOOST_TEST(same(a.books.work_by_cell, b.books.work_by_cell, std::abs(a.books.work_by_cell)));
        BOOST_TEST((a.books.work_by_cell != 0.0) == sheared);
    }
}

}  // namespace

using Dims = boost::mpl::list<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;

BOOST_AUTO_TEST_CASE_TEMPLATE(packet_loop_is_the_scalar_loop, D, Dims) {
    compare<D::value, false, false, double>(1.0, 1.0);
}

BOOST_AUTO_TEST_CASE_TEMPLATE(packet_loop_books_and_ghosts_as_the_scalar_loop, D, Dims) {
    compare<D::value, true, false, double>(1.0, 1.0);
    compare<D::value, true, true, double>(1.0, 0.8);  // the last fifth are ghosts: their pairs count half
}

BOOST_AUTO_TEST_CASE_TEMPLATE(packet_loop_spills_as_the_scalar_loop, D, Dims) {
    compare<D::value, true, false, double>(0.5, 1.0);  // the second half belongs to a later thread's share
}

BOOST_AUTO_TEST_CASE_TEMPLATE(packet_loop_in_a_sheared_cell_is_the_scalar_loop, D, Dims) {
    compare<D::value, false, false, double>(1.0, 1.0, true);
    compare<D::value, true, false, double>(1.0, 1.0, true);  // the cell's work through the contacts across its boundary
}

BOOST_AUTO_TEST_CASE_TEMPLATE(packet_loop_in_a_float_scene_is_the_scalar_loop, D, Dims) {
    compare<D::value, true, false, float>(1.0, 1.0);
}

// A spring record's last word as the packets read it: trial (a float), then the flags sliding,
// touching and fresh a byte each; and records come back from lanes as they went in.
BOOST_AUTO_TEST_CASE_TEMPLATE(spring_records_go_into_lanes_and_back_whole, D, Dims) {
    constexpr int dim = D::value;
    Spring<dim> records[8], copies[8];
    Spring<dim>*at[8], *to[8];
    for (int l = 0; l < 8; ++l) {
        Spring<dim>& h = records[l];
        if constexpr (dim == 2) {
            h.spring = 10.0 * l;
            h.ahead = -10.0 * l;
        } else
            for (int a = 0; a < 3; ++a) {
                h.spring[a] = 10 * l + a;
                h.ahead[a] = -10.0 * l - a;
            }
        h.trial = 0.25f * float(l);
        h.sliding = l % 2 == 1;
        h.touching = l % 3 != 0;
        h.fresh = l % 4 == 2;
        at[l] = &h;
        to[l] = &copies[l];
    }
    const mm::packets::Springs<dim> s = mm::packets::load_springs(at);
    alignas(64) double spring[8], ahead[8];
    alignas(64) std::uint64_t word[8];
    if constexpr (dim == 2) {
        _mm512_store_pd(spring, s.spring);
        _mm512_store_pd(ahead, s.ahead);
    } else {
        _mm512_store_pd(spring, s.spring.y);
        _mm512_store_pd(ahead, s.ahead.z);
    }
    _mm512_store_si512(word, s.word);
    for (int l = 0; l < 8; ++l) {
        if constexpr (dim == 2) {
            BOOST_TEST(spring[l] == records[l].spring);
            BOOST_TEST(ahead[l] == records[l].ahead);
        } else {
            BOOST_TEST(spring[l] == records[l].spring[1]);
            BOOST_TEST(ahead[l] == records[l].ahead[2]);
        }
        float trial;
        const std::uint32_t low = std::uint32_t(word[l]);
        std::memcpy(&trial, &low, sizeof trial);
        BOOST_TEST(trial == records[l].trial);
        BOOST_TEST(bool(word[l] >> mm::packets::sliding_bit & 0xff) == records[l].sliding);
        BOOST_TEST(bool(word[l] >> mm::packets::touching_bit & 0xff) == records[l].touching);
        BOOST_TEST(bool(word[l] >> mm::packets::fresh_bit & 0xff) == records[l].fresh);
    }
    mm::packets::store_springs(s, to, 0xFF);
    for (int l = 0; l < 8; ++l) {
        BOOST_TEST(copies[l].spring == records[l].spring);
        BOOST_TEST(copies[l].ahead == records[l].ahead);
        BOOST_TEST(copies[l].trial == records[l].trial);
        BOOST_TEST((copies[l].sliding == records[l].sliding && copies[l].touching == records[l].touching &&
                    copies[l].fresh == records[l].fresh));
    }
}
#else
// Without AVX-512 every scene runs the scalar loop.
BOOST_AUTO_TEST_CASE(without_avx512_the_scalar_loop_runs) {
    BOOST_TEST(!(mm::detail::packet_pair_loop_applies<2, true, mm::FrictionalLinear>));
    BOOST_TEST(!(mm::detail::packet_pair_loop_applies<3, true, mm::FrictionalLinear>));
}
#endif

BOOST_AUTO_TEST_SUITE_END()
