#pragma once
// Reading the tangential contact forces of a packing written by another code, to go with the
// packing file (io/packing_files.hpp): a CSV table, one contact per line. Errors name the file
// and the line.
#include <algorithm>
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/io/packing_files.hpp"

namespace micromacro::io {

/// One line of a contact-force file: the tangential force on particle `i` from particle `j`.
template <int dim>
struct ContactForceRecord {
    long long i, j;  ///< particle ids (the packing's id column, else 0-based order)
    Vec<dim> tangential_force;
    std::size_t line;
};

/// Tangential contact forces from a CSV file with columns i, j and ft_x, ft_z (2D) or ft_x, ft_y,
/// ft_z (3D), each contact on one line (a pair listed twice, in either order, is refused).
template <int dim>
std::vector<ContactForceRecord<dim>> read_contact_forces(const std::string& path) {
    std::vector<ContactForceRecord<dim>> out;
    std::array<std::string, dim + 2> wanted;
    wanted[0] = "i";
    wanted[1] = "j";
    const auto axes = csv_coordinates<dim>();
    for (int a = 0; a < dim; ++a) wanted[a + 2] = std::string("ft_") + axes[a];
    std::array<int, dim + 2> columns{};
    detail::read_csv_rows(
        path,
        [&](const std::vector<std::string>& names, std::size_t line) {
            for (std::size_t w = 0; w < wanted.size(); ++w) {
                const auto it = std::find(names.begin(), names.end(), wanted[w]);
                if (it == names.end()) file_error(path, line, "missing column '" + wanted[w] + "'");
                columns[w] = static_cast<int>(it - names.begin());
            }
        },
        [&](const std::vector<std::string>& fields, std::size_t line) {
            ContactForceRecord<dim> r;
            r.i = detail::whole_number(fields[columns[0]], path, line, "i");
            r.j = detail::whole_number(fields[columns[1]], path, line, "j");
            for (int a = 0; a < dim; ++a) r.tangential_force[a] = detail::number(fields[columns[a + 2]], path, line, wanted[a + 2]);
            r.line = line;
            out.push_back(r);
        });
    // One line per contact: a pair listed twice (in either order) would leave its force to
    // whichever line came last.
    std::vector<std::size_t> order(out.size());
    for (std::size_t q = 0; q < order.size(); ++q) order[q] = q;
    auto pair = [&](std::size_t q) { return std::pair{std::min(out[q].i, out[q].j), std::max(out[q].i, out[q].j)}; };
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return pair(a) < pair(b) || (pair(a) == pair(b) && a < b); });
    for (std::size_t q = 1; q < order.size(); ++q)
        if (pair(order[q]) == pair(order[q - 1]))
            file_error(path, out[order[q]].line, "lists the contact of particles " + std::to_string(out[order[q]].i) + " and " +
                                                     std::to_string(out[order[q]].j) + " again (first on line " +
                                                     std::to_string(out[order[q - 1]].line) + "); give each contact once");
    return out;
}

}  // namespace micromacro::io
