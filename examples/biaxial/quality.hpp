#pragma once
// How quasi-static and how unbiased a biaxial loading was, from its time series: the figures
// run.json reports under "quality" and biaxial_summary prints.
//
// Over the motion of the top wall (eps_zz below its final value):
// - roughness of a column: the rms over the middle 60% of the motion (t from 0.2 to 0.8 of its
//   duration) of (x - m) / m, m the mean of x over the rows within +-0.005 of strain (NaN, null
//   in run.json, where fewer than three rows fall in that window);
// - the side walls: per lateral axis the mean push of the fixed (lower) and of the
//   stress-controlled (upper) wall, and the controlled wall's rms deviation from p, over the
//   whole motion;
// - the bias of the inner box: per axis the median of (sigma_kk - sigma_wall_kk) / sigma_wall_kk
//   over the middle 60% of the motion (sigma of the inner box, sigma_wall from the walls), and the
//   same gap at rest before the top wall moves (the first row): what the packing's structure gives
//   without any motion or drag, e.g. the looser layer next to a flat wall in a small 3D box;
// - the damping: the energy the damping policies removed over the motion, over the work the
//   walls did on the packing.
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "timeseries.hpp"

namespace biaxial {

struct LoadingQuality {
    double roughness_sigma_zz = NAN, roughness_sigma_wall_zz = NAN;
    std::vector<double> fixed_side_wall, controlled_side_wall;  ///< mean push over the area, per lateral axis
    std::vector<double> controlled_rms_deviation;              ///< relative to p, per lateral axis
    std::vector<double> inner_over_wall;                       ///< median relative gap, per axis
    std::vector<double> inner_over_wall_at_rest;               ///< the gap of the first row, per axis
    double damping_over_wall_work = NAN;
};

/// The roughness of `x` (see above) over rows [first, last] of the motion rows [0, motion_end].
inline double roughness(const std::vector<double>& x, const std::vector<double>& strain, std::size_t motion_end,
                        std::size_t first, std::size_t last) {
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t r = first; r <= last; ++r) {
        double mean = 0.0;
        std::size_t n = 0;
        for (std::size_t q = 0; q <= motion_end; ++q)
            if (std::abs(strain[q] - strain[r]) <= 0.005) mean += x[q], ++n;
        if (n < 3) return NAN;  // rows too far apart in strain for a running mean: no figure, rather than a false 0
        mean /= double(n);
        sum += (x[r] - mean) * (x[r] - mean) / (mean * mean);
        ++count;
    }
    return count ? std::sqrt(sum / double(count)) : NAN;
}

/// The quality figures of a loading's columns (read_timeseries); p the side pressure.
inline LoadingQuality loading_quality(const std::map<std::string, std::vector<double>>& col, int dim, double pressure,
                                      double final_strain) {
    LoadingQuality q;
    const std::string z = std::to_string(dim) + std::to_string(dim);
    const auto& strain = col.at("strain_" + z);
    const auto& time = col.at("time");
    std::size_t motion_end = 0;
    while (motion_end + 1 < strain.size() && strain[motion_end + 1] < final_strain - 1e-12) ++motion_end;
    const double duration = time[motion_end];
    std::size_t first = motion_end, last = 0;
    for (std::size_t r = 0; r <= motion_end; ++r)
        if (time[r] >= 0.2 * duration && time[r] <= 0.8 * duration) first = std::min(first, r), last = r;
    if (first > last) return q;  // too few rows
    q.roughness_sigma_zz = roughness(col.at("sigma_" + z), strain, motion_end, first, last);
    q.roughness_sigma_wall_zz = roughness(col.at("sigma_wall_" + z), strain, motion_end, first, last);
    for (int k = 1; k < dim; ++k) {
        const std::string kk = std::to_string(k) + std::to_string(k);
        const auto& lower = col.at("sigma_wall_" + kk + "_lower");
        const auto& upper = col.at("sigma_wall_" + kk + "_upper");
        double fixed = 0.0, controlled = 0.0, deviation = 0.0;
        for (std::size_t r = 0; r <= motion_end; ++r) {
            fixed += lower[r];
            controlled += upper[r];
            deviation += (upper[r] - pressure) * (upper[r] - pressure);
        }
        const double rows = double(motion_end + 1);
        q.fixed_side_wall.push_back(fixed / rows);
        q.controlled_side_wall.push_back(controlled / rows);
        q.controlled_rms_deviation.push_back(std::sqrt(deviation / rows) / pressure);
    }
    for (int k = 1; k <= dim; ++k) {
        const std::string kk = std::to_string(k) + std::to_string(k);
        const auto &inner = col.at("sigma_" + kk), &wall = col.at("sigma_wall_" + kk);
        std::vector<double> gaps;
        for (std::size_t r = first; r <= last; ++r) gaps.push_back((inner[r] - wall[r]) / wall[r]);
        q.inner_over_wall.push_back(quantile(gaps, 0.5));
        q.inner_over_wall_at_rest.push_back((inner[0] - wall[0]) / wall[0]);
    }
    const auto &damped = col.at("dissipated_background"), &work = col.at("work_by_walls");
    const double done = work[motion_end] - work[0];
    q.damping_over_wall_work = done != 0.0 ? (damped[motion_end] - damped[0]) / done : NAN;
    return q;
}

}  // namespace biaxial
