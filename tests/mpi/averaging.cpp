// The micro-macro averages of a scene run over MPI ranks (mpi::average) under mpirun with 1-4
// ranks against the serial averages of the same scene: fabric, the stress's normal, tangential
// and kinetic parts, the normal and tangential stiffness, coordination (also without rattlers),
// volume fraction and the counts of particles, contacts and rattlers, over the whole periodic box and over a box
// across the ranks' boundaries, with both selection rules and with and without rattlers, at the
// start and after 200 steps (the particles handed to new ranks on the way). In 2D and 3D. A
// tenth of the particles are shrunk out of contact, and the rattler peel cascades across ranks:
// in 3D it takes about a tenth more at the start, in 2D every particle (on a square lattice a
// particle between two holes is left with two contacts, and so on through the whole box). The
// same in a box of moving walls, whose contacts count.
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <array>
#include <type_traits>

#include <micromacro/mpi/averaging.hpp>

#include "support/mpi_lattice.hpp"
#include "support/mpi_runtime.hpp"

BOOST_AUTO_TEST_SUITE(mpi_averaging)  // the file's cases, run as the CTest test of this file's name

namespace mm = micromacro;
using mmtest::Dims;

namespace {
template <class M>
double relative(const M& a, const M& b) {
    const double scale = b.norm();
    return scale > 0.0 ? (a - b).norm() / scale : (a - b).norm();
}

template <int dim>
void compare(const mm::MicroMacro<dim>& split, const mm::MicroMacro<dim>& whole, const std::string& what) {
    // Every sum adds the same terms in another order: round-off. A contact counted twice or
    // missed, or a wrong rattler, would move a tensor by its share, about 1 / (number of
    // contacts) = 1e-3 here, far above the tolerance.
    const double round_off = 1e-11;
    BOOST_TEST(split.particles == whole.particles, what);
    BOOST_TEST(split.contacts == whole.contacts, what);
    BOOST_TEST(split.rattlers == whole.rattlers, what);
    BOOST_TEST(std::abs(split.coordination - whole.coordination) <= round_off * whole.coordination, what);
    BOOST_TEST(std::abs(split.coordination_without_rattlers - whole.coordination_without_rattlers) <=
                   round_off * whole.coordination_without_rattlers, what);
    BOOST_TEST(std::abs(split.volume_fraction - whole.volume_fraction) <= round_off * whole.volume_fraction, what);
    BOOST_TEST(std::abs(split.sliding_fraction - whole.sliding_fraction) <= round_off, what);
    BOOST_TEST(relative(split.fabric, whole.fabric) < round_off, what << ": fabric");
    BOOST_TEST_MESSAGE(what << ": stress differs by " << relative(split.stress_normal, whole.stress_normal) << " (normal), "
                            << relative(split.stress_tangential, whole.stress_tangential) << " (tangential)");
    BOOST_TEST(relative(split.stress_normal, whole.stress_normal) < round_off, what << ": normal stress");
    BOOST_TEST(relative(split.stress_tangential, whole.stress_tangential) < round_off, what << ": tangential stress");
    BOOST_TEST(relative(split.stress_kinetic, whole.stress_kinetic) < round_off, what << ": kinetic stress");
    BOOST_TEST(relative(split.stiffness_normal.matrix(), whole.stiffness_normal.matrix()) < round_off, what << ": C^n");
    BOOST_TEST(relative(split.stiffness_tangential.matrix(), whole.stiffness_tangential.matrix()) < round_off, what << ": C^t");
}

// compare() for both selection rules, with and without rattlers, over `region`; `seen(whole,
// what)` gets each serial average with its description (`where` followed by the options).
template <int dim, class Run, class Seen>
void compare_every_option(const mm::PackingSnapshot<dim>& snapshot, Run& distributed, const mm::Region<dim>& region,
                          bool kinetic_stress, const std::string& where, Seen&& seen) {
    for (auto rule : {mm::SelectionRule::contact_point, mm::SelectionRule::particle_centre})
        for (bool exclude : {false, true}) {
            mm::AveragingOptions opt;
            opt.rule = rule;
            opt.exclude_rattlers = exclude;
            opt.kinetic_stress = kinetic_stress;
            const auto whole = mm::average(snapshot, region, opt);
            const auto split = mm::mpi::average(distributed, region, opt);
            const std::string what = where + (rule == mm::SelectionRule::contact_point ? ", contact points" : ", particle centres") +
                                     (exclude ? ", rattlers left out" : "");
            compare(split, whole, what);
            seen(whole, what);
        }
}
}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(averages_over_ranks_are_the_serial_averages, D, Dims) {
    constexpr int dim = D::value;
    // Spaced 1.98 mm: every pair of lattice neighbours presses (4 contacts per particle in 2D,
    // 6 in 3D) but those of the holes.
    auto serial = mmtest::lattice<dim>(dim == 2 ? 18 : 8, 10e-6, 0.1, 1.98e-3);
    mm::mpi::DistributedRun distributed(MPI_COMM_WORLD, serial);
    serial.prepare();
    const mm::Domain<dim> box = serial.domain();
    // A box across the middle of the domain, where 2-4 ranks meet, reaching past the periodic end
    // on the first axis.
    mm::Vec<dim> lo, hi;
    for (int a = 0; a < dim; ++a) {
        const double L = box.hi()[a] - box.lo()[a];
        lo[a] = box.lo()[a] + 0.3 * L;
        hi[a] = box.lo()[a] + 0.75 * L;
    }
    const auto whole_box = mm::Region<dim>::box(box.lo(), box.hi());
    const auto middle = mm::Region<dim>::box(lo, hi);
    std::size_t rattlers_at_start = 0;
    for (int steps : {0, 200}) {
        if (steps > 0) {
            serial.run(steps);
            distributed.run(steps);
        }
        const auto snapshot = mm::take_snapshot(serial);
        for (const auto* region : {&whole_box, &middle}) {
            std::ostringstream where;
            where << dim << "D, step " << steps << (region == &whole_box ? ", whole box" : ", middle box");
            compare_every_option(snapshot, distributed, *region, true, where.str(), [&](const auto& whole, const std::string& what) {
                BOOST_TEST_MESSAGE(what << ": " << whole.particles << " particles, " << whole.rattlers << " rattlers, " << whole.contacts
                                        << " contacts");
                if (steps == 0 && region == &whole_box) rattlers_at_start = whole.rattlers;
            });
        }
    }
    const std::size_t n = serial.particles().size();
    if constexpr (dim == 2) BOOST_TEST(rattlers_at_start == n);
    else BOOST_TEST((rattlers_at_start > n / 10 && rattlers_at_start < n / 5), rattlers_at_start << " rattlers of " << n);
    BOOST_TEST(distributed.redistributions() > 0u);
}

// In a box of walls that move (Eq. 17 and 18), with the walls' contacts in the sums: the paper's
// inner box (10% left out next to each wall) and the whole box, after 0 and 200 steps.
BOOST_AUTO_TEST_CASE_TEMPLATE(averages_in_a_box_of_walls_over_ranks_are_the_serial_averages, D, Dims) {
    constexpr int dim = D::value;
    auto serial = mmtest::walled_lattice<dim>(dim == 2 ? 19 : 7, 10e-6, true);
    serial.set_track_energy(false);  // as the distributed run (see tests/mpi/distributed_run.cpp)
    mm::mpi::DistributedRun distributed(MPI_COMM_WORLD, serial);
    serial.prepare();
    std::size_t wall_contacts = 0;
    for (int steps : {0, 200}) {
        if (steps > 0) {
            serial.run(steps);
            distributed.run(steps);
        }
        const auto snapshot = mm::take_snapshot(serial);
        for (double margin : {0.1, 0.0}) {
            std::ostringstream where;
            where << dim << "D walls, step " << steps << ", margin " << margin;
            compare_every_option(snapshot, distributed, mm::Region<dim>::inner(snapshot, margin), false, where.str(),
                                 [](const auto&, const std::string&) {});
        }
        for (const auto& c : snapshot.contacts) wall_contacts += c.wall;
    }
    BOOST_TEST(wall_contacts > 0u);
}

// The coarse-grained fields (Lucy's kernel, two diameters wide, on a grid of 10 points per axis in
// 2D and 5 in 3D, about two diameters apart)
// over the ranks against the serial fields at every grid point, with both rules and with and
// without rattlers, after 100 steps: within 1e-11 of each field's largest value.
BOOST_AUTO_TEST_CASE_TEMPLATE(coarse_grained_fields_over_ranks_are_the_serial_fields, D, Dims) {
    constexpr int dim = D::value;
    auto serial = mmtest::lattice<dim>(dim == 2 ? 18 : 8, 10e-6, 0.1, 1.98e-3);
    mm::mpi::DistributedRun distributed(MPI_COMM_WORLD, serial);
    serial.prepare();
    serial.run(100);
    distributed.run(100);
    std::array<int, dim> points;
    points.fill(dim == 2 ? 10 : 5);
    const auto grid = mm::Grid<dim>::covering(serial.domain().lo(), serial.domain().hi(), points);
    const mm::LucyKernel kernel{4e-3};
    const auto snapshot = mm::take_snapshot(serial);
    for (auto rule : {mm::SelectionRule::contact_point, mm::SelectionRule::particle_centre})
        for (bool exclude : {false, true}) {
            mm::AveragingOptions opt;
            opt.rule = rule;
            opt.exclude_rattlers = exclude;
            const auto whole = mm::coarse_grain(snapshot, grid, kernel, opt);
            const auto split = mm::mpi::coarse_grain(distributed, grid, kernel, opt);
            auto worst = [](const auto& a, const auto& b) {
                double scale = 0, diff = 0;
                for (std::size_t x = 0; x < b.size(); ++x) {
                    if constexpr (std::is_same_v<std::decay_t<decltype(b[x])>, double>) {
                        scale = std::max(scale, std::abs(b[x]));
                        diff = std::max(diff, std::abs(a[x] - b[x]));
                    } else if constexpr (requires { b[x].matrix(); }) {
                        scale = std::max(scale, b[x].matrix().norm());
                        diff = std::max(diff, (a[x].matrix() - b[x].matrix()).norm());
                    } else {
                        scale = std::max(scale, b[x].norm());
                        diff = std::max(diff, (a[x] - b[x]).norm());
                    }
                }
                return scale > 0 ? diff / scale : diff;
            };
            const double largest = std::max({worst(split.volume_fraction, whole.volume_fraction), worst(split.fabric, whole.fabric),
                                             worst(split.stress_normal, whole.stress_normal),
                                             worst(split.stress_tangential, whole.stress_tangential),
                                             worst(split.stiffness_normal, whole.stiffness_normal),
                                             worst(split.stiffness_tangential, whole.stiffness_tangential)});
            BOOST_TEST_MESSAGE(dim << "D coarse-grained, " << (rule == mm::SelectionRule::contact_point ? "contact points" : "particle centres")
                                   << (exclude ? ", rattlers left out" : "") << ": largest difference " << largest);
            BOOST_TEST(largest < 1e-11);
            if (!exclude)  // the fields are not empty
                BOOST_TEST(std::all_of(whole.fabric.begin(), whole.fabric.end(), [](const auto& F) { return F.trace() > 0.0; }));
        }
}

BOOST_AUTO_TEST_SUITE_END()
