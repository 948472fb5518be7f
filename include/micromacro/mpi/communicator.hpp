#pragma once
// A Cartesian communicator over a box: the ranks arranged in dims[a] slabs per axis by
// MPI_Dims_create and MPI_Cart_create (periodic axes wrap across ranks), each rank's place in
// the split (CartesianSplit) and its neighbours across each face. Needs MPI (the optional
// micromacro::mpi target).
#include <algorithm>
#include <array>
#include <cstddef>
#include <functional>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include <mpi.h>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/domain.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/mpi/cartesian_split.hpp"

namespace micromacro::mpi {

/// Throws with MPI's own message when an MPI call fails (MPI_ERRORS_RETURN is set on the
/// communicators made here).
inline void check(int code, const char* what) {
    if (code == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(code, text, &length);
    micromacro::detail::throw_input_error(what, " failed: ", std::string(text, static_cast<std::size_t>(length)));
}

/// MPI for the life of the object: MPI_Init when made (with main's arguments, or none), and
/// MPI_Finalize when it goes. A program's main, or a test module's global fixture, holds one.
class Runtime {
public:
    Runtime() { MPI_Init(nullptr, nullptr); }
    Runtime(int& argc, char**& argv) { MPI_Init(&argc, &argv); }
    ~Runtime() { MPI_Finalize(); }
    Runtime(const Runtime&) = delete;
    Runtime& operator=(const Runtime&) = delete;
};

template <int dim>
class CartesianComm {
public:
    /// The ranks of `parent` over `box`; dims fixed per axis where `dims` is positive, the rest
    /// chosen by MPI_Dims_create (as even a split as the rank count allows). With none fixed,
    /// the most slabs go along the longest axis (of equal ones, the last): the axis the engine's
    /// spatial order runs slowest along (neighbors/spatial_order.hpp), so that a rank's particles
    /// keep the serial run's long rows in memory (rows cut in half ran 0.92x, docs/performance.md).
    CartesianComm(MPI_Comm parent, const Domain<dim>& box, std::array<int, dim> dims = {}) {
        int size = 0;
        check(MPI_Comm_size(parent, &size), "MPI_Comm_size");
        size_ = size;
        const bool chosen = std::all_of(dims.begin(), dims.end(), [](int d) { return d == 0; });
        check(MPI_Dims_create(size, dim, dims.data()), "MPI_Dims_create");
        if (chosen) {  // MPI_Dims_create's counts, largest first, onto the axes, longest first
            std::array<int, dim> axes;
            std::iota(axes.begin(), axes.end(), 0);
            std::stable_sort(axes.begin(), axes.end(), [&](int a, int b) {
                return box.length(a) > box.length(b) || (box.length(a) == box.length(b) && a > b);
            });
            std::array<int, dim> counts = dims;
            std::sort(counts.begin(), counts.end(), std::greater<int>());
            for (int k = 0; k < dim; ++k) dims[axes[k]] = counts[k];
        }
        std::array<int, dim> periods{};
        for (int a = 0; a < dim; ++a) periods[a] = box.periodic(a) ? 1 : 0;
        check(MPI_Cart_create(parent, dim, dims.data(), periods.data(), 0, &comm_), "MPI_Cart_create");
        MPI_Comm_set_errhandler(comm_, MPI_ERRORS_RETURN);
        check(MPI_Comm_rank(comm_, &rank_), "MPI_Comm_rank");
        std::array<int, dim> coords{};
        check(MPI_Cart_coords(comm_, rank_, dim, coords.data()), "MPI_Cart_coords");
        split_ = CartesianSplit<dim>::of(box, dims, coords);
        for (int a = 0; a < dim; ++a) check(MPI_Cart_shift(comm_, a, 1, &below_[a], &above_[a]), "MPI_Cart_shift");
    }
    CartesianComm(const CartesianComm&) = delete;
    CartesianComm& operator=(const CartesianComm&) = delete;
    ~CartesianComm() { MPI_Comm_free(&comm_); }

    MPI_Comm comm() const { return comm_; }
    int rank() const { return rank_; }
    int size() const { return size_; }
    const CartesianSplit<dim>& split() const { return split_; }
    /// The rank whose subdomain owns position x.
    int owner(const Vec<dim>& x) const {
        std::array<int, dim> coords{};
        for (int a = 0; a < dim; ++a) coords[a] = split_.slab(a, x[a]);
        int rank = 0;
        check(MPI_Cart_rank(comm_, coords.data(), &rank), "MPI_Cart_rank");
        return rank;
    }
    /// Moves the split's box to [lo, hi] along the axes where `along` is true (open axes; each
    /// rank keeps its place in the split).
    void move_box(const Vec<dim>& lo, const Vec<dim>& hi, const std::array<bool, dim>& along) {
        for (int a = 0; a < dim; ++a)
            if (along[a]) split_.lo[a] = lo[a], split_.hi[a] = hi[a];
    }
    /// The inner boundaries along axis a as fractions of the box (CartesianSplit::cuts; each
    /// rank keeps its place in the split).
    void set_cuts(int a, std::vector<double> cuts) { split_.cuts[a] = std::move(cuts); }
    /// The rank across the lower (direction -1) or upper (+1) face along axis a; MPI_PROC_NULL
    /// at an open box's end. With one slab on a periodic axis, this rank itself.
    int neighbour(int a, int direction) const { return direction < 0 ? below_[a] : above_[a]; }

private:
    MPI_Comm comm_ = MPI_COMM_NULL;
    int rank_ = 0, size_ = 1;
    CartesianSplit<dim> split_{};
    std::array<int, dim> below_{}, above_{};
};

/// Adds `sums` over the ranks of `comm`, number by number (its for_each_number), on every rank.
template <class Sums>
void add_over_ranks(Sums& sums, MPI_Comm comm, const char* what) {
    std::vector<double> numbers;
    sums.for_each_number([&](double& x) { numbers.push_back(x); });
    check(MPI_Allreduce(MPI_IN_PLACE, numbers.data(), static_cast<int>(numbers.size()), MPI_DOUBLE, MPI_SUM, comm), what);
    std::size_t k = 0;
    sums.for_each_number([&](double& x) { x = numbers[k++]; });
}

}  // namespace micromacro::mpi
