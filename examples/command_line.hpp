#pragma once
// The command line of every program here, parsed as the README promises: --help prints the usage
// and exits 0; an unknown option, a bad value or a missing argument prints CLI11's message and
// exits 1 (CLI11's own codes, 105-114, say which kind of parse error, which no caller needs).
#include <CLI/CLI.hpp>

#include <cmath>
#include <sstream>
#include <string>

#define MICROMACRO_PARSE_COMMAND_LINE(app, argc, argv)      \
    try {                                                 \
        (app).parse((argc), (argv));                      \
    } catch (const CLI::ParseError& parse_error) {        \
        return (app).exit(parse_error) == 0 ? 0 : 1;      \
    }

namespace micromacro::cli {

/// A check of a real number: it must parse, be finite and pass `rule`; else CLI11's error names
/// the option, the value and the rule ("--skin: nan is not a finite number above 0"). CLI11's
/// PositiveNumber and NonNegativeNumber state their limit as a range up to 1.8e308, and its
/// Range lets nan through.
template <class Rule>
CLI::Validator finite_number(const std::string& what, Rule rule) {
    return CLI::Validator(
        [what, rule](std::string& text) -> std::string {
            double x = 0.0;
            if (!CLI::detail::lexical_cast(text, x)) return "'" + text + "' is not a number; give " + what;
            if (!std::isfinite(x) || !rule(x)) return text + " is not " + what;
            return {};
        },
        "NUMBER");
}

/// A finite number above 0.
inline CLI::Validator positive() {
    return finite_number("a finite number above 0", [](double x) { return x > 0.0; });
}
/// A finite number of 0 or more.
inline CLI::Validator non_negative() {
    return finite_number("a finite number of 0 or more", [](double x) { return x >= 0.0; });
}
/// A finite number in [lo, hi].
inline CLI::Validator between(double lo, double hi) {
    std::ostringstream what;
    what << "a finite number from " << lo << " to " << hi;
    return finite_number(what.str(), [lo, hi](double x) { return x >= lo && x <= hi; });
}

}  // namespace micromacro::cli
