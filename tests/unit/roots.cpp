// core/roots.hpp gives each number's square root and its reciprocal exactly as the scalar
// std::sqrt and 1 / std::sqrt do (both correctly rounded), at every count: the AVX-512 path's
// whole packets and the Eigen path agree with the plain arithmetic bit for bit. Built twice
// (tests/CMakeLists.txt): as the build is, and without AVX-512.
#include <boost/test/unit_test.hpp>

#include <array>
#include <cmath>
#include <limits>

#include <micromacro/core/roots.hpp>

BOOST_AUTO_TEST_SUITE(unit_roots)  // the file's cases, run as the CTest test of this file's name

BOOST_AUTO_TEST_CASE(roots_and_reciprocals_are_the_correctly_rounded_ones_at_every_count) {
    std::array<double, 32> square{};
    for (std::size_t k = 0; k < square.size(); ++k) square[k] = std::ldexp(1.0 + 0.37 * k + 1e-3 * k * k, -20 + int(k % 7));
    square[3] = 2.0;                                  // sqrt(2): rounded, not exact
    square[11] = std::numeric_limits<double>::min();  // the smallest normal number
    square[17] = std::numeric_limits<double>::denorm_min();
    for (std::size_t count = 0; count <= square.size(); ++count) {
        std::array<double, 32> root{}, inverse{};
        micromacro::detail::roots_and_reciprocals(square, root, inverse, count);
        for (std::size_t k = 0; k < count; ++k) {
            const double expected = std::sqrt(square[k]);
            BOOST_TEST(root[k] == expected, "count " << count << ", root " << k);
            BOOST_TEST(inverse[k] == 1.0 / expected, "count " << count << ", inverse " << k);
        }
    }
}

BOOST_AUTO_TEST_SUITE_END()
