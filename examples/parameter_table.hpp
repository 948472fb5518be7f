#pragma once
// A program's parameters written once, as a table: each row gives its command-line option (if it
// has one), its key in run.json and in saved states, its help text, the Config member it sets, and
// whether it made the packing (then a prepared state supplies it). The command line, run.json and
// the states of biaxial and element_test are all made from their tables with these functions.
#include <cstddef>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "command_line.hpp"

namespace micromacro::cli {

template <class Config>
struct Parameter {
    const char* option;  ///< "--mu", or nullptr: saved but not an option (a preset sets it)
    const char* key;     ///< in run.json's "parameters"
    const char* help;
    std::variant<double Config::*, std::size_t Config::*, unsigned long long Config::*, int Config::*, std::string Config::*,
                 bool Config::*>
        field;
    bool preparation = false;   ///< made the packing: a prepared state supplies it
    const char* law = nullptr;  ///< the contact law it belongs to, or nullptr: every law
    bool later = false;         ///< added after files were written without it: those keep Config's default
};

template <class Config>
using ParameterTable = std::vector<Parameter<Config>>;

/// The table's values in `c` as run.json's "parameters", in the table's order.
template <class Config>
nlohmann::ordered_json parameters_json(const ParameterTable<Config>& table, const Config& c) {
    nlohmann::ordered_json j;
    for (const auto& p : table) std::visit([&](auto field) { j[p.key] = c.*field; }, p.field);
    return j;
}

/// The values saved in `saved` (run.json's or a state's "parameters") over `c`. A `later` row a
/// file lacks takes Config's default: the value every run had before the row existed.
template <class Config>
Config config_from_json(const ParameterTable<Config>& table, const nlohmann::ordered_json& saved, Config c) {
    const Config then;
    for (const auto& p : table)
        std::visit(
            [&](auto field) {
                using T = std::remove_cvref_t<decltype(std::declval<Config&>().*field)>;
                c.*field = p.later && !saved.contains(p.key) ? then.*field : saved.at(p.key).template get<T>();
            },
            p.field);
    return c;
}

/// The table's options on `app`, unbound (a flag for a bool): read with apply_options after the
/// preset has set the defaults. One entry per row, nullptr for a row without an option.
template <class Config>
std::vector<CLI::Option*> add_options(CLI::App& app, const ParameterTable<Config>& table) {
    std::vector<CLI::Option*> options;
    for (const auto& p : table) {
        CLI::Option* o = nullptr;
        if (p.option)
            o = std::holds_alternative<bool Config::*>(p.field) ? app.add_flag(p.option, p.help) : app.add_option(p.option, p.help);
        options.push_back(o);
    }
    return options;
}

/// The options given, over the preset's values in `c`. Counts and seeds are whole numbers >= 0 as
/// typed: "-5" or "1e19" is refused, not wrapped.
template <class Config>
void apply_options(const ParameterTable<Config>& table, const std::vector<CLI::Option*>& options, Config& c) {
    for (std::size_t k = 0; k < table.size(); ++k) {
        const CLI::Option* o = options[k];
        if (!o || !o->count()) continue;
        std::visit(
            [&](auto field) {
                using T = std::remove_cvref_t<decltype(std::declval<Config&>().*field)>;
                if constexpr (std::is_same_v<T, std::size_t> || std::is_same_v<T, unsigned long long>)
                    c.*field = whole_number<T>(*o);
                else if constexpr (std::is_same_v<T, bool>)
                    c.*field = true;
                else
                    c.*field = o->as<T>();
            },
            table[k].field);
    }
}

/// Whether the option of the row keyed `key` was given.
template <class Config>
bool given(const ParameterTable<Config>& table, const std::vector<CLI::Option*>& options, const std::string& key) {
    for (std::size_t k = 0; k < table.size(); ++k)
        if (key == table[k].key) return options[k] && options[k]->count();
    return false;
}

/// The options of rows that made the packing and were given (refused with --from-prepared).
template <class Config>
std::vector<std::string> preparation_options_given(const ParameterTable<Config>& table, const std::vector<CLI::Option*>& options) {
    std::vector<std::string> names;
    for (std::size_t k = 0; k < table.size(); ++k)
        if (table[k].preparation && options[k] && options[k]->count()) names.push_back(options[k]->get_name());
    return names;
}

/// What a prepared state fixes: the rows that made the packing, from `prepared` into `c`.
template <class Config>
void take_preparation(const ParameterTable<Config>& table, const Config& prepared, Config& c) {
    for (const auto& p : table)
        if (p.preparation) std::visit([&](auto field) { c.*field = prepared.*field; }, p.field);
}

}  // namespace micromacro::cli
