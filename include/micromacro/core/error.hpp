#pragma once
// One exception type for every rejected input, so callers can catch it apart from programming
// errors. Messages name the offending value, the limit it broke and what to do instead.
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace micromacro {

class InputError : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

/// Raised when a run becomes numerically invalid (NaN, blow-up) although the input was accepted.
class SimulationError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

namespace detail {
template <class... Parts>
std::string concat(const Parts&... parts) {
    std::ostringstream out;
    out.precision(10);
    (out << ... << parts);
    return out.str();
}
}  // namespace detail

/// Throws an InputError whose message is the parts written one after another (numbers to 10
/// digits): what programs built on the library use to refuse their own options the same way.
template <class... Parts>
[[noreturn]] void throw_input_error(const Parts&... parts) {
    throw InputError(detail::concat(parts...));
}

/// Requires value > 0 and finite; else an InputError naming `what`, the value and the `fix`.
inline void require_positive(double value, const char* what, const char* fix) {
    if (!(value > 0.0) || !std::isfinite(value))
        throw_input_error(what, " = ", value, " is invalid: it must be finite and > 0; ", fix);
}
/// Requires value >= 0 and finite; else an InputError naming `what`, the value and the `fix`.
inline void require_non_negative(double value, const char* what, const char* fix) {
    if (!(value >= 0.0) || !std::isfinite(value))
        throw_input_error(what, " = ", value, " is invalid: it must be finite and >= 0; ", fix);
}

// The library's own code calls them through detail:: as well.
namespace detail {
using micromacro::require_non_negative;
using micromacro::require_positive;
using micromacro::throw_input_error;
}  // namespace detail

}  // namespace micromacro
