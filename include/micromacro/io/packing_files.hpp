#pragma once
// Reading packings written by other codes: a CSV table of particles, or a LAMMPS dump. Every
// error names the file and the line. Needs only the standard library (no VTK).
//
// CSV: a header line naming the columns, then one particle per line. 2D needs x, z and r
// (the paper's coordinates), 3D needs x, y, z and r; `radius` or `diameter` (2 r) may stand for
// r, but only one of the three; an `id` column is optional, each id once; a column the reader
// uses named twice is refused; other columns are ignored. Blank lines and # lines are skipped.
// LAMMPS: the first snapshot of a text dump: ITEM: BOX BOUNDS (orthogonal box; pp marks a
// periodic axis) and ITEM: ATOMS with x y z and radius or diameter (2D uses x and y).
// `read_packing` reads either, `packing_domain` settles the box: the programs that take a
// packing file (analyze_packing, the throughput benchmark) resolve format, dimension, box and
// periodic axes here, the same way. io/packing_writer.hpp writes the LAMMPS form.
#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/domain.hpp"
#include "micromacro/core/error.hpp"

namespace micromacro::io {

template <int dim>
struct PackingFile {
    std::vector<Vec<dim>> position;
    std::vector<double> radius;
    std::vector<long long> id;      ///< from the id column, else 0, 1, 2, ...
    std::vector<std::size_t> line;  ///< line of each particle in the file
    std::optional<std::pair<Vec<dim>, Vec<dim>>> box;  ///< from the file (LAMMPS)
    std::array<bool, dim> periodic{};                   ///< from the file (LAMMPS pp)
};

/// Throws an InputError "path:line: what" (line 0: "path: what"), the form of every file error.
[[noreturn]] inline void file_error(const std::string& path, std::size_t line, const std::string& what) {
    micromacro::throw_input_error(path, line ? ":" + std::to_string(line) : std::string(), ": ", what);
}

namespace detail {
inline std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::string field;
    std::istringstream in(s);
    if (sep == ' ') {
        while (in >> field) out.push_back(field);
    } else {
        while (std::getline(in, field, sep)) {
            const auto a = field.find_first_not_of(" \t\r"), b = field.find_last_not_of(" \t\r");
            out.push_back(a == std::string::npos ? std::string() : field.substr(a, b - a + 1));
        }
        if (!s.empty() && s.back() == sep) out.emplace_back();
    }
    return out;
}

inline double number(const std::string& text, const std::string& path, std::size_t line, const std::string& column) {
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v))
        file_error(path, line, "column '" + column + "': '" + text + "' is not a finite number");
    return v;
}

/// A whole number (an id, a count) from a field: integral and within +-2^53, where doubles count exactly.
inline long long whole_number(const std::string& text, const std::string& path, std::size_t line, const std::string& column) {
    const double v = number(text, path, line, column);
    if (v != std::floor(v) || std::abs(v) > 9007199254740992.0)
        file_error(path, line, "column '" + column + "': '" + text + "' is not a whole number within +-2^53");
    return static_cast<long long>(v);
}

inline std::ifstream open(const std::string& path) {
    std::ifstream in(path);
    if (!in) file_error(path, 0, "cannot open the file for reading");
    return in;
}

/// Reads a CSV file: calls header(names, line) for the first data line and row(fields, line)
/// for every further one; skips blank lines and # comments; checks the field count.
template <class Header, class Row>
void read_csv_rows(const std::string& path, Header&& header, Row&& row) {
    auto in = open(path);
    std::string text;
    std::size_t line = 0, columns = 0;
    while (std::getline(in, text)) {
        ++line;
        if (!text.empty() && text.back() == '\r') text.pop_back();
        if (line == 1 && text.rfind("\xef\xbb\xbf", 0) == 0) text.erase(0, 3);  // a UTF-8 byte-order mark
        const auto first = text.find_first_not_of(" \t");
        if (first == std::string::npos || text[first] == '#') continue;
        const auto fields = split(text, ',');
        if (columns == 0 && fields.size() == 1)
            for (const char separator : {';', '\t', ' '})
                if (text.find(separator) != std::string::npos)
                    file_error(path, line, std::string("the header is separated by ") + (separator == ';' ? "';'" : separator == '\t' ? "tabs" : "spaces") +
                                         ", not commas; save the file as comma-separated CSV");
        if (columns == 0) {
            columns = fields.size();
            header(fields, line);
            continue;
        }
        if (fields.size() != columns)
            file_error(path, line, "has " + std::to_string(fields.size()) + " fields, the header has " + std::to_string(columns));
        row(fields, line);
    }
    if (columns == 0) file_error(path, 0, "the file is empty (no header line)");
}

/// Rejects a file without particles and particles with identical centres (undefined normal).
template <int dim>
void check_particles(PackingFile<dim>& f, const std::string& path) {
    if (f.position.empty()) file_error(path, 0, "the file holds no particles");
    // Ids name particles (contact-force files refer to them): each once.
    std::vector<std::size_t> by_id(f.id.size());
    std::iota(by_id.begin(), by_id.end(), 0);
    std::sort(by_id.begin(), by_id.end(), [&](std::size_t a, std::size_t b) { return f.id[a] < f.id[b] || (f.id[a] == f.id[b] && a < b); });
    for (std::size_t q = 1; q < by_id.size(); ++q)
        if (f.id[by_id[q]] == f.id[by_id[q - 1]])
            file_error(path, f.line[by_id[q]], "particle id " + std::to_string(f.id[by_id[q]]) + " is taken by the particle on line " +
                                                   std::to_string(f.line[by_id[q - 1]]) + " already; give each particle its own id");
    // Identical centres: sort by position and compare neighbours.
    std::vector<std::size_t> order(f.position.size());
    std::iota(order.begin(), order.end(), 0);
    auto key = [&](std::size_t i) {
        std::array<double, dim> k;
        for (int a = 0; a < dim; ++a) k[a] = f.position[i][a];
        return k;
    };
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
    for (std::size_t q = 1; q < order.size(); ++q)
        if (key(order[q]) == key(order[q - 1]))
            file_error(path, std::max(f.line[order[q]], f.line[order[q - 1]]),
                 "particle has the same centre as the particle on line " +
                     std::to_string(std::min(f.line[order[q]], f.line[order[q - 1]])) +
                     "; the contact normal between them is undefined");
}

template <int dim>
void add_particle(PackingFile<dim>& f, const std::vector<std::string>& fields, const std::array<int, dim>& columns,
                  int radius_column, double radius_factor, int id_column, const std::vector<std::string>& names,
                  const std::string& path, std::size_t line) {
    Vec<dim> x;
    for (int a = 0; a < dim; ++a) x[a] = number(fields[columns[a]], path, line, names[columns[a]]);
    const double r = radius_factor * number(fields[radius_column], path, line, names[radius_column]);
    if (!(r > 0.0)) file_error(path, line, "radius " + fields[radius_column] + " is not positive; every particle needs a radius > 0");
    f.position.push_back(x);
    f.radius.push_back(r);
    f.id.push_back(id_column >= 0 ? whole_number(fields[id_column], path, line, "id") : static_cast<long long>(f.id.size()));
    f.line.push_back(line);
}

/// Finds the columns for the coordinates and the radius among `names`.
template <int dim>
void locate(const std::vector<std::string>& names, const std::array<const char*, dim>& coordinates,
            std::array<int, dim>& columns, int& radius_column, double& radius_factor, int& id_column,
            const std::string& path, std::size_t line) {
    auto find = [&](const std::string& n) {
        const auto it = std::find(names.begin(), names.end(), n);
        if (it != names.end())
            if (const auto again = std::find(it + 1, names.end(), n); again != names.end())
                file_error(path, line, "column '" + n + "' is named twice (fields " + std::to_string(it - names.begin() + 1) + " and " +
                                           std::to_string(again - names.begin() + 1) + "), so which one it is is ambiguous; "
                                           "rename or remove one");
        return it == names.end() ? -1 : static_cast<int>(it - names.begin());
    };
    for (int a = 0; a < dim; ++a) {
        columns[a] = find(coordinates[a]);
        if (columns[a] < 0) file_error(path, line, std::string("missing column '") + coordinates[a] + "'");
    }
    // One column gives the size: two could disagree, and which one was meant cannot be told.
    std::string sizes;
    for (const char* name : {"r", "radius", "diameter"})
        if (find(name) >= 0) sizes += (sizes.empty() ? "'" : ", '") + std::string(name) + "'";
    if (sizes.find(',') != std::string::npos)
        file_error(path, line, "the header has more than one size column (" + sizes + "); keep one of them");
    radius_factor = 1.0;
    radius_column = find("r");
    if (radius_column < 0) radius_column = find("radius");
    if (radius_column < 0) {
        radius_column = find("diameter");
        radius_factor = 0.5;
    }
    if (radius_column < 0) file_error(path, line, "missing column 'r' (or 'radius' or 'diameter')");
    id_column = find("id");
}
}  // namespace detail

/// The coordinate columns of a CSV file for dimension dim.
template <int dim>
constexpr std::array<const char*, dim> csv_coordinates() {
    if constexpr (dim == 2) return {"x", "z"};
    else return {"x", "y", "z"};
}

template <int dim>
PackingFile<dim> read_csv(const std::string& path) {
    PackingFile<dim> f;
    std::vector<std::string> names;
    std::array<int, dim> columns{};
    int radius_column = -1, id_column = -1;
    double radius_factor = 1.0;
    detail::read_csv_rows(
        path,
        [&](const std::vector<std::string>& header, std::size_t line) {
            names = header;
            if (dim == 2 && std::find(names.begin(), names.end(), "y") != names.end())
                file_error(path, line, "the header names a y column: a 3D packing, read as 2D (2D files have x and z); "
                                         "read it in 3D (analyze_packing --dim 3)");
            detail::locate<dim>(names, csv_coordinates<dim>(), columns, radius_column, radius_factor, id_column, path, line);
        },
        [&](const std::vector<std::string>& fields, std::size_t line) {
            detail::add_particle<dim>(f, fields, columns, radius_column, radius_factor, id_column, names, path, line);
        });
    detail::check_particles(f, path);
    return f;
}

template <int dim>
PackingFile<dim> read_lammps_dump(const std::string& path) {
    auto in = detail::open(path);
    PackingFile<dim> f;
    std::string text;
    std::size_t line = 0, expected = 0;
    bool have_count = false, in_atoms = false;
    std::vector<std::string> names;
    std::array<int, dim> columns{};
    int radius_column = -1, id_column = -1;
    double radius_factor = 1.0;
    [[maybe_unused]] double first_z = 0.0;  // 2D: every atom at the first one's z
    auto next = [&] {
        if (!std::getline(in, text)) file_error(path, line, "the file ends early");
        ++line;
        if (!text.empty() && text.back() == '\r') text.pop_back();
    };
    while (std::getline(in, text)) {
        ++line;
        if (!text.empty() && text.back() == '\r') text.pop_back();
        if (text.rfind("ITEM:", 0) == 0) {
            if (in_atoms) break;  // the next snapshot: only the first is read
            if (text.rfind("ITEM: NUMBER OF ATOMS", 0) == 0) {
                next();
                const auto count = detail::split(text, ' ');
                const long long n = detail::whole_number(count.empty() ? std::string() : count[0], path, line, "number of atoms");
                if (n < 0) file_error(path, line, "a negative number of atoms, " + count[0]);
                expected = static_cast<std::size_t>(n);
                have_count = true;
            } else if (text.rfind("ITEM: BOX BOUNDS", 0) == 0) {
                const auto flags = detail::split(text.substr(16), ' ');
                if (flags.size() > 3 || (!flags.empty() && flags[0] == "xy"))
                    file_error(path, line, "triclinic boxes are not supported");
                Vec<dim> lo, hi;
                for (int a = 0; a < 3; ++a) {
                    next();
                    const auto b = detail::split(text, ' ');
                    if (b.size() < 2) file_error(path, line, "a box bound line needs two numbers");
                    if (a < dim) {
                        lo[a] = detail::number(b[0], path, line, "box lo");
                        hi[a] = detail::number(b[1], path, line, "box hi");
                        f.periodic[a] = a < static_cast<int>(flags.size()) && flags[a] == "pp";
                    }
                }
                f.box = std::pair{lo, hi};
            } else if (text.rfind("ITEM: ATOMS", 0) == 0) {
                names = detail::split(text.substr(11), ' ');
                const std::array<const char*, 3> xyz{"x", "y", "z"};
                std::array<const char*, dim> coordinates;
                for (int a = 0; a < dim; ++a) coordinates[a] = xyz[a];
                detail::locate<dim>(names, coordinates, columns, radius_column, radius_factor, id_column, path, line);
                in_atoms = true;
            }
            continue;
        }
        if (!in_atoms) continue;
        if (text.find_first_not_of(" \t") == std::string::npos) continue;
        const auto fields = detail::split(text, ' ');
        if (fields.size() != names.size())
            file_error(path, line, "has " + std::to_string(fields.size()) + " fields, ITEM: ATOMS names " + std::to_string(names.size()));
        detail::add_particle<dim>(f, fields, columns, radius_column, radius_factor, id_column, names, path, line);
        if constexpr (dim == 2) {  // LAMMPS's 2D plane is x-y, at one z
            const auto z = std::find(names.begin(), names.end(), "z");
            if (z != names.end()) {
                const double value = detail::number(fields[z - names.begin()], path, line, "z");
                if (f.position.size() == 1) first_z = value;
                else if (value != first_z)
                    file_error(path, line, "z = " + fields[z - names.begin()] + " differs from the first atom's " +
                                                 std::to_string(first_z) + ": a 3D packing, read as 2D; read it in 3D "
                                                 "(analyze_packing --dim 3)");
            }
        }
    }
    if (line == 0) file_error(path, 0, "the file is empty");
    if (!in_atoms) file_error(path, line, "no ITEM: ATOMS section: not a LAMMPS dump");
    if (have_count && f.position.size() != expected)
        file_error(path, line, "ITEM: NUMBER OF ATOMS says " + std::to_string(expected) + ", the file holds " +
                                     std::to_string(f.position.size()));
    detail::check_particles(f, path);
    return f;
}

enum class PackingFormat { csv, lammps_dump };

/// The format of a packing file from its first line: a LAMMPS dump starts with "ITEM:".
inline PackingFormat guess_format(const std::string& path) {
    auto in = detail::open(path);
    std::string first;
    std::getline(in, first);
    return first.rfind("ITEM:", 0) == 0 ? PackingFormat::lammps_dump : PackingFormat::csv;
}

/// The dimension a packing file describes: for a LAMMPS dump 3 unless its ITEM: ATOMS line names
/// no z column (a 2D dump written without z); for a CSV file 3 if its header names a y column,
/// else 2 (2D uses the paper's x and z).
inline int guess_dimension(const std::string& path, PackingFormat format) {
    auto in = detail::open(path);
    std::string line;
    if (format == PackingFormat::lammps_dump) {
        while (std::getline(in, line)) {
            if (!line.empty() && line.back() == '\r') line.pop_back();
            if (line.rfind("ITEM: ATOMS", 0) != 0) continue;
            const auto names = detail::split(line.substr(11), ' ');
            return std::find(names.begin(), names.end(), "z") == names.end() ? 2 : 3;
        }
        return 3;
    }
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#' || line.find_first_not_of(" \t\r") == std::string::npos) continue;
        for (const auto& name : detail::split(line, ','))
            if (name == "y") return 3;
        return 2;
    }
    return 2;
}

template <int dim>
PackingFile<dim> read_packing(const std::string& path, PackingFormat format) {
    return format == PackingFormat::lammps_dump ? read_lammps_dump<dim>(path) : read_csv<dim>(path);
}

/// Periodic axes from a list of axis names, e.g. "x,z" (2D: x and z, the paper's plane; 3D: x,
/// y and z); commas and spaces separate them.
template <int dim>
std::array<bool, dim> parse_periodic_axes(const std::string& list) {
    const std::string names = dim == 2 ? "xz" : "xyz";
    std::array<bool, dim> periodic{};
    for (char c : list) {
        if (c == ',' || c == ' ') continue;
        const auto axis = names.find(c);
        if (axis == std::string::npos)
            micromacro::detail::throw_input_error("periodic axes '", list, "': unknown axis '", std::string(1, c),
                                                  "'; in ", dim, "D name them from ", dim == 2 ? "x, z" : "x, y, z",
                                                  " (for example ", dim == 2 ? "x,z" : "x,y,z", ")");
        periodic[axis] = true;
    }
    return periodic;
}

/// The box of a packing: `box` (lo hi per axis) if given, else the file's own (LAMMPS), else the
/// particles' extent; periodic axes from `periodic_axes` (see parse_periodic_axes) if it is not
/// empty, else the file's (LAMMPS pp). A periodic axis needs a box from the file or from `box`.
template <int dim>
Domain<dim> packing_domain(const PackingFile<dim>& file, const std::vector<double>& box, const std::string& periodic_axes) {
    const std::array<bool, dim> periodic = periodic_axes.empty() ? file.periodic : parse_periodic_axes<dim>(periodic_axes);
    Vec<dim> lo, hi;
    if (!box.empty()) {
        if (box.size() != 2 * dim)
            micromacro::detail::throw_input_error("a ", dim, "D box needs ", 2 * dim, " numbers (lo hi per axis), got ", box.size());
        for (int a = 0; a < dim; ++a) {
            lo[a] = box[2 * a];
            hi[a] = box[2 * a + 1];
        }
    } else if (file.box) {
        std::tie(lo, hi) = *file.box;
    } else {
        for (int a = 0; a < dim; ++a) {
            if (periodic[a])
                micromacro::detail::throw_input_error("periodic axis ", csv_coordinates<dim>()[a],
                                                      " needs the box's bounds, and the file gives none: give them (--box in the programs)");
            lo[a] = hi[a] = file.position.at(0)[a];
            for (std::size_t p = 0; p < file.position.size(); ++p) {
                lo[a] = std::min(lo[a], file.position[p][a] - file.radius[p]);
                hi[a] = std::max(hi[a], file.position[p][a] + file.radius[p]);
            }
        }
    }
    return Domain<dim>(lo, hi, periodic);
}

}  // namespace micromacro::io
