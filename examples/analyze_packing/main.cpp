// analyze_packing: the micro-macro averages of a packing made by any code, as JSON.
//
//   analyze_packing packing.csv --k 1e5 --kt 2e4 --margin 0.1
//   analyze_packing dump.lammps --dim 3 --periodic x,y,z
//
// Contacts are the overlapping pairs; their normal forces follow from the overlaps with the
// linear spring k, tangential forces come from an optional contact-force file. Run with --help
// for every option.
#include <cstdio>
#include <filesystem>
#include <functional>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "../command_line.hpp"
#include "../output_paths.hpp"
#include "../standard_output.hpp"

#include <micromacro/io/json.hpp>
#include <micromacro/io/contact_force_files.hpp>
#include <micromacro/io/packing_files.hpp>
#include <micromacro/io/whole_file.hpp>
#include <micromacro/micromacro.hpp>

namespace mm = micromacro;

namespace {
struct Options {
    std::string input, format, output, rule = "contact", periodic, contact_forces;
    int dim = 0;
    std::vector<double> box;
    double k = 1e5, kt = 0.0, margin = 0.1;
    bool exclude_rattlers = false;
};

/// Gives the detected contacts the tangential forces of a contact-force file (projected into
/// each contact's tangent plane); a listed pair that does not overlap is an error.
template <int dim>
void add_tangential_forces(mm::PackingSnapshot<dim>& s, const mm::io::PackingFile<dim>& file, const std::string& path) {
    std::map<long long, mm::Index> index;
    for (std::size_t p = 0; p < file.id.size(); ++p) index[file.id[p]] = static_cast<mm::Index>(p);
    std::map<std::pair<mm::Index, mm::Index>, std::size_t> contact;
    for (std::size_t q = 0; q < s.contacts.size(); ++q) contact[{s.contacts[q].i, s.contacts[q].j}] = q;
    for (const auto& r : mm::io::read_contact_forces<dim>(path)) {
        const auto i = index.find(r.i), j = index.find(r.j);
        if (i == index.end() || j == index.end())
            mm::io::file_error(path, r.line, "particle id " + std::to_string(i == index.end() ? r.i : r.j) + " is not in the packing");
        const bool swapped = i->second > j->second;
        const auto c = contact.find(swapped ? std::pair{j->second, i->second} : std::pair{i->second, j->second});
        if (c == contact.end())
            mm::io::file_error(path, r.line, "particles " + std::to_string(r.i) + " and " + std::to_string(r.j) +
                                                  " do not overlap, so they have no contact to carry a force");
        auto& record = s.contacts[c->second];
        const mm::Vec<dim> f = swapped ? mm::Vec<dim>(-r.tangential_force) : r.tangential_force;
        record.tangential_force = f - record.normal * record.normal.dot(f);
    }
}

mm::SelectionRule selection_rule(const std::string& rule) {
    if (rule == "contact") return mm::SelectionRule::contact_point;
    if (rule == "center" || rule == "centre") return mm::SelectionRule::particle_centre;
    mm::throw_input_error("--rule '", rule, "' is unknown; use contact or center");
}

template <int dim>
nlohmann::ordered_json analyze(const Options& o, mm::io::PackingFormat format) {
    const auto file = mm::io::read_packing<dim>(o.input, format);
    if (file.position.size() < 2)  // one particle has no contacts, and its own extent is no box to average over
        mm::throw_input_error(o.input, " holds one particle; averages need a packing (at least 2)");
    // Box and periodic axes: the options, else the dump's, else the particles' extent.
    const auto domain = mm::io::packing_domain<dim>(file, o.box, o.periodic);
    const mm::Vec<dim> lo = domain.lo(), hi = domain.hi();
    mm::PackingSnapshot<dim> s;
    s.domain = domain;
    s.position = file.position;
    s.radius = file.radius;
    mm::detect_contacts(s, o.k, o.kt);
    if (!o.contact_forces.empty()) add_tangential_forces(s, file, o.contact_forces);

    mm::AveragingOptions options;
    options.rule = selection_rule(o.rule);
    options.exclude_rattlers = o.exclude_rattlers;
    const auto region = mm::Region<dim>::box(lo, hi).inner(s.domain, o.margin);
    auto j = mm::io::to_json(mm::average(s, region, options));
    j["anisotropy"] = mm::io::to_json(mm::anisotropy(s, region, options));
    // Numbers that overflowed would print as null: refused.
    std::function<void(const nlohmann::ordered_json&, const std::string&)> finite = [&](const auto& v, const std::string& key) {
        if (v.is_number_float() && !std::isfinite(v.template get<double>()))
            mm::throw_input_error(o.input, ": the average '", key, "' is not finite: the file's values overflow "
                                          "double arithmetic (are lengths in m and stiffnesses in N/m?)");
        for (auto it = v.begin(); v.is_structured() && it != v.end(); ++it) finite(*it, v.is_object() ? it.key() : key);
    };
    finite(j, "");
    j["region"] = {{"lo", mm::io::vector_json(region.lo)}, {"hi", mm::io::vector_json(region.hi)}};
    j["rule"] = options.rule == mm::SelectionRule::contact_point ? "contact" : "center";
    j["margin"] = o.margin;
    j["k"] = o.k;
    j["kt"] = o.kt;
    return j;
}
}  // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App app{"micro-macro averages (fabric, stress, stiffness) of a packing, printed as JSON"};
    app.add_option("packing", o.input, "CSV (header x,z,r in 2D or x,y,z,r in 3D; optional id) or LAMMPS dump")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("--format", o.format, "csv or lammps (default: guessed from the first line)")
        ->check(CLI::IsMember({"csv", "lammps"}));
    app.add_option("--dim", o.dim, "2 or 3 (default: CSV 3 if it has a y column, else 2; LAMMPS 3)")
        ->check(CLI::IsMember({2, 3}));
    app.add_option("--box", o.box, "bounds lo hi per axis, e.g. 0 0.09 0 0.09 (m; default: the dump's box, "
                                   "else the particles' extent)")
        ->expected(4, 6);
    app.add_option("--periodic", o.periodic, "periodic axes, e.g. x,z (default: the dump's pp axes, else none)");
    app.add_option("--k", o.k, "normal contact stiffness (N/m) for forces and the stiffness tensor")->capture_default_str();
    app.add_option("--kt", o.kt, "tangential stiffness (N/m) for the tangential stiffness tensor")->capture_default_str();
    app.add_option("--margin", o.margin, "fraction of the box left out next to each non-periodic boundary")
        ->capture_default_str();
    app.add_option("--rule", o.rule, "contact (contact point inside, Eq. 31) or center (particle centre inside, Eq. 10)")
        ->capture_default_str();
    app.add_option("--contact-forces", o.contact_forces,
                   "CSV of tangential contact forces: columns i, j (particle ids) and ft_x, ft_z (2D) or ft_x, ft_y, "
                   "ft_z (3D), the force on i from j (N); without it contacts carry normal forces only")
        ->check(CLI::ExistingFile);
    app.add_flag("--exclude-rattlers", o.exclude_rattlers, "leave out particles with fewer than dim + 1 contacts");
    app.add_option("--output,-o", o.output, "write the JSON here instead of standard output (written whole, then renamed)");
    MICROMACRO_PARSE_COMMAND_LINE(app, argc, argv);

    try {
        selection_rule(o.rule);  // refuse a bad option before reading anything
        mm::cli::refuse_writing_over_inputs(o.output, "-o", {{"the input", o.input}, {"--contact-forces", o.contact_forces}});
        const auto format = o.format.empty() ? mm::io::guess_format(o.input)
                            : o.format == "lammps" ? mm::io::PackingFormat::lammps_dump
                                                   : mm::io::PackingFormat::csv;
        const int dim = o.dim ? o.dim : mm::io::guess_dimension(o.input, format);
        const auto json = dim == 2 ? analyze<2>(o, format) : analyze<3>(o, format);
        const std::string text = json.dump(2) + "\n";
        if (o.output.empty()) {
            std::cout << text;
            if (!standard_output_complete()) mm::throw_input_error("cannot write to standard output (is the disk full?)");
        } else {
            mm::io::write_whole_file(o.output, text);
        }
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "analyze_packing: " << e.what() << "\n";
        return 1;
    }
}
