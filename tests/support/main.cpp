// The main of a test program built from several test files (tests/CMakeLists.txt,
// micromacro_test_program): each file is a suite of its own, which CTest runs by name.
#define BOOST_TEST_MODULE micromacro
#include <boost/test/unit_test.hpp>
