// The biaxial test's own box over MPI ranks under mpirun with 1-4 ranks: the quick preset's
// preparation (examples/biaxial/biaxial.hpp, with fewer particles), then the loading's walls,
// law and affine damping, continued from the prepared state (its forces and springs) for 200
// steps over the ranks and serially. Every particle and wall ends where the serial run's does,
// to round-off, and the forces within a small part of what the positions' last bits allow; one
// rank gives the serial bits, and so do 2-4 without fused multiply-adds. The walls cross every
// rank: the strain-controlled one moves in, the stress-controlled ones follow the packing. In 2D
// and 3D.
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>

#include <micromacro/mpi/distributed_run.hpp>

#include "biaxial/biaxial.hpp"
#include "support/mpi_runtime.hpp"
#include "support/scenes.hpp"

BOOST_AUTO_TEST_SUITE(mpi_biaxial_box)  // the file's cases, run as the CTest test of this file's name

namespace mm = micromacro;
using mmtest::Dims;

BOOST_AUTO_TEST_CASE_TEMPLATE(the_loading_gives_the_serial_state, D, Dims) {
    constexpr int dim = D::value;
    biaxial::Config c;
    c.dim = dim;
    biaxial::apply_preset(c, "quick");
    c.particles = dim == 2 ? 200 : 250;
    biaxial::Experiment<dim> experiment(c);
    experiment.build();
    experiment.prepare();
    experiment.start_loading();
    auto& serial = experiment.simulation();
    serial.set_track_energy(false);  // as the distributed run (see tests/mpi/distributed_run.cpp)
    serial.prepare();                // the loading's law evaluated, as the serial run's next step would first
    using Run = mm::mpi::DistributedRun<std::remove_reference_t<decltype(serial)>>;
    Run run(MPI_COMM_WORLD, serial, Run::Start::resume);
    const double top = serial.walls()[2 * dim - 1].offset;
    serial.run(200);
    run.run(200);
    // The packing is nearly at rest: a particle's net force is a residual of contact forces a
    // hundred times larger, whose overlaps are known only to the positions' last bit. So the
    // forces are compared with what one unit in the last place of a position changes in a
    // contact force (k times position_resolution()), the velocities with that force over the
    // steps, the positions with a radius.
    const auto& s = serial.particles();
    const auto& p = run.local().particles();
    const auto index = s.index_by_id();
    const double last_bit_force = c.k * serial.position_resolution(), m_min = mm::sphere_mass(c.density, c.radius_min);
    double dx = 0.0, dv = 0.0, df = 0.0;
    for (std::size_t i = 0; i < run.owned(); ++i) {
        const std::size_t k = index[run.global_id(i)];
        dx = std::max(dx, (p.position()[i] - s.position()[k]).norm() / c.radius_min);
        df = std::max(df, (p.force()[i] - s.force()[k]).norm() / last_bit_force);
        dv = std::max(dv, (p.velocity()[i] - s.velocity()[k]).norm() / (200 * last_bit_force * serial.time_step() / m_min));
    }
    double walls = 0.0, force = 0.0;
    for (std::size_t k = 0; k < serial.walls().size(); ++k) force = std::max(force, serial.walls()[k].force.norm());
    for (std::size_t k = 0; k < serial.walls().size(); ++k)
        walls = std::max({walls, std::abs(run.local().walls()[k].offset - serial.walls()[k].offset) / c.radius_min,
                          (run.local().walls()[k].force - serial.walls()[k].force).norm() / force});
    BOOST_TEST_MESSAGE(dim << "D, " << mmtest::world_size() << " ranks (" << run.owned() << " particles here), " << run.redistributions()
                           << " redistributions: positions within " << dx << " of a radius, forces within " << df
                           << " and velocities within " << dv << " of a position's last bit's, walls within " << walls);
    if (mmtest::world_size() == 1) BOOST_TEST((dx == 0.0 && df == 0.0 && dv == 0.0 && walls == 0.0), "one rank gives the serial bits");
    // Each rank sums a particle's contacts in the serial order (DistributedRun::serial_pair_order)
    // and the walls' forces too (set_serial_wall_sums): without fused multiply-adds any number of
    // ranks gives the serial bits. With them a rank's pair loop may fuse other products than the
    // serial one (one last bit of a contact's force, 1 here; 2-4 ranks gave the serial bits there
    // too), so only round-off is promised. A contact lost or doubled would be 1e5 last bits'
    // forces and more.
    BOOST_TEST(dx < 2e-11);
    BOOST_TEST(df < 100.0);
    BOOST_TEST(dv < 100.0);
    BOOST_TEST(walls < 2e-11);
#ifndef MICROMACRO_FP_CONTRACT
    BOOST_TEST((dx == 0.0 && df == 0.0 && dv == 0.0 && walls == 0.0), "the serial bits");
#endif
    BOOST_TEST(std::abs(serial.walls()[2 * dim - 1].offset - top) > 0.0, "the loading moved the top wall");
}

BOOST_AUTO_TEST_SUITE_END()
