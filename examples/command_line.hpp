#pragma once
// The command line of every program here, parsed as the README promises: --help prints the usage
// and exits 0; an unknown option, a bad value or a missing argument prints CLI11's message and
// exits 1 (CLI11's own codes, 105-114, say which kind of parse error, which no caller needs).
#include <CLI/CLI.hpp>

#define MICROMACRO_PARSE_COMMAND_LINE(app, argc, argv)      \
    try {                                                 \
        (app).parse((argc), (argv));                      \
    } catch (const CLI::ParseError& parse_error) {        \
        return (app).exit(parse_error) == 0 ? 0 : 1;      \
    }
