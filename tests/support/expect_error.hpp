#pragma once
// expect_error(f, {fragments}): passes if f throws E whose message contains every fragment.
// Include after <boost/test/unit_test.hpp>.
#include <exception>
#include <initializer_list>
#include <string>

#include <micromacro/core/error.hpp>

namespace mmtest {

template <class E = micromacro::InputError, class F>
void expect_error(F&& f, std::initializer_list<std::string> fragments) {
    try {
        f();
    } catch (const E& e) {
        const std::string what = e.what();
        for (const auto& fragment : fragments)
            BOOST_TEST(what.find(fragment) != std::string::npos, "message '" << what << "' lacks '" << fragment << "'");
        return;
    } catch (const std::exception& e) {
        BOOST_ERROR("wrong exception type: " << e.what());
        return;
    }
    BOOST_ERROR("no exception");
}

}  // namespace mmtest
