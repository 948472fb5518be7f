// The build's code generation keeps constants as written. GCC 12.2 (Debian 12) with AVX-512
// enabled (-march=native on a CPU that has it) may store an initialised array whose first half
// repeats one value and whose second half is zero as that value broadcast to all 64 bytes: a
// silent wrong constant anywhere in the library's programs. CMakeLists.txt caps GCC's vectors at
// 256 bits (-mprefer-vector-width=256), which avoids it; these are the patterns that showed it.
#include <boost/test/unit_test.hpp>

#include <array>
#include <vector>

#include <micromacro/micromacro.hpp>  // the intrinsics headers, as every program of the project includes them

BOOST_AUTO_TEST_SUITE(unit_code_generation)  // the file's cases, run as the CTest test of this file's name

namespace {
template <class T>
__attribute__((noinline)) std::vector<T> kept(const std::vector<T>& v) {
    return v;
}
}  // namespace

BOOST_AUTO_TEST_CASE(half_broadcast_constants_are_stored_as_written) {
    const std::vector<double> doubles = kept<double>({100, 100, 100, 100, 0, 0, 0, 0});
    const std::vector<float> floats = kept<float>({3, 3, 3, 3, 3, 3, 3, 3, 0, 0, 0, 0, 0, 0, 0, 0});
    const std::vector<long> longs = kept<long>({5, 5, 5, 5, 0, 0, 0, 0});
    for (std::size_t k = 0; k < 8; ++k) {
        BOOST_TEST(doubles[k] == (k < 4 ? 100.0 : 0.0), "double " << k);
        BOOST_TEST(longs[k] == (k < 4 ? 5 : 0), "long " << k);
    }
    for (std::size_t k = 0; k < 16; ++k) BOOST_TEST(floats[k] == (k < 8 ? 3.0f : 0.0f), "float " << k);
}

BOOST_AUTO_TEST_SUITE_END()
