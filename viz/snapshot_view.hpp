#pragma once
// What render_snapshot draws where, shared with its test: the paper's colour map (Fig. 3), the
// colour scale of a series of frames, and the mapping from world coordinates to image pixels.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace viz {

/// The colour of a normalised potential energy u in [0, 1]: black (0), blue (1/3), green (2/3),
/// red (1), linear in between: "decaying from red, green (bright) to blue and black (dark)".
inline std::array<double, 3> energy_colour(double u) {
    u = std::clamp(u, 0.0, 1.0);
    static constexpr std::array<std::array<double, 3>, 4> stops{{{0, 0, 0}, {0, 0, 1}, {0, 1, 0}, {1, 0, 0}}};
    const double x = 3.0 * u;
    const int k = std::min(2, static_cast<int>(x));
    const double t = x - k;
    return {stops[k][0] + t * (stops[k + 1][0] - stops[k][0]), stops[k][1] + t * (stops[k + 1][1] - stops[k][1]),
            stops[k][2] + t * (stops[k + 1][2] - stops[k][2])};
}

inline constexpr std::array<double, 3> background = {1.0, 1.0, 1.0};

/// The value below which a share q (0..1) of `v` lies (the element at floor(q (n - 1)) in sorted
/// order); `v` is reordered. Needs a non-empty `v`.
inline double quantile(std::vector<double>& v, double q) {
    const auto k = static_cast<std::ptrdiff_t>(std::floor(q * double(v.size() - 1)));
    std::nth_element(v.begin(), v.begin() + k, v.end());
    return v[static_cast<std::size_t>(k)];
}

/// A colour scale for `values`: their extent, or with `robust` (one scale for every frame of a
/// series, from all their values) the smallest value to the 99th percentile, so that a few highly
/// loaded particles neither darken the rest nor move the scale from frame to frame. With `log`
/// only the positive values count (a logarithmic scale has no zero), and a robust scale starts at
/// their 1st percentile. {0, 0} when there is nothing to scale.
inline std::array<double, 2> colour_scale(std::vector<double> values, bool log, bool robust) {
    if (log) values.erase(std::remove_if(values.begin(), values.end(), [](double x) { return !(x > 0.0); }), values.end());
    if (values.empty()) return {0.0, 0.0};
    const double lo = robust && log ? quantile(values, 0.01) : *std::min_element(values.begin(), values.end());
    const double hi = robust ? quantile(values, 0.99) : *std::max_element(values.begin(), values.end());
    return {lo, hi};
}

/// The view: the box [lo, hi] (x, y of the image plane) fills the left 85% of the image (the
/// colour bar takes the rest) below a strip of `caption` pixels at the top, with a 5% margin on
/// its tighter side.
struct View {
    double cx, cy;      ///< world x at the middle of the drawing area, world y at the image's middle
    double half_height; ///< world half-height of the image (the camera's parallel scale)
    int width, height;

    static View fit(double xlo, double xhi, double ylo, double yhi, int width, int height, int caption = 0) {
        const int area_height = std::max(1, height - caption);
        const double area_aspect = 0.85 * width / area_height;
        const double half_area = 0.5 * 1.05 * std::max(yhi - ylo, (xhi - xlo) / area_aspect);
        const double metres_per_pixel = 2.0 * half_area / area_height;
        return {0.5 * (xlo + xhi), 0.5 * (ylo + yhi) + 0.5 * caption * metres_per_pixel, 0.5 * height * metres_per_pixel, width,
                height};
    }
    /// World x at the image centre (where the camera looks).
    double camera_x() const { return cx + (0.5 - 0.425) * width * (2.0 * half_height / height); }
    /// Pixel column and row (row 0 at the top) of a world point.
    std::array<int, 2> pixel(double x, double y) const {
        const double scale = 0.5 * height / half_height;  // pixels per metre
        const double px = 0.425 * width + (x - cx) * scale;
        const double py = 0.5 * height + (y - cy) * scale;
        return {static_cast<int>(std::floor(px)), height - 1 - static_cast<int>(std::floor(py))};
    }
};

}  // namespace viz
