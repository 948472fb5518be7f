// The packing readers under random damage: a deterministic mutation loop (byte flips, cuts,
// repeats, inserted numbers and separators) over a small valid corpus of each format. Every
// damaged file must give a clear InputError or a valid result (finite positions, positive finite
// radii, finite forces), never a crash, another exception or a silent NaN. Run under the
// sanitizer build (scripts/sanitize.sh), undefined behaviour on the way counts as a crash too.
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <micromacro/io/contact_force_files.hpp>
#include <micromacro/io/packing_files.hpp>

#include "support/mutate.hpp"

BOOST_AUTO_TEST_SUITE(unit_fuzz_readers)  // the file's cases, run as the CTest test of this file's name

namespace mm = micromacro;
namespace fs = std::filesystem;

namespace {

const fs::path dir = fs::temp_directory_path() / "micromacro_fuzz_readers";

/// Runs `read` on `mutations` damaged copies of every text of `corpus`; `valid` checks a result.
/// Returns how many copies were refused with an InputError.
template <class Read>
int fuzz(const std::string& name, const std::vector<std::string>& corpus, int mutations, Read read) {
    fs::create_directories(dir);
    std::mt19937_64 rng(20261202);
    int refused = 0;
    for (int m = 0; m < mutations; ++m) {
        const std::string text = mmtest::mutate(corpus[m % corpus.size()], rng);
        const fs::path file = dir / (name + ".txt");
        std::ofstream(file, std::ios::binary) << text;
        try {
            const std::string problem = read(file.string());
            if (!problem.empty()) BOOST_ERROR(name << " mutation " << m << ": " << problem << "\n---\n" << text << "\n---");
        } catch (const mm::InputError&) {
            ++refused;
        } catch (const std::exception& e) {
            BOOST_ERROR(name << " mutation " << m << ": " << e.what() << " is not an InputError\n---\n" << text << "\n---");
        }
    }
    return refused;
}

template <int dim>
std::string check_packing(const mm::io::PackingFile<dim>& f) {
    if (f.position.size() != f.radius.size() || f.position.size() != f.id.size()) return "arrays of different lengths";
    for (std::size_t i = 0; i < f.position.size(); ++i) {
        if (!f.position[i].allFinite()) return "a position that is not finite";
        if (!(f.radius[i] > 0.0) || !std::isfinite(f.radius[i])) return "a radius that is not positive and finite";
    }
    if (f.box && !(f.box->first.allFinite() && f.box->second.allFinite())) return "a box that is not finite";
    return "";
}

}  // namespace

BOOST_AUTO_TEST_CASE(packing_csv) {
    const std::vector<std::string> corpus2{"x,z,r\n0.001,0.002,0.0005\n0.003,0.002,0.0007\n0.002,0.004,0.001\n",
                                           "# a comment\nid,x,z,radius\n5,0,0,1e-3\n7,2.5e-3,0,1.2e-3\n"};
    const std::vector<std::string> corpus3{"x,y,z,r\n0,0,0,1e-3\n2.1e-3,0,0,1e-3\n0,2.2e-3,0,1.1e-3\n",
                                           "id,x,y,z,radius\r\n1,0,0,0,1e-3\r\n2,0,0,2.4e-3,1.3e-3\r\n"};
    const int refused2 = fuzz("csv2", corpus2, 3000, [](const std::string& p) { return check_packing(mm::io::read_csv<2>(p)); });
    const int refused3 = fuzz("csv3", corpus3, 3000, [](const std::string& p) { return check_packing(mm::io::read_csv<3>(p)); });
    BOOST_TEST_MESSAGE("CSV: " << refused2 << " and " << refused3 << " of 3000 damaged files refused, the rest read validly");
    BOOST_TEST(refused2 > 1000);  // most damage is detectable; the rest still reads as a valid packing
    BOOST_TEST(refused3 > 1000);
}

BOOST_AUTO_TEST_CASE(lammps_dump) {
    const std::vector<std::string> corpus{
        "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n3\nITEM: BOX BOUNDS pp pp pp\n0 0.01\n0 0.01\n0 0.01\n"
        "ITEM: ATOMS id type x y z radius\n1 1 0.001 0.001 0.001 0.0005\n2 1 0.003 0.001 0.001 0.0005\n"
        "3 1 0.005 0.002 0.001 0.0006\n",
        "ITEM: TIMESTEP\n10\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS ff ff pp\n-0.01 0.01\n-0.01 0.01\n-0.001 0.001\n"
        "ITEM: ATOMS id x y z diameter\n4 0 0 0 0.002\n9 0.0025 0 0 0.002\nITEM: TIMESTEP\n20\n"};
    const int refused3 = fuzz("dump3", corpus, 3000, [](const std::string& p) { return check_packing(mm::io::read_lammps_dump<3>(p)); });
    const int refused2 = fuzz("dump2", corpus, 3000, [](const std::string& p) { return check_packing(mm::io::read_lammps_dump<2>(p)); });
    BOOST_TEST_MESSAGE("LAMMPS dump: " << refused3 << " (3D) and " << refused2 << " (2D) of 3000 damaged files refused");
    BOOST_TEST(refused3 > 1000);
    BOOST_TEST(refused2 > 1000);
}

BOOST_AUTO_TEST_CASE(contact_forces) {
    const std::vector<std::string> corpus{"i,j,ft_x,ft_y,ft_z\n0,1,1e-3,0,-2e-3\n1,2,0,0,0\n2,0,-1e-4,5e-5,1e-3\n"};
    const int refused = fuzz("forces", corpus, 3000, [](const std::string& p) {
        for (const auto& r : mm::io::read_contact_forces<3>(p))
            if (!r.tangential_force.allFinite()) return std::string("a force that is not finite");
        return std::string();
    });
    BOOST_TEST_MESSAGE("contact forces: " << refused << " of 3000 damaged files refused");
    BOOST_TEST(refused > 1000);
}

BOOST_AUTO_TEST_SUITE_END()
