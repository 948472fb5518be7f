// biaxial_summary: the key numbers of a biaxial run as a Markdown table (the table of examples/biaxial/README.md).
//
//   biaxial_summary runs/paper
//
// Reads DIR/timeseries.csv and DIR/run.json. The peak is the row of the largest stress ratio
// (sigma_zz - sigma_xx) / (sigma_zz + sigma_xx) of the inner box during the motion; the
// "critical state" values are means over the last quarter of the motion (eps_zz from 3/4 of
// the final strain on). The swings of the stress are taken over the middle 60% of the motion
// (t from 0.2 to 0.8 of its duration): the 5th and 95th percentiles of single rows, and the
// upward crossings of sigma_zz through its centred 25-row running mean, which give the mean period.
// Then the quality figures of run.json (examples/biaxial/quality.hpp), where the run wrote them.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "../standard_output.hpp"
#include "timeseries.hpp"

namespace {

int summarise(const std::string& dir);

}  // namespace

int main(int argc, char** argv) {
    const std::string usage = "usage: biaxial_summary RUN_DIRECTORY (the --out of a finished biaxial run)\n";
    if (argc == 2 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
        std::printf("biaxial_summary: the key numbers of a biaxial run as a Markdown table\n%s", usage.c_str());
        return 0;
    }
    if (argc != 2) {
        std::fprintf(stderr, "biaxial_summary: %d arguments given, one run directory expected\n%s", argc - 1, usage.c_str());
        return 1;
    }
    if (argv[1][0] == '\0') {
        std::fprintf(stderr, "biaxial_summary: the run directory is empty; give the --out of a finished biaxial run\n%s", usage.c_str());
        return 1;
    }
    if (argv[1][0] == '-') {
        std::fprintf(stderr, "biaxial_summary: unknown option %s\n%s", argv[1], usage.c_str());
        return 1;
    }
    try {
        return summarise(argv[1]);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "biaxial_summary: %s\n", e.what());
        return 1;
    }
}

namespace {

int summarise(const std::string& dir) {
    const std::string json_path = dir + "/run.json";
    std::ifstream run_json(json_path);
    if (!run_json)
        throw std::runtime_error(json_path + " cannot be read: " + dir + " is not a finished biaxial run (give its --out)");
    const auto col_read = biaxial::read_timeseries(dir + "/timeseries.csv");
    nlohmann::json run;
    try {
        run = nlohmann::json::parse(run_json);
        (void)run.at("parameters").at("dim").get<int>(), (void)run.at("parameters").at("final_strain").get<double>();
        (void)run.at("timing").at("wall_seconds").get<double>();
    } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(json_path + ": " + e.what());
    }
    const int dim = run["parameters"]["dim"];
    if (dim != 2 && dim != 3) throw std::runtime_error(json_path + ": dim " + std::to_string(dim) + " is neither 2 nor 3");
    // Every column used below, checked before anything is printed.
    const std::string zc = dim == 2 ? "22" : "33";
    std::vector<std::string> needed{"time", "strain_" + zc, "sigma_" + zc, "sigma_11", "deviatoric_fabric", "trF", "g2",
                                    "C_n_" + zc + zc, "C_n_1111", "volumetric_strain", "coordination", "volume_fraction"};
    if (dim == 2) needed.insert(needed.end(), {"phi_F", "C_n_1112", "C_n_1222"});
    for (const auto& name : needed)
        if (!col_read.count(name)) throw std::runtime_error(dir + "/timeseries.csv has no column '" + name + "'");
    if (col_read.at("time").empty()) throw std::runtime_error(dir + "/timeseries.csv has no rows");
    const auto& col = col_read;
    const std::string z = dim == 2 ? "22" : "33", zzzz = dim == 2 ? "2222" : "3333";
    const double final_strain = run["parameters"]["final_strain"];
    const auto& ezz = col.at("strain_" + z);
    const auto& sigma_zz = col.at("sigma_" + z);  // the compressed axis
    const auto& sigma_11 = col.at("sigma_11");
    auto ratio = [&](std::size_t r) { return (sigma_zz[r] - sigma_11[r]) / (sigma_zz[r] + sigma_11[r]); };
    std::size_t peak = 0, fabric_peak = 0, motion_end = 0;
    for (std::size_t r = 0; r < ezz.size(); ++r) {
        if (ezz[r] < final_strain - 1e-12) motion_end = r;
        else continue;
        if (ratio(r) > ratio(peak)) peak = r;
        if (col.at("deviatoric_fabric")[r] > col.at("deviatoric_fabric")[fabric_peak]) fabric_peak = r;
    }
    auto late_mean = [&](auto value) {
        double sum = 0;
        int n = 0;
        for (std::size_t r = 0; r <= motion_end; ++r)
            if (ezz[r] >= 0.75 * final_strain) sum += value(r), ++n;
        return n ? sum / n : NAN;
    };
    auto C_ratio = [&](std::size_t r) { return col.at("C_n_" + zzzz)[r] / col.at("C_n_1111")[r]; };
    std::printf("| quantity | value |\n|---|---|\n");
    std::printf("| particles, dimension | %d, %dD |\n", int(run["parameters"]["particles"]), dim);
    std::printf("| peak stress ratio (s_zz - s_xx)/(s_zz + s_xx) | %.3f at eps_zz = %.3f |\n", ratio(peak), ezz[peak]);
    std::printf("| maximum deviatoric fabric | %.3f at eps_zz = %.3f (tr F there %.3f) |\n", col.at("deviatoric_fabric")[fabric_peak],
                ezz[fabric_peak], col.at("trF")[fabric_peak]);
    std::printf("| C_n_zzzz / C_n_1111 at the stress peak | %.3f |\n", C_ratio(peak));
    // Sec. 4.4's small entries: the fabric's tilt from the box axes and the odd stiffness entries
    // (2D), medians over the motion past eps_zz = 0.01.
    if (dim == 2) {
        std::vector<double> tilt, odd_1112, odd_1222;
        for (std::size_t r = 0; r <= motion_end; ++r) {
            if (ezz[r] < 0.01) continue;
            const double phi = std::fmod(std::abs(col.at("phi_F")[r]), M_PI / 2);  // a box axis every 90 degrees
            tilt.push_back(std::min(phi, M_PI / 2 - phi) * 180 / M_PI);
            odd_1112.push_back(std::abs(col.at("C_n_1112")[r]) / col.at("C_n_1111")[r]);
            odd_1222.push_back(std::abs(col.at("C_n_1222")[r]) / col.at("C_n_1111")[r]);
        }
        if (!tilt.empty())
            std::printf("| past eps_zz = 0.01, medians: fabric tilt from the box axes; abs(C_n_1112), abs(C_n_1222) over C_n_1111 | "
                        "%.1f degrees; %.4f, %.4f |\n",
                        biaxial::quantile(tilt, 0.5), biaxial::quantile(odd_1112, 0.5), biaxial::quantile(odd_1222, 0.5));
    }
    std::printf("| g2 (start, peak) | %.3f, %.3f |\n", col.at("g2")[0], col.at("g2")[peak]);
    std::printf("| volumetric strain (max compaction, end of motion) | %.4f, %.4f |\n",
                *std::max_element(col.at("volumetric_strain").begin(), col.at("volumetric_strain").begin() + motion_end + 1),
                col.at("volumetric_strain")[motion_end]);
    std::printf("| late stress ratio, deviatoric fabric, C_n_zzzz/C_n_1111 | %.3f, %.3f, %.3f |\n", late_mean(ratio),
                late_mean([&](std::size_t r) { return col.at("deviatoric_fabric")[r]; }), late_mean(C_ratio));
    std::printf("| late coordination, volume fraction | %.3f, %.4f |\n", late_mean([&](std::size_t r) { return col.at("coordination")[r]; }),
                late_mean([&](std::size_t r) { return col.at("volume_fraction")[r]; }));
    // tr F at the start, its highest value in the first 1e-4 of strain, and at the first row past 0.006.
    const auto& trF = col.at("trF");
    std::size_t early_high = 0, past = 0;
    for (std::size_t r = 0; r < ezz.size() && ezz[r] <= 1e-4; ++r)
        if (trF[r] > trF[early_high]) early_high = r;
    while (past + 1 < ezz.size() && ezz[past] < 0.006) ++past;
    std::printf("| tr F (start; highest before eps_zz = 1e-4; first row past eps_zz = 0.006) | %.3f; %.3f at eps_zz = %.2g; %.3f at %.4f |\n",
                trF[0], trF[early_high], ezz[early_high], trF[past], ezz[past]);
    const auto& time = col.at("time");
    const double t_end = time[motion_end];
    std::vector<double> ratios, szz;
    std::size_t first = motion_end, last = 0;
    for (std::size_t r = 0; r <= motion_end; ++r)
        if (time[r] >= 0.2 * t_end && time[r] <= 0.8 * t_end) {
            ratios.push_back(ratio(r));
            szz.push_back(sigma_zz[r]);
            first = std::min(first, r);
            last = r;
        }
    const int crossings = biaxial::upward_crossings(sigma_zz, biaxial::running_mean(sigma_zz, 25), first, last);
    std::printf("| middle 60%% of the motion (t = %.3g-%.3g s): stress ratio, 5th and 95th percentiles | %.3f, %.3f |\n",
                time[first], time[last], biaxial::quantile(ratios, 0.05), biaxial::quantile(ratios, 0.95));
    std::printf("| there: sigma_zz, 5th and 95th percentiles; upward crossings of its 25-row running mean, mean period | %.1f, %.1f %s; %d, %.2g s |\n",
                biaxial::quantile(szz, 0.05), biaxial::quantile(szz, 0.95), dim == 2 ? "N/m" : "Pa", crossings,
                crossings > 0 ? (time[last] - time[first]) / crossings : NAN);
    if (run.contains("quality")) {  // examples/biaxial/quality.hpp
        auto q = run["quality"];  // a copy: a missing figure reads as null, printed as nan
        auto list = [](const nlohmann::json& a) {
            std::string t;
            for (const auto& x : a) {
                char b[32];
                std::snprintf(b, sizeof b, "%s%.3g", t.empty() ? "" : " / ", x.is_number() ? double(x) : NAN);
                t += b;
            }
            return t;
        };
        auto number = [](const nlohmann::json& x) { return x.is_number() ? double(x) : NAN; };
        std::printf("| roughness of sigma_zz, of sigma_wall_zz | %.3f, %.3f |\n", number(q["roughness_sigma_zz"]),
                    number(q["roughness_sigma_wall_zz"]));
        std::printf("| side walls' mean push, fixed; controlled; controlled rms off p | %s; %s; %s |\n",
                    list(q["fixed_side_wall_mean"]).c_str(), list(q["controlled_side_wall_mean"]).c_str(),
                    list(q["controlled_side_wall_rms_deviation_over_p"]).c_str());
        std::printf("| inner-box over wall stress, median relative gap per axis; at rest before the loading | %s; %s |\n",
                    list(q["inner_minus_wall_stress_over_wall_stress_median"]).c_str(),
                    q.contains("inner_minus_wall_stress_over_wall_stress_at_rest")
                        ? list(q["inner_minus_wall_stress_over_wall_stress_at_rest"]).c_str()
                        : "-");
        std::printf("| damping's energy over the walls' work | %.3f |\n", number(q["damping_energy_over_wall_work"]));
    }
    std::printf("| cost | %.0f s wall, %.3g particle-steps/s, %.3g steps |\n", double(run["timing"]["wall_seconds"]),
                double(run["timing"].value("particle_steps_per_second", NAN)), double(run["timing"].value("steps", NAN)));
    if (!standard_output_complete())
        throw std::runtime_error("cannot write the table to standard output (is the disk full?)");
    return 0;
}

}  // namespace
