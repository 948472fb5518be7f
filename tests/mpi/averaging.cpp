// The micro-macro averages of a scene run over MPI ranks (mpi::average) under mpirun with 1-4
// ranks against the serial averages of the same scene: fabric, the stress's normal, tangential
// and kinetic parts, the normal and tangential stiffness, coordination, volume fraction and
// the counts of particles, contacts and rattlers, over the whole periodic box and over a box
// across the ranks' boundaries, with both selection rules and with and without rattlers, at the
// start and after 200 steps (the particles handed to new ranks on the way). In 2D and 3D. A
// tenth of the particles are shrunk out of contact, and the rattler peel cascades across ranks:
// in 3D it takes about a tenth more at the start, in 2D every particle (on a square lattice a
// particle between two holes is left with two contacts, and so on through the whole box).
#define BOOST_TEST_MODULE mpi_averaging
#include <boost/test/unit_test.hpp>

#include <micromacro/mpi/averaging.hpp>

#include "support/mpi_lattice.hpp"
#include "support/mpi_runtime.hpp"

namespace mm = micromacro;
using mmtest::Dims;

using mmtest::MpiRuntime;
BOOST_TEST_GLOBAL_FIXTURE(MpiRuntime);

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
        for (const auto* region : {&whole_box, &middle})
            for (auto rule : {mm::SelectionRule::contact_point, mm::SelectionRule::particle_centre})
                for (bool exclude : {false, true}) {
                    mm::AveragingOptions opt;
                    opt.rule = rule;
                    opt.exclude_rattlers = exclude;
                    opt.kinetic_stress = true;
                    const auto whole = mm::average(snapshot, *region, opt);
                    const auto split = mm::mpi::average(distributed, *region, opt);
                    std::ostringstream what;
                    what << dim << "D, step " << steps << (region == &whole_box ? ", whole box" : ", middle box")
                         << (rule == mm::SelectionRule::contact_point ? ", contact points" : ", particle centres")
                         << (exclude ? ", rattlers left out" : "");
                    compare(split, whole, what.str());
                    BOOST_TEST_MESSAGE(what.str() << ": " << whole.particles << " particles, " << whole.rattlers << " rattlers, "
                                                  << whole.contacts << " contacts");
                    if (steps == 0 && region == &whole_box) rattlers_at_start = whole.rattlers;
                }
    }
    const std::size_t n = serial.particles().size();
    if constexpr (dim == 2) BOOST_TEST(rattlers_at_start == n);
    else BOOST_TEST((rattlers_at_start > n / 10 && rattlers_at_start < n / 5), rattlers_at_start << " rattlers of " << n);
    BOOST_TEST(distributed.redistributions() > 0u);
}
