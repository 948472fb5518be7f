#pragma once
// Coarse-grained fields: the averages of micro_macro.hpp with a smooth kernel instead of a box,
// evaluated at the points of a grid, in the spirit of MercuryCG (Weinhart et al.).
//
// A contact's contributions (the same terms and weights as the box average) are spread around
// its contact point, or for the particle-centre rule around each partner's centre with that
// partner's share; particle volumes are spread around the centres. Each source's kernel is
// normalised on the grid (its values times the cell volume sum to one), so the grid integral of
// every field is exactly the box sum: sum_X field(X) dV / V equals the whole-box average.
#include <array>
#include <cmath>
#include <concepts>
#include <numbers>
#include <vector>

#include "micromacro/averaging/contact_sums.hpp"
#include "micromacro/averaging/micro_macro.hpp"

namespace micromacro {

/// A coarse-graining kernel: its value at distance r (per volume, integrating to one in dim
/// dimensions) and the radius beyond which it is zero. A new kernel is one struct with these two;
/// coarse_grain normalises each source's weights on the grid, so a kernel's own normalisation
/// only needs to be close.
template <class K>
concept CoarseGrainingKernel = requires(const K& k, double r) {
    { k.support() } -> std::convertible_to<double>;
    { k.template value<2>(r) } -> std::convertible_to<double>;
    { k.template value<3>(r) } -> std::convertible_to<double>;
};

/// Gaussian exp(-r^2 / (2 w^2)) / (2 pi w^2)^(dim/2), cut at 4 w (the weight beyond is below 3e-4
/// and goes to the grid normalisation).
struct GaussianKernel {
    double width;  ///< w, the standard deviation (m)
    double support() const { return 4.0 * width; }
    template <int dim>
    double value(double r) const {
        return std::exp(-0.5 * r * r / (width * width)) / std::pow(2.0 * std::numbers::pi * width * width, 0.5 * dim);
    }
};

/// Lucy's polynomial A (1 + 3 r/c)(1 - r/c)^3 for r < c, with A = 5/(pi c^2) in 2D and
/// 105/(16 pi c^3) in 3D so that it integrates to one.
struct LucyKernel {
    double width;  ///< c, the support radius (m)
    double support() const { return width; }
    template <int dim>
    double value(double r) const {
        if (r >= width) return 0.0;
        const double q = r / width;
        const double norm = dim == 2 ? 5.0 / (std::numbers::pi * width * width)
                                     : 105.0 / (16.0 * std::numbers::pi * width * width * width);
        return norm * (1.0 + 3.0 * q) * std::pow(1.0 - q, 3);
    }
};

static_assert(CoarseGrainingKernel<GaussianKernel>);
static_assert(CoarseGrainingKernel<LucyKernel>);

/// Mean particle diameter: kernel widths are usually given in diameters, w = n * mean_diameter(s).
template <int dim>
double mean_diameter(const PackingSnapshot<dim>& s) {
    double sum = 0.0;
    for (double r : s.radius) sum += 2.0 * r;
    return s.radius.empty() ? 0.0 : sum / static_cast<double>(s.radius.size());
}

template <int dim>
struct Grid {
    Vec<dim> lo;                 ///< first point
    Vec<dim> spacing;            ///< between points
    std::array<int, dim> count;  ///< points per axis

    /// Cell-centred points covering [lo, hi]: n points per axis.
    static Grid covering(const Vec<dim>& lo, const Vec<dim>& hi, std::array<int, dim> n) {
        Grid g;
        for (int a = 0; a < dim; ++a) {
            if (n[a] < 1) detail::throw_input_error("grid: axis ", a, " has ", n[a], " points; need at least 1");
            g.spacing[a] = (hi[a] - lo[a]) / n[a];
            g.lo[a] = lo[a] + 0.5 * g.spacing[a];
            g.count[a] = n[a];
        }
        return g;
    }
    std::size_t size() const {
        std::size_t s = 1;
        for (int c : count) s *= static_cast<std::size_t>(c);
        return s;
    }
    double cell_volume() const { return spacing.prod(); }
    /// Point number `index`; axis 0 runs fastest.
    Vec<dim> point(std::size_t index) const {
        Vec<dim> x;
        for (int a = 0; a < dim; ++a) {
            x[a] = lo[a] + spacing[a] * static_cast<double>(index % count[a]);
            index /= count[a];
        }
        return x;
    }
};

template <int dim>
struct CoarseGrainedFields {
    Grid<dim> grid;
    std::vector<double> volume_fraction;
    std::vector<Tensor2<dim>> fabric, stress_normal, stress_tangential;
    std::vector<Tensor4<dim>> stiffness_normal, stiffness_tangential;

    /// Every number of every field, in one order, for a sum over processes.
    template <class F>
    void for_each_number(F&& f) {
        for (double& x : volume_fraction) f(x);
        for (auto* field : {&fabric, &stress_normal, &stress_tangential})
            for (auto& t : *field)
                for (int k = 0; k < dim * dim; ++k) f(t.data()[k]);
        for (auto* field : {&stiffness_normal, &stiffness_tangential})
            for (auto& t : *field)
                for (int k = 0; k < dim * dim * dim * dim; ++k) f(t.data()[k]);
    }
};

namespace detail {
/// Calls f(grid index, normalised weight) for every grid point within the kernel's support of x
/// (minimum image on periodic axes, each point at most once even if the support exceeds the period).
template <int dim, class Kernel, class F>
void spread(const Grid<dim>& g, const Domain<dim>& domain, const Kernel& kernel, const Vec<dim>& x, F&& f,
            std::vector<std::pair<std::size_t, double>>& scratch) {
    scratch.clear();
    std::array<int, dim> first, last;
    for (int a = 0; a < dim; ++a) {
        first[a] = static_cast<int>(std::floor((x[a] - kernel.support() - g.lo[a]) / g.spacing[a]));
        last[a] = static_cast<int>(std::ceil((x[a] + kernel.support() - g.lo[a]) / g.spacing[a]));
        if (!domain.periodic(a)) {
            first[a] = std::max(first[a], 0);
            last[a] = std::min(last[a], g.count[a] - 1);
        } else if (last[a] - first[a] + 1 > g.count[a]) {
            last[a] = first[a] + g.count[a] - 1;  // the support covers the period: each point once
        }
    }
    double total = 0.0;
    std::array<int, dim> i = first;
    while (true) {
        std::size_t index = 0, stride = 1;
        Vec<dim> p;
        for (int a = 0; a < dim; ++a) {
            const int wrapped = ((i[a] % g.count[a]) + g.count[a]) % g.count[a];
            index += stride * static_cast<std::size_t>(wrapped);
            stride *= static_cast<std::size_t>(g.count[a]);
            p[a] = g.lo[a] + g.spacing[a] * wrapped;
        }
        const double w = kernel.template value<dim>(domain.separation(p, x).norm());
        if (w > 0.0) {
            scratch.emplace_back(index, w);
            total += w;
        }
        int a = 0;
        for (; a < dim; ++a) {
            if (++i[a] <= last[a]) break;
            i[a] = first[a];
        }
        if (a == dim) break;
    }
    if (total == 0.0)
        throw_input_error("coarse graining: the kernel (support ", kernel.support(), " m) reaches no grid point from a source; "
                          "use a finer grid or a wider kernel");
    for (const auto& [index, w] : scratch) f(index, w / total);
}
}  // namespace detail

/// Coarse-grained fields of the packing on `grid` (sources outside the grid's reach are an
/// error; periodic axes wrap), from the particles and contacts of `share` (null: all), the
/// contacts counted as `cw` counts them (contact_weights; every counted contact enters whole):
/// a process's part of a packing split over processes, whose fields add up to the whole's.
template <int dim, CoarseGrainingKernel Kernel>
CoarseGrainedFields<dim> coarse_grain(const PackingSnapshot<dim>& s, const Grid<dim>& grid, const Kernel& kernel,
                                      const AveragingOptions& opt, const ContactWeights<dim>& cw,
                                      const AveragingShare* share) {
    detail::require_positive(kernel.support(), "kernel support", "give the width in m (about one particle diameter)");
    CoarseGrainedFields<dim> out;
    out.grid = grid;
    const std::size_t n = grid.size();
    out.volume_fraction.assign(n, 0.0);
    const double dV = grid.cell_volume();
    std::vector<std::pair<std::size_t, double>> scratch;

    for (std::size_t p = 0; p < s.size(); ++p)
        if (!share || share->particle[p])
            detail::spread(grid, s.domain, kernel, detail::wrapped(s, s.position[p]),
                           [&](std::size_t x, double w) { out.volume_fraction[x] += w / dV * DimTraits<dim>::particle_volume(s.radius[p]); },
                           scratch);

    // Every contact counts (weight 1 or its partners' shares): the box around the whole packing.
    std::vector<ContactSums<dim>> sums(n);
    for (std::size_t q = 0; q < s.contacts.size(); ++q) {
        const auto& c = s.contacts[q];
        if (!cw.counted[q] || (share && !share->contact[q])) continue;
        const bool tangential_stiffness = !(opt.exclude_sliding_from_tangential_stiffness && c.sliding);
        auto add = [&](const Vec<dim>& at, double share, double volume_share) {
            detail::spread(grid, s.domain, kernel, detail::wrapped(s, at), [&](std::size_t x, double w) {
                const double wv = w / dV;
                sums[x].add(c, wv * share, wv * volume_share, tangential_stiffness);
            }, scratch);
        };
        const double vi = DimTraits<dim>::particle_volume(s.radius[c.i]);
        const double vj = c.wall ? 0.0 : DimTraits<dim>::particle_volume(s.radius[c.j]);
        if (opt.rule == SelectionRule::contact_point) {
            add(c.point, 1.0, vi + vj);
        } else {
            add(s.position[c.i], c.share_i, vi);
            if (!c.wall) add(s.position[c.j], 1.0 - c.share_i, vj);
        }
    }
    out.fabric.reserve(n);
    out.stress_normal.reserve(n);
    out.stress_tangential.reserve(n);
    out.stiffness_normal.reserve(n);
    out.stiffness_tangential.reserve(n);
    for (const auto& x : sums) {
        out.fabric.push_back(x.fabric);
        out.stress_normal.push_back(x.stress_normal);
        out.stress_tangential.push_back(x.stress_tangential);
        out.stiffness_normal.push_back(x.stiffness_normal);
        out.stiffness_tangential.push_back(x.stiffness_tangential);
    }
    return out;
}

template <int dim, CoarseGrainingKernel Kernel>
CoarseGrainedFields<dim> coarse_grain(const PackingSnapshot<dim>& s, const Grid<dim>& grid, const Kernel& kernel,
                                      const AveragingOptions& opt = {}) {
    return coarse_grain(s, grid, kernel, opt, contact_weights(s, Region<dim>::whole(s), opt), nullptr);
}

}  // namespace micromacro
