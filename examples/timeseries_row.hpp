#pragma once
// A row of a program's timeseries.csv, and the columns biaxial and element_test share, named the
// same way in both: components by 1-based indices ("sigma_13", "C_n_1122").
#include <initializer_list>
#include <string>
#include <vector>

#include <micromacro/averaging/anisotropy.hpp>
#include <micromacro/averaging/micro_macro.hpp>

namespace micromacro::cli {

/// One row of the time series: named columns, in order.
struct Row {
    std::vector<std::string> names;
    std::vector<double> values;
    void add(const std::string& name, double value) {
        names.push_back(name);
        values.push_back(value);
    }
};

/// "13" for the indices (0, 2): a column's 1-based component name.
inline std::string component(std::initializer_list<int> indices) {
    std::string name;
    for (int i : indices) name += std::to_string(i + 1);
    return name;
}

/// The stiffness of Eq. 9 in N/m (2D) or Pa (3D), one column per independent entry: C^n has minor
/// and major symmetry (C_n_abcd with a <= b, c <= d, ab <= cd), C^t only major symmetry (C_t_abcd
/// with ab <= cd over all index pairs).
template <int dim>
void add_stiffness_columns(Row& r, const MicroMacro<dim>& m) {
    for (int a = 0; a < dim; ++a)
        for (int b = a; b < dim; ++b)
            for (int c = 0; c < dim; ++c)
                for (int d = c; d < dim; ++d)
                    if (a * dim + b <= c * dim + d) r.add("C_n_" + component({a, b, c, d}), m.stiffness_normal(a, b, c, d));
    for (int p = 0; p < dim * dim; ++p)
        for (int q = p; q < dim * dim; ++q)
            r.add("C_t_" + component({p / dim, p % dim, q / dim, q % dim}), m.stiffness_tangential(p / dim, p % dim, q / dim, q % dim));
}

/// The anisotropy coefficients (averaging/anisotropy.hpp): a_c, a_n, a_t (2D the Fourier
/// coefficients, 3D sqrt(3/2 a : a)), and in 2D their major directions theta_c, theta_n, theta_t
/// (rad from axis 1).
template <int dim>
void add_anisotropy_columns(Row& r, const Anisotropy<dim>& a) {
    r.add("a_c", a.a_c);
    r.add("a_n", a.a_n);
    r.add("a_t", a.a_t);
    if constexpr (dim == 2) {
        r.add("theta_c", a.theta_c);
        r.add("theta_n", a.theta_n);
        r.add("theta_t", a.theta_t);
    }
}

}  // namespace micromacro::cli
