#pragma once
// Writing a packing as a LAMMPS text dump, the form io/packing_files.hpp reads back with its box
// and periodic axes (scripts/vs_lammps.sh turns it into a LAMMPS data file). No VTK needed.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/domain.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/io/whole_file.hpp"

namespace micromacro::io {

/// Writes particles (centres x, radii r) in `domain` as one snapshot of a LAMMPS text dump
/// (timestep 0, ids 1..n, type 1; 2D in LAMMPS's x-y plane without a z column, which tells
/// guess_dimension, and z bounds -0.5..0.5) with every digit a double holds, so that
/// read_packing gives back the same numbers. Written whole or not at all (io/whole_file.hpp).
template <int dim>
void write_lammps_dump(const std::filesystem::path& path, const std::vector<Vec<dim>>& x, const std::vector<double>& r,
                       const Domain<dim>& domain) {
    if (x.size() != r.size())
        micromacro::detail::throw_input_error("write_lammps_dump: ", x.size(), " centres and ", r.size(), " radii; give one radius per centre");
    write_whole_file(path, std::ios::out, [&](std::ofstream& out) {
        char text[256];
        out << "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n" << x.size() << "\nITEM: BOX BOUNDS";
        for (int a = 0; a < 3; ++a) out << (a < dim && !domain.periodic(a) ? " ff" : " pp");
        out << "\n";
        for (int a = 0; a < 3; ++a) {
            if (a < dim) std::snprintf(text, sizeof text, "%.17g %.17g\n", domain.lo()[a], domain.hi()[a]);
            else std::snprintf(text, sizeof text, "-0.5 0.5\n");
            out << text;
        }
        out << (dim == 2 ? "ITEM: ATOMS id type radius x y\n" : "ITEM: ATOMS id type radius x y z\n");
        for (std::size_t p = 0; p < x.size(); ++p) {
            std::snprintf(text, sizeof text, "%zu 1 %.17g", p + 1, r[p]);
            out << text;
            for (int a = 0; a < dim; ++a) {
                std::snprintf(text, sizeof text, " %.17g", x[p][a]);
                out << text;
            }
            out << "\n";
        }
    });
}

}  // namespace micromacro::io
