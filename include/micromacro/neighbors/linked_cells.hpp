#pragma once
// Linked-cell neighbour search, O(N) for a bounded size ratio.
//
// Cells are at least one interaction range (largest diameter + skin) wide, so every partner of
// a particle lies in its own or an adjacent cell. Particles are binned with a counting sort, so
// a search allocates only when the particle number or the cell count grows.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "micromacro/core/index.hpp"
#include "micromacro/core/domain.hpp"

namespace micromacro {

class LinkedCells {
public:
    template <int dim, class Real>
    void find_pairs(const std::vector<Vec<dim, Real>>& x, const std::vector<Real>& r, const Domain<dim>& domain,
                    double skin, std::vector<IndexPair>& out) {
        const auto n = static_cast<Index>(x.size());
        if (n < 2) return;
        const double range = 2.0 * double(*std::max_element(r.begin(), r.end())) + skin;

        // Grid: the periodic box on periodic axes, the particles' bounding box elsewhere.
        std::array<double, dim> lo{}, extent{}, size{};
        std::array<int, dim> cells{};
        double total_cells = 1.0;
        for (int k = 0; k < dim; ++k) {
            double a, b;
            if (domain.periodic(k)) {
                a = domain.lo()[k];
                b = domain.hi()[k];
            } else {
                a = b = x[0][k];
                for (const auto& p : x) {
                    a = std::min(a, double(p[k]));
                    b = std::max(b, double(p[k]));
                }
            }
            lo[k] = a;
            extent[k] = b - a;
            cells[k] = std::max(1, static_cast<int>(std::floor((b - a) / range)));
            total_cells *= cells[k];
        }
        // A particle that flew far away must not make the grid huge: coarsen until there are
        // at most a few cells per particle (cells stay wider than the range, so still correct).
        while (total_cells > 4.0 * n + 64) {
            total_cells = 1.0;
            for (int k = 0; k < dim; ++k) {
                if (!domain.periodic(k) || cells[k] > 1) cells[k] = std::max(1, cells[k] / 2);
                total_cells *= cells[k];
            }
        }
        for (int k = 0; k < dim; ++k)
            size[k] = domain.periodic(k) ? extent[k] / cells[k] : std::max(range, extent[k] / cells[k]);

        // Counting sort of the particles into cells.
        cell_of_.resize(n);
        cell_start_.assign(static_cast<std::size_t>(total_cells) + 1, 0);
        for (Index i = 0; i < n; ++i) {
            cell_of_[i] = linear_index<dim>(coords<dim>(x[i], lo, size, cells), cells);
            ++cell_start_[cell_of_[i] + 1];
        }
        for (std::size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
        sorted_.resize(n);
        fill_.assign(cell_start_.begin(), cell_start_.end() - 1);
        for (Index i = 0; i < n; ++i) sorted_[fill_[cell_of_[i]]++] = i;

        std::array<int, most_cells(dim)> neighbours{};
        std::vector<Index>& partners = partners_;
        for (Index i = 0; i < n; ++i) {
            const auto c = coords<dim>(x[i], lo, size, cells);
            int count = 0;
            if (domain.tilted())
                count = tilted_neighbours<dim>(convert<double>(x[i]), c, domain, lo, size, cells, range, neighbours);
            else for (int s = 0; s < ipow3(dim); ++s) {
                std::array<int, dim> nc{};
                bool inside = true;
                for (int k = 0, t = s; k < dim; ++k, t /= 3) {
                    nc[k] = c[k] + t % 3 - 1;
                    if (domain.periodic(k)) nc[k] = (nc[k] + cells[k]) % cells[k];
                    else if (nc[k] < 0 || nc[k] >= cells[k]) inside = false;
                }
                if (!inside) continue;
                const int id = linear_index<dim>(nc, cells);
                // With fewer than three cells on a periodic axis two offsets reach the same cell.
                if (std::find(neighbours.begin(), neighbours.begin() + count, id) == neighbours.begin() + count)
                    neighbours[count++] = id;
            }
            partners.clear();
            for (int q = 0; q < count; ++q)
                for (Index s = cell_start_[neighbours[q]]; s < cell_start_[neighbours[q] + 1]; ++s) {
                    const Index j = sorted_[s];
                    if (j <= i) continue;
                    const double reach = double(r[i]) + double(r[j]) + skin;
                    if (domain.separation(convert<double>(x[i]), convert<double>(x[j])).squaredNorm() < reach * reach)
                        partners.push_back(j);
                }
            std::sort(partners.begin(), partners.end());
            for (Index j : partners) out.push_back({i, j});
        }
    }

private:
    static constexpr int ipow3(int d) { return d == 2 ? 9 : 27; }
    // Room for four cells per axis: an interval two ranges long spans three cells at most, and a
    // rounding at its ends may add one.
    static constexpr int most_cells(int d) { return d == 2 ? 16 : 64; }

    // The cells a partner of a particle at p (in cell c) can lie in, in a box with Lees-Edwards
    // images (Domain::tilt): across the faces of a periodic axis k a partner's image is shifted by
    // the tilts along the lower axes, so from the last axis down each axis takes the cells of the
    // interval within `range` of p less the shift the images chosen so far add (at most three
    // cells, which are at least a range wide), and the image each cell lies in adds its shift to
    // the axes below. Open axes take the cells next to c, as without tilt. Returns the count.
    template <int dim>
    static int tilted_neighbours(const Vec<dim>& p, const std::array<int, dim>& c, const Domain<dim>& domain,
                                 const std::array<double, dim>& lo, const std::array<double, dim>& size,
                                 const std::array<int, dim>& cells, double range, std::array<int, most_cells(dim)>& out) {
        int count = 0;
        std::array<int, dim> at{};
        const auto visit = [&](const auto& self, int k, Vec<dim> shift) -> void {
            if (k < 0) {
                const int id = linear_index<dim>(at, cells);
                if (std::find(out.begin(), out.begin() + count, id) == out.begin() + count) out[count++] = id;
                return;
            }
            int first = c[k] - 1, last = c[k] + 1;
            if (domain.periodic(k)) {
                first = static_cast<int>(std::floor((p[k] - shift[k] - range - lo[k]) / size[k]));
                last = static_cast<int>(std::floor((p[k] - shift[k] + range - lo[k]) / size[k]));
            }
            for (int b = first; b <= last; ++b) {
                Vec<dim> next = shift;
                if (domain.periodic(k)) {
                    const int image = b >= 0 ? b / cells[k] : -((-b - 1) / cells[k]) - 1;  // floor(b / cells)
                    at[k] = b - image * cells[k];
                    for (int i = 0; i < k; ++i) next[i] += image * domain.tilt(i, k);
                } else {
                    if (b < 0 || b >= cells[k]) continue;
                    at[k] = b;
                }
                self(self, k - 1, next);
            }
        };
        visit(visit, dim - 1, Vec<dim>::Zero());
        return count;
    }

    template <int dim, class Real>
    static std::array<int, dim> coords(const Vec<dim, Real>& p, const std::array<double, dim>& lo,
                                       const std::array<double, dim>& size, const std::array<int, dim>& cells) {
        std::array<int, dim> c{};
        for (int k = 0; k < dim; ++k)
            c[k] = std::clamp(static_cast<int>(std::floor((double(p[k]) - lo[k]) / size[k])), 0, cells[k] - 1);
        return c;
    }

    template <int dim>
    static int linear_index(const std::array<int, dim>& c, const std::array<int, dim>& cells) {
        int id = 0;
        for (int k = dim - 1; k >= 0; --k) id = id * cells[k] + c[k];
        return id;
    }

    std::vector<int> cell_of_;
    std::vector<Index> cell_start_, fill_, sorted_, partners_;
};

}  // namespace micromacro
