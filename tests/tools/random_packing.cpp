// random_packing end to end, 2D and 3D: the dump it writes reads back (io::read_packing) as a
// periodic packing of the radii asked for, dense, at the pressure asked for (recomputed here from
// the overlaps alone, k times overlap along each branch), without a particle pair pressed deeper
// than 20 times the mean overlap; the same seed gives the same file (2D); an existing file is kept
// unless --overwrite; absurd options are refused.
#define BOOST_TEST_MODULE tools_random_packing
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include <micromacro/io/packing_files.hpp>

#include "support/programs.hpp"

namespace fs = std::filesystem;
namespace mm = micromacro;

namespace {
const mmtest::WorkFolder work_folder("micromacro_random_packing_test");  // removed when the test process ends
const fs::path& work = work_folder.path;

mmtest::ProgramResult run(const std::string& args) { return mmtest::run_program(RANDOM_PACKING, args, work); }

struct Contacts {
    double pressure = 0.0;  ///< (1 / (dim V)) sum k overlap |branch|
    double mean_overlap = 0.0, deepest = 0.0;
    std::size_t count = 0;
};

template <int dim>
Contacts contacts(const mm::io::PackingFile<dim>& f, double k) {
    const auto [lo, hi] = *f.box;
    const mm::Vec<dim> L = hi - lo;
    Contacts c;
    for (std::size_t i = 0; i < f.position.size(); ++i)
        for (std::size_t j = i + 1; j < f.position.size(); ++j) {
            mm::Vec<dim> d = f.position[i] - f.position[j];
            for (int a = 0; a < dim; ++a) d[a] -= L[a] * std::round(d[a] / L[a]);
            const double overlap = f.radius[i] + f.radius[j] - d.norm();
            if (overlap <= 0.0) continue;
            ++c.count;
            c.mean_overlap += overlap;
            c.deepest = std::max(c.deepest, overlap);
            c.pressure += k * overlap * d.norm();
        }
    c.mean_overlap /= double(c.count);
    c.pressure /= dim * L.prod();
    return c;
}

template <int dim>
void check_packing(std::size_t n, double pressure, double dense, bool same_seed_again) {
    const fs::path out = work / ("packing" + std::to_string(dim) + ".dump");
    const auto r = run("--dim " + std::to_string(dim) + " --particles " + std::to_string(n) + " --pressure " + std::to_string(pressure) +
                       " --radii 0.5e-3 1.5e-3 --seed 3 --out " + out.string());
    BOOST_TEST_REQUIRE(r.exit_code() == 0, r.err);
    const auto f = mm::io::read_packing<dim>(out.string(), mm::io::PackingFormat::lammps_dump);
    BOOST_TEST(f.position.size() == n);
    BOOST_REQUIRE(f.box.has_value());
    double solid = 0.0, mean_radius = 0.0;
    for (int a = 0; a < dim; ++a) BOOST_TEST(f.periodic[a]);
    for (std::size_t p = 0; p < n; ++p) {
        BOOST_TEST(f.radius[p] >= 0.5e-3);
        BOOST_TEST(f.radius[p] <= 1.5e-3);
        for (int a = 0; a < dim; ++a) {
            BOOST_TEST(f.position[p][a] >= f.box->first[a]);
            BOOST_TEST(f.position[p][a] < f.box->second[a]);
        }
        solid += mm::DimTraits<dim>::particle_volume(f.radius[p]);
        mean_radius += f.radius[p] / double(n);
    }
    const double fraction = solid / (f.box->second - f.box->first).prod();
    BOOST_TEST(fraction > dense, "packing fraction " << fraction);
    // The pressure from the overlaps alone: at rest the dashpots carry nothing, so within the
    // program's 2% of the target (p / k in 2D, p a / k in 3D, k = 1e5 N/m) and round-off.
    const double k = 1e5, target = pressure * k / (dim == 2 ? 1.0 : mean_radius);
    const Contacts c = contacts(f, k);
    BOOST_TEST(std::abs(c.pressure / target - 1.0) < 0.021, "pressure " << c.pressure << " against " << target);
    BOOST_TEST(c.count >= n);  // a jammed packing: over one contact per particle, well over
    BOOST_TEST(c.deepest < 20.0 * c.mean_overlap, "deepest overlap " << c.deepest << ", mean " << c.mean_overlap);

    if (!same_seed_again) return;  // (once is enough: the sanitizer build runs these slowly)
    // The same seed, the same file to the last digit.
    const fs::path again = work / ("again" + std::to_string(dim) + ".dump");
    const auto r2 = run("--dim " + std::to_string(dim) + " --particles " + std::to_string(n) + " --pressure " + std::to_string(pressure) +
                        " --radii 0.5e-3 1.5e-3 --seed 3 --out " + again.string());
    BOOST_TEST_REQUIRE(r2.exit_code() == 0, r2.err);
    BOOST_TEST(mmtest::slurp(out) == mmtest::slurp(again));
}
}  // namespace

BOOST_AUTO_TEST_CASE(a_dense_periodic_packing_at_the_pressure_2d) { check_packing<2>(120, 5e-4, 0.78, true); }
BOOST_AUTO_TEST_CASE(a_dense_periodic_packing_at_the_pressure_3d) { check_packing<3>(120, 5e-4, 0.56, false); }

// Too few particles for their radii: the box they pack into would be shorter than two
// interaction ranges (2 x (2 largest radii + skin)), where a particle meets two images of one
// partner and the minimum image counts only one (8 disks and 20 spheres packed so before, with no
// word). Refused before any work with a count that fits, which packs into a box long enough.
template <int dim>
void too_few_particles_for_the_box(int n) {
    const fs::path out = work / ("few" + std::to_string(dim) + ".dump");
    const std::string common = "--dim " + std::to_string(dim) + " --seed 1 --out " + out.string() + " --particles ";
    const auto r = run(common + std::to_string(n));
    BOOST_TEST(r.exit_code() == 1);
    BOOST_TEST(r.err.find("shorter than two interaction ranges") != std::string::npos, r.err);
    BOOST_TEST(!fs::exists(out));
    const std::string use = "use --particles >= ";
    const auto at = r.err.find(use);
    BOOST_TEST_REQUIRE(at != std::string::npos, r.err);
    const int enough = std::stoi(r.err.substr(at + use.size()));
    BOOST_TEST(enough > n);
    const auto ok = run(common + std::to_string(enough));
    BOOST_TEST_REQUIRE(ok.exit_code() == 0, ok.err);
    const auto f = mm::io::read_packing<dim>(out.string(), mm::io::PackingFormat::lammps_dump);
    double largest = 0.0, sum = 0.0;
    for (const double a : f.radius) largest = std::max(largest, a), sum += a;
    const double range = 2.0 * largest + 0.2 * sum / double(f.radius.size());  // the engine's default skin
    const auto [lo, hi] = *f.box;
    for (int a = 0; a < dim; ++a) BOOST_TEST(hi[a] - lo[a] >= 2.0 * range);
}
BOOST_AUTO_TEST_CASE(too_few_particles_for_the_box_2d) { too_few_particles_for_the_box<2>(8); }
BOOST_AUTO_TEST_CASE(too_few_particles_for_the_box_3d) { too_few_particles_for_the_box<3>(20); }

BOOST_AUTO_TEST_CASE(an_existing_file_is_kept_and_absurd_options_refused) {
    const std::string kept = mmtest::write_file(work, "kept.dump", "an earlier result\n");
    const auto refused = run("--particles 20 --out " + kept);
    BOOST_TEST(refused.exit_code() == 1);
    BOOST_TEST(refused.err.find("--overwrite") != std::string::npos, refused.err);
    BOOST_TEST(mmtest::slurp(kept) == "an earlier result\n");

    const auto replaced = run("--particles 20 --overwrite --out " + kept);
    BOOST_TEST(replaced.exit_code() == 0, replaced.err);
    BOOST_TEST(mmtest::slurp(kept).rfind("ITEM: TIMESTEP", 0) == 0u);

    for (const std::string args : {"--radii 1e-3 0.5e-3", "--radii 0 1e-3", "--pressure 0.5", "--particles 2", "--dim 4"}) {
        const auto r = run(args + " --out " + (work / "absurd.dump").string());
        BOOST_TEST(r.exit_code() == 1, args);
        BOOST_TEST(!r.err.empty(), args);
        BOOST_TEST(!fs::exists(work / "absurd.dump"), args);
    }
    const auto no_folder = run("--particles 20 --out /nonexistent_micromacro_folder/p.dump");
    BOOST_TEST(no_folder.exit_code() == 1);
    BOOST_TEST(no_folder.err.find("/nonexistent_micromacro_folder") != std::string::npos, no_folder.err);
}
