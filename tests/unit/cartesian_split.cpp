// The MPI layer's split of a box into slabs (no MPI needed): every point has exactly one owner,
// also on a slab boundary and whatever the rounding of the boundaries; points outside an open
// box go to the end slabs; a halo wider than a slab is refused with the numbers and the fix; a
// rank's search window unwraps a periodic axis of several slabs where its particles span less
// than a period less a halo width.
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <random>
#include <string>

#include <micromacro/mpi/cartesian_split.hpp>

BOOST_AUTO_TEST_SUITE(unit_cartesian_split)  // the file's cases, run as the CTest test of this file's name

namespace mm = micromacro;

BOOST_AUTO_TEST_CASE(every_point_has_one_owner) {
    // Three slabs of a box whose boundaries 0.1 + 0.7 c / 3 do not round exactly.
    const mm::Domain<2> box(mm::Vec<2>(0.1, -0.2), mm::Vec<2>(0.8, 0.5), {true, false});
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> U(-0.3, 0.9);
    std::vector<mm::Vec<2>> points;
    for (int k = 0; k < 2000; ++k) points.push_back(mm::Vec<2>(U(rng), U(rng)));
    const auto probe = mm::mpi::CartesianSplit<2>::of(box, {3, 2}, {0, 0});
    for (int c = 0; c <= 3; ++c)  // on a boundary, and the neighbouring doubles either side of it
        for (double x : {probe.boundary(0, c), std::nextafter(probe.boundary(0, c), -1.0), std::nextafter(probe.boundary(0, c), 2.0)})
            points.push_back(mm::Vec<2>(x, 0.15));
    for (const auto& x : points) {
        int owners = 0;
        for (int cx = 0; cx < 3; ++cx)
            for (int cy = 0; cy < 2; ++cy) {
                const auto split = mm::mpi::CartesianSplit<2>::of(box, {3, 2}, {cx, cy});
                if (split.owns(x)) {
                    ++owners;
                    // Inside the box, the owner's subdomain holds the point as [sub_lo, sub_hi).
                    for (int a = 0; a < 2; ++a)
                        if (x[a] >= box.lo()[a] && x[a] < box.hi()[a])
                            BOOST_TEST((x[a] >= split.sub_lo(a) && x[a] < split.sub_hi(a)), "axis " << a << " at " << x[a]);
                }
            }
        BOOST_TEST(owners == 1, "point " << x.transpose() << " has " << owners << " owners");
    }
    BOOST_TEST(probe.boundary(0, 3) == 0.8);  // the last slab ends at the box's end exactly
}

BOOST_AUTO_TEST_CASE(a_halo_wider_than_a_slab_is_refused) {
    const mm::Domain<3> box(mm::Vec<3>::Zero(), mm::Vec<3>(0.04, 0.01, 0.02), {true, true, false});
    const auto split = mm::mpi::CartesianSplit<3>::of(box, {4, 1, 2}, {1, 0, 1});
    BOOST_CHECK_NO_THROW(split.check_halo(0.009));  // x slabs 0.01 wide; y one periodic slab 0.01; z 0.01
    try {
        split.check_halo(0.011);
        BOOST_FAIL("a halo of 0.011 m across 0.01 m slabs was accepted");
    } catch (const mm::InputError& e) {
        const std::string m = e.what();
        BOOST_TEST(m.find("0.011") != std::string::npos, m);
        BOOST_TEST(m.find("0.01 m slabs along axis 0") != std::string::npos, m);
        BOOST_TEST(m.find("use fewer ranks") != std::string::npos, m);
    }
    BOOST_CHECK_THROW((mm::mpi::CartesianSplit<3>::of(box, {4, 1, 2}, {4, 0, 0})), mm::InputError);  // no slab 4 of 4
}

BOOST_AUTO_TEST_CASE(a_search_window_is_one_period_centred_on_the_slab_where_the_particles_fit) {
    // x: periodic, 4 slabs of 0.01; y: one periodic slab; z: open, 2 slabs.
    const mm::Domain<3> box(mm::Vec<3>::Zero(), mm::Vec<3>(0.04, 0.01, 0.02), {true, true, false});
    const auto split = mm::mpi::CartesianSplit<3>::of(box, {4, 1, 2}, {1, 0, 1});
    // The particles span 0.01 + 2 (0.004 + 0.001) = 0.02 along x, and 0.02 + 0.004 < 0.04.
    const auto w = split.search_window(0.004, 0.001);
    BOOST_TEST(w.unwrap[0]);
    BOOST_TEST(w.origin[0] == 0.01 - 0.5 * (0.04 - 0.01), boost::test_tools::tolerance(1e-15));
    BOOST_TEST(!w.unwrap[1]);  // one slab: the rank's engine wraps it as the serial one does
    BOOST_TEST(!w.unwrap[2]);  // open: binned over the particles' extent anyway
    // 0.01 + 2 (0.0085 + 0.001) + 0.0085 = 0.0375 < 0.04 still; 0.0095 gives 0.0405.
    BOOST_TEST(split.search_window(0.0085, 0.001).unwrap[0]);
    BOOST_TEST(!split.search_window(0.0095, 0.001).unwrap[0]);
    // Two slabs of a periodic axis: each rank's particles reach round to the other side sooner.
    const auto two = mm::mpi::CartesianSplit<3>::of(box, {2, 1, 1}, {0, 0, 0});
    BOOST_TEST(two.search_window(0.006, 0.0005).unwrap[0]);    // 0.02 + 0.013 + 0.006 = 0.039
    BOOST_TEST(!two.search_window(0.0065, 0.0005).unwrap[0]);  // 0.02 + 0.014 + 0.0065 = 0.0405
}

// Balanced boundaries (mpi/balance.hpp): each cut where an equal share of a histogram lies below
// it, interpolated within its bin; each kept a halo width inside its present neighbours, so that a
// slab stays a halo wide and a particle moving less than a halo goes at most one slab on; and
// ownership by the cuts as by equal slabs, one owner per point.
BOOST_AUTO_TEST_CASE(balanced_cuts_give_each_slab_an_equal_share) {
    const mm::Domain<2> box(mm::Vec<2>(0.0, 0.0), mm::Vec<2>(1.0, 0.1), {true, false});
    auto split = mm::mpi::CartesianSplit<2>::of(box, {4, 1}, {0, 0});
    // Particles evenly over [0, 0.5) only: 8 bins of 0.125, the first four of 100 each.
    const std::vector<double> counts{100, 100, 100, 100, 0, 0, 0, 0};
    // Without a halo: 0.125 and 0.25, and 0.5 for the third, which may not pass the present
    // boundary below it (0.5, of the equal slabs).
    const std::vector<double> free = split.balanced_cuts(0, counts, 0.0);
    BOOST_TEST_REQUIRE(free.size() == 3u);
    BOOST_TEST(free[0] == 0.125, boost::test_tools::tolerance(1e-15));
    BOOST_TEST(free[1] == 0.25, boost::test_tools::tolerance(1e-15));
    BOOST_TEST(free[2] == 0.5, boost::test_tools::tolerance(1e-15));
    // Within a bin: 150 of 400 below 0.125 * (1 + 50/100).
    BOOST_TEST(split.balanced_cuts(0, {100, 100, 100, 100}, 0.0)[0] == 0.25, boost::test_tools::tolerance(1e-15));
    // A halo of 0.05 from the present boundaries 0, 0.25, 0.5, 0.75, 1: cut 1 at least 0.05
    // above 0 and cut 2 at least 0.05 above cut 1 and 0.25, below 0.75 - 0.05.
    const std::vector<double> held = split.balanced_cuts(0, counts, 0.05);
    BOOST_TEST(held[0] == 0.125, boost::test_tools::tolerance(1e-15));
    BOOST_TEST(held[1] == 0.3, boost::test_tools::tolerance(1e-15));   // 0.25 + 0.05
    BOOST_TEST(held[2] == 0.55, boost::test_tools::tolerance(1e-15));  // 0.5 + 0.05
    split.cuts[0] = held;
    BOOST_TEST(split.boundary(0, 2) == 0.3, boost::test_tools::tolerance(1e-15));
    BOOST_CHECK_NO_THROW(split.check_halo(0.12));
    BOOST_CHECK_THROW(split.check_halo(0.13), mm::InputError);  // the narrowest slab now [0, 0.125)
    // A second pass from there comes closer: every cut may move to a halo from its neighbours.
    split.cuts[0] = split.balanced_cuts(0, counts, 0.05);
    BOOST_TEST(split.cuts[0][1] == 0.25, boost::test_tools::tolerance(1e-15));
    BOOST_TEST(split.cuts[0][2] == 0.375, boost::test_tools::tolerance(1e-15));
    // One owner per point, the owner's subdomain holding it.
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    for (int k = 0; k < 1000; ++k) {
        const mm::Vec<2> x(U(rng), 0.05);
        int owners = 0;
        for (int c = 0; c < 4; ++c) {
            auto s = mm::mpi::CartesianSplit<2>::of(box, {4, 1}, {c, 0});
            s.cuts = split.cuts;
            if (!s.owns(x)) continue;
            ++owners;
            BOOST_TEST((x[0] >= s.sub_lo(0) && x[0] < s.sub_hi(0)));
        }
        BOOST_TEST(owners == 1);
    }
    // Slabs narrower than the halo leave a cut no room between its bounds: refused as by
    // check_halo, naming the equal slabs (0.25 m) before any cut moves.
    const auto equal = mm::mpi::CartesianSplit<2>::of(box, {4, 1}, {0, 0});
    try {
        (void)equal.balanced_cuts(0, counts, 0.3);
        BOOST_FAIL("balanced cuts with a halo of 0.3 m across 0.25 m slabs were given");
    } catch (const mm::InputError& e) {
        const std::string m = e.what();
        BOOST_TEST(m.find("0.25 m slabs along axis 0") != std::string::npos, m);
    }
}

BOOST_AUTO_TEST_SUITE_END()
