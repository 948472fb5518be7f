// The serial engine run over MPI ranks (mpi::DistributedRun) under mpirun with 1-4 ranks: 200
// steps of a dense frictional periodic packing, each rank stepping its own particles with the
// ghosts of its halo refreshed after every particle pass, give every particle the serial run's
// position, velocity, angular velocity, force and torque to round-off (the forces on a particle
// are summed in another order on a rank than in the serial run). In 2D and 3D. Contacts press,
// turn and slide: the tangential springs carry the history the comparison checks.
#define BOOST_TEST_MODULE mpi_distributed_run
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include <micromacro/mpi/distributed_run.hpp>

#include "support/scenes.hpp"

namespace mm = micromacro;
using mmtest::Dims;

namespace {
struct MpiSession {
    MpiSession() { MPI_Init(nullptr, nullptr); }
    ~MpiSession() { MPI_Finalize(); }
};
}  // namespace
BOOST_TEST_GLOBAL_FIXTURE(MpiSession);

namespace {
// A jittered lattice of particles with radii 0.995-1.005 mm, spaced 1.99 mm in a periodic box,
// so that neighbours overlap by up to about 1.5% of a radius; random velocities of 0.05 m/s
// and spins of 10 rad/s. The same on every rank. The skin of 0.5 mm keeps the 200 steps within
// one distribution of the particles (DistributedRun does not redistribute yet).
template <int dim>
auto lattice(int per_side) {
    const double spacing = 1.99e-3, L = per_side * spacing;
    const mm::FrictionalLinear law{mm::LinearSpringDashpot(mmtest::k, mmtest::gamma0), mm::CundallStrack(0.2 * mmtest::k, 0.02, 0.5)};
    mm::BasicSimulation<dim, double, mm::FrictionalLinear> sim(law, mmtest::periodic_box<dim>(L));
    std::mt19937_64 rng(23);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    std::normal_distribution<double> N(0.0, 1.0);
    const int n = dim == 2 ? per_side * per_side : per_side * per_side * per_side;
    for (int k = 0; k < n; ++k) {
        mm::Vec<dim> x;
        int rest = k;
        for (int a = 0; a < dim; ++a) {
            x[a] = (rest % per_side + 0.5) * spacing + 0.005e-3 * U(rng);
            rest /= per_side;
        }
        const double r = 1e-3 + 0.005e-3 * U(rng);
        const std::size_t i = sim.particles().add(x, r, mm::sphere_mass(mmtest::rho, r));
        for (int a = 0; a < dim; ++a) sim.particles().velocity()[i][a] = 0.05 * N(rng);
        auto& w = sim.particles().template get<mm::field::AngularVelocity>()[i];
        if constexpr (dim == 2) w = 10.0 * N(rng);
        else w = mm::Vec<3>(10.0 * N(rng), 10.0 * N(rng), 10.0 * N(rng));
    }
    sim.set_time_step(mm::contact_duration(mmtest::k, mmtest::gamma0, mm::sphere_mass(mmtest::rho, 0.995e-3) / 2) / 50);
    sim.set_skin(0.5e-3);
    sim.set_auto_sort(false);
    return sim;
}

template <int dim>
double largest(const std::vector<mm::Vec<dim>>& v) {
    double m = 0.0;
    for (const auto& x : v) m = std::max(m, x.norm());
    return m;
}
template <int dim, class A>
double norm(const A& w) {
    return std::sqrt(mm::DimTraits<dim>::squared_norm(w));
}
}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(two_hundred_steps_give_the_serial_state, D, Dims) {
    constexpr int dim = D::value;
    auto serial = lattice<dim>(dim == 2 ? 18 : 8);
    mm::mpi::DistributedRun distributed(MPI_COMM_WORLD, serial);  // from the state before the steps
    serial.prepare();
    const auto& s = serial.particles();
    const auto& p = distributed.local().particles();
    const auto by_id = s.index_by_id();
    const int rank = distributed.comm().rank();
    std::size_t sliding = 0, contacts = 0;  // at the three comparisons
    // Every owned particle against the serial one, relative to the serial run's largest value
    // (positions: to a radius), after `steps` steps.
    auto compare = [&](int steps) {
        const auto& w = s.template get<mm::field::AngularVelocity>();
        const auto& t = s.template get<mm::field::Torque>();
        const auto& local_w = p.template get<mm::field::AngularVelocity>();
        const auto& local_t = p.template get<mm::field::Torque>();
        double w_scale = 0.0, t_scale = 0.0;
        for (std::size_t i = 0; i < s.size(); ++i) w_scale = std::max(w_scale, norm<dim>(w[i])), t_scale = std::max(t_scale, norm<dim>(t[i]));
        const double x_scale = 1e-3, v_scale = largest<dim>(s.velocity()), f_scale = largest<dim>(s.force());
        BOOST_TEST_REQUIRE((v_scale > 0 && f_scale > 0 && w_scale > 0 && t_scale > 0));
        double dx = 0, dv = 0, dw = 0, df = 0, dt = 0;
        for (std::size_t i = 0; i < distributed.owned(); ++i) {
            const std::size_t k = by_id[distributed.global_id(i)];
            dx = std::max(dx, serial.domain().separation(p.position()[i], s.position()[k]).norm() / x_scale);
            dv = std::max(dv, (p.velocity()[i] - s.velocity()[k]).norm() / v_scale);
            df = std::max(df, (p.force()[i] - s.force()[k]).norm() / f_scale);
            dw = std::max(dw, norm<dim>(decltype(local_w[i])(local_w[i] - w[k])) / w_scale);
            dt = std::max(dt, norm<dim>(decltype(local_t[i])(local_t[i] - t[k])) / t_scale);
        }
        BOOST_TEST_MESSAGE(dim << "D, rank " << rank << ", after " << steps << " steps, relative differences: position " << dx
                               << ", velocity " << dv << ", angular velocity " << dw << ", force " << df << ", torque " << dt);
        BOOST_TEST(dx < 1e-11, "rank " << rank << ", step " << steps << ": positions differ by " << dx << " of a radius");
        BOOST_TEST(dv < 1e-11, "rank " << rank << ", step " << steps << ": velocities by " << dv);
        BOOST_TEST(dw < 1e-11, "rank " << rank << ", step " << steps << ": angular velocities by " << dw);
        BOOST_TEST(df < 1e-11, "rank " << rank << ", step " << steps << ": forces by " << df);
        BOOST_TEST(dt < 1e-11, "rank " << rank << ", step " << steps << ": torques by " << dt);
        serial.for_each_contact([&](const auto& c) {
            ++contacts;
            sliding += c.sliding;
        });
    };
    compare(0);
    for (int steps : {100, 200}) {
        serial.run(100);
        distributed.run(100);
        compare(steps);
    }
    // Every particle is some rank's.
    unsigned long long mine = distributed.owned(), all = 0;
    MPI_Allreduce(&mine, &all, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    BOOST_TEST(all == s.size());
    // The springs were loaded and some contacts slid: the comparison saw tangential history.
    BOOST_TEST(contacts > 3 * s.size());
    BOOST_TEST(sliding > 0u);
}
