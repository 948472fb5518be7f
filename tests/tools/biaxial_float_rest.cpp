// Why a biaxial packing stored in float does not come to rest, and what the preparation says
// then. A particle whose step moves it by less than half the position resolution R stays where it
// is while its net force speeds it up, so in float the particles move at about R / (2 dt) or not
// at all: the rest the preparation asks for (kinetic energy below 1e-6 of the elastic) needs rms
// speeds far below that floor. The same packing in double, at the same time, is far slower than
// the float floor; the float one stays at a fraction of it and is told to use double precision.
#define BOOST_TEST_MODULE tools_biaxial_float_rest
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <string>

#include "biaxial/biaxial.hpp"
#include "support/scenes.hpp"

namespace mm = micromacro;

namespace {
template <int dim>
biaxial::Config small_config(double max_time) {
    biaxial::Config c;
    c.dim = dim;
    biaxial::apply_preset(c, "quick");
    c.particles = 100;
    c.dt_fraction = 100;
    c.max_prepare_time = max_time;
    return c;
}

struct Outcome {
    std::string message;  ///< empty if the preparation came to rest
    double rms_speed, floor_speed;
};

template <int dim, class Real>
Outcome prepare(const biaxial::Config& c) {
    biaxial::Experiment<dim, mm::VelocityVerlet, Real> e(c);
    e.build();
    Outcome o;
    try {
        e.prepare();
    } catch (const mm::InputError& error) {
        o.message = error.what();
    }
    const auto& sim = e.simulation();
    double mass = 0.0;
    for (const auto m : sim.particles().mass()) mass += double(m);
    o.rms_speed = std::sqrt(2.0 * sim.energy().kinetic() / mass);
    o.floor_speed = sim.position_resolution() / (2.0 * sim.time_step());
    return o;
}
}  // namespace

// 2D, 100 particles at t_c/100 for 0.06 s: the float packing's rms speed measured 0.48 of its
// floor (6e-3 m/s), the double packing's 8e-5 m/s, at rest.
BOOST_AUTO_TEST_CASE(a_float_packing_keeps_speeds_near_its_resolution_floor) {
    const auto c = small_config<2>(0.06);
    const Outcome in_float = prepare<2, float>(c), in_double = prepare<2, double>(c);
    BOOST_TEST_INFO("float rms " << in_float.rms_speed << " m/s, floor " << in_float.floor_speed << " m/s, double rms "
                                 << in_double.rms_speed << " m/s");
    BOOST_TEST(in_float.rms_speed > 0.2 * in_float.floor_speed);
    BOOST_TEST(in_float.rms_speed < in_float.floor_speed);
    BOOST_TEST(in_double.rms_speed < 0.2 * in_float.floor_speed);
    BOOST_TEST(in_float.message.find("store the particles in double precision") != std::string::npos, in_float.message);
    BOOST_TEST(in_float.message.find("resolve") != std::string::npos, in_float.message);
}

// The advice depends on the storage, not on the dimension: a preparation stopped early says to
// store in double in float and to change the damping or speed in double, in 2D and 3D.
BOOST_AUTO_TEST_CASE_TEMPLATE(a_stopped_preparation_names_the_float_floor, D, mmtest::Dims) {
    constexpr int dim = D::value;
    const auto c = small_config<dim>(0.002);
    const Outcome in_float = prepare<dim, float>(c), in_double = prepare<dim, double>(c);
    BOOST_TEST(in_float.message.find("store the particles in double precision") != std::string::npos, in_float.message);
    BOOST_TEST(in_float.message.find("--gamma-b-prepare") == std::string::npos, in_float.message);
    BOOST_TEST(in_double.message.find("--gamma-b-prepare") != std::string::npos, in_double.message);
    BOOST_TEST(in_double.message.find("double precision") == std::string::npos, in_double.message);
}
