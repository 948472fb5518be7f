#pragma once
// The command line of every program here, parsed as the README promises: --help prints the usage
// and exits 0; an unknown option, a bad, empty or repeated value or a missing argument prints a
// message naming the program and exits 1 (CLI11's own codes, 105-114, say which kind of parse
// error, which no caller needs).
#include <CLI/CLI.hpp>

#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>

#include <micromacro/core/error.hpp>

#define MICROMACRO_PARSE_COMMAND_LINE(app, argc, argv)                      \
    try {                                                                 \
        micromacro::cli::prepare_parse((app), (argc), (argv));            \
        (app).parse((argc), (argv));                                      \
    } catch (const CLI::ParseError& parse_error) {                        \
        return (app).exit(parse_error) == 0 ? 0 : 1;                      \
    }

namespace micromacro::cli {

/// A parse error as every program states it: its name first, then what was wrong and the fix, then
/// where to read more. CLI11's "--preset: At Most 1 required but received 2" names no program and
/// no fix, so that one is said again in words.
inline std::string failure_message(const CLI::App* app, const CLI::Error& e) {
    std::string what = e.what();
    const std::string repeated = ": At Most 1 required but received ";
    if (const auto at = what.find(repeated); at != std::string::npos)
        what = what.substr(0, at) + " was given " + what.substr(at + repeated.size()) +
               " times; give it once (a later one does not replace an earlier one)";
    return app->get_name() + ": " + what + "\nRun " + app->get_name() + " --help for every option, its unit and its limits.\n";
}

/// An argument left empty (`--mu ''`, `--mu=`): CLI11 would read an empty number as 0, so an empty
/// value is refused as a missing one, for every option of every program.
inline void refuse_empty_values(int argc, const char* const* argv) {
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        if (arg == "--") return;  // what follows is positional, as the user wrote it
        if (arg.empty()) {
            const std::string_view before = i > 1 ? argv[i - 1] : "";
            if (before.size() > 1 && before[0] == '-')
                throw CLI::ValidationError(std::string(before), "the value is empty; give a value (an empty one is not read as 0)");
            throw CLI::ValidationError("argument " + std::to_string(i) + " is empty; give a value or leave it out");
        }
        if (arg.size() > 3 && arg.substr(0, 2) == "--" && arg.back() == '=')
            throw CLI::ValidationError(std::string(arg.substr(0, arg.size() - 1)),
                                       "the value after '=' is empty; give a value (an empty one is not read as 0)");
    }
}

/// What MICROMACRO_PARSE_COMMAND_LINE does before CLI11 parses: the program named as typed
/// (without its directory) in the usage and the messages, the messages above, empty values refused.
inline void prepare_parse(CLI::App& app, int argc, const char* const* argv) {
    if (app.get_name().empty() && argc > 0) {
        const std::string_view path = argv[0];
        app.name(std::string(path.substr(path.find_last_of('/') == std::string_view::npos ? 0 : path.find_last_of('/') + 1)));
    }
    app.failure_message(failure_message);
    refuse_empty_values(argc, argv);
}

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

/// The value of option `o` as a whole number from 0 to T's largest, as typed: "-5" or "1e19" is
/// refused by name and value, not wrapped or rounded.
template <class T>
T whole_number(const CLI::Option& o) {
    const std::string text = o.as<std::string>();
    unsigned long long v = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (error != std::errc() || end != text.data() + text.size() || v > std::numeric_limits<T>::max())
        throw_input_error(o.get_name(), " '", text, "' is not a whole number from 0 to ", std::numeric_limits<T>::max());
    return static_cast<T>(v);
}

}  // namespace micromacro::cli
