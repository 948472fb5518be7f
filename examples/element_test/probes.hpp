#pragma once
// Stress probes from a packing at rest: a small strain increment in each of a few directions, and
// the stress change it brings, four ways:
//   cell:      the cell deformed along the increment at the loading's rate by CellControl, then
//              held while the packing relaxes (the element test's own probe);
//   relaxed:   every particle and the cell mapped affinely at once, then relaxed at fixed cell;
//   affine:    the frozen affine probe (averaging/affine_probe.hpp), no particle relaxing;
//   predicted: (C^n + C^t) : eps, the averaged stiffness of Eq. 9 before the increment.
// Strains are compression positive (eps = 1 - F, symmetric part); a shear increment eps_ik = e
// is made by F_ik = -2 e (i < k), which adds a rotation by e whose stress change, of order
// e sigma, is p/k smaller than the response.
#include <cmath>
#include <string>
#include <vector>

#include "experiment.hpp"

namespace element_test {

template <int dim>
struct ProbeDirection {
    std::string name;
    mm::Tensor2<dim> eps;  ///< unit Frobenius norm, symmetric
};

template <int dim>
std::vector<ProbeDirection<dim>> probe_directions() {
    using T = mm::Tensor2<dim>;
    auto unit = [](T t) { return T(t / t.norm()); };
    auto diag = [](std::initializer_list<double> d) {
        T t = T::Zero();
        int k = 0;
        for (double v : d) t(k, k) = v, ++k;
        return t;
    };
    auto shear = [](int i, int k) {
        T t = T::Zero();
        t(i, k) = t(k, i) = 1.0;
        return t;
    };
    if constexpr (dim == 2)
        return {{"isotropic", unit(diag({1, 1}))}, {"axial", diag({0, 1})},        {"lateral", diag({1, 0})},
                {"deviatoric", unit(diag({-1, 1}))}, {"shear_12", unit(shear(0, 1))}};
    else
        return {{"isotropic", unit(diag({1, 1, 1}))}, {"axial", diag({0, 0, 1})}, {"deviatoric", unit(diag({-1, -1, 2}))},
                {"shear_13", unit(shear(0, 2))}, {"shear_12", unit(shear(0, 1))}};
}

/// The cell's deformation gradient of the increment eps: upper triangular, as the cell allows.
template <int dim>
Eigen::Matrix<double, dim, dim> probe_deformation(const mm::Tensor2<dim>& eps) {
    Eigen::Matrix<double, dim, dim> F = Eigen::Matrix<double, dim, dim>::Identity();
    for (int k = 0; k < dim; ++k) {
        F(k, k) -= eps(k, k);
        for (int i = 0; i < k; ++i) F(i, k) = -2.0 * eps(i, k);
    }
    return F;
}

template <int dim>
struct ProbeResult {
    std::string name;
    mm::Tensor2<dim> eps;
    mm::Tensor2<dim> cell, relaxed, affine, predicted;  ///< stress changes
    std::size_t relaxation_steps = 0;                   ///< of the cell probe
};

/// The probes of the packing `exp` holds (at rest, cell still). Each runs on a copy.
template <int dim>
std::vector<ProbeResult<dim>> run_probes(const Experiment<dim>& exp) {
    using Sim = typename Experiment<dim>::Sim;
    const Config& c = exp.config();
    const auto symmetric = [](const mm::Tensor2<dim>& s) { return mm::Tensor2<dim>(0.5 * (s + s.transpose())); };
    const auto before = mm::CellControl<dim>::measure(exp.simulation());
    const auto snapshot = mm::take_snapshot(exp.simulation());
    // Relaxed: the fluctuating kinetic energy below rest_ratio of the elastic energy, after at
    // least 20 contact durations (a packing just mapped affinely is still at rest, not relaxed).
    const auto relax = [&](Sim& sim) {
        const std::size_t contact = std::llround(c.contact_duration() / sim.time_step());
        std::size_t steps = 20 * contact;
        sim.run(steps);
        const std::size_t limit = 20000 * contact;  // 2e4 contact durations
        for (; steps < limit; steps += 100) {
            const auto e = sim.energy();
            if (kinetic_relative_to_flow(sim) < c.rest_ratio * (e.elastic_normal + e.elastic_tangential)) return steps;
            sim.run(100);
        }
        mm::throw_input_error("a probe did not relax within ", limit, " steps; raise --gamma-b or --rest-ratio");
    };
    std::vector<ProbeResult<dim>> results;
    for (const auto& d : probe_directions<dim>()) {
        ProbeResult<dim> r;
        r.name = d.name;
        r.eps = c.probe_strain * d.eps;
        const auto F = probe_deformation(r.eps);
        {  // the cell, at the loading's rate along the increment, then held
            Sim sim = exp.simulation();
            mm::CellControl<dim> drive(0.0, c.max_rate());
            const double span = c.probe_strain / c.rate();
            for (int k = 0; k < dim; ++k)
                for (int i = 0; i <= k; ++i) {
                    const double goal = F(i, k) - (i == k ? 1.0 : 0.0);
                    drive.strain_path(i, k, [=](double t) { return goal * std::min(1.0, t / span); });
                }
            drive.run(sim, std::max<std::size_t>(1, std::llround(span / sim.time_step())));
            sim.set_velocity_gradient(Eigen::Matrix<double, dim, dim>::Zero());
            r.relaxation_steps = relax(sim);
            r.cell = symmetric(mm::CellControl<dim>::measure(sim).stress - before.stress);
        }
        {  // every particle and the cell mapped at once, then relaxed
            Sim sim = exp.simulation();
            sim.deform_affinely(F);
            relax(sim);
            r.relaxed = symmetric(mm::CellControl<dim>::measure(sim).stress - before.stress);
        }
        const auto frozen = mm::affine_response(snapshot, mm::Region<dim>::whole(snapshot), r.eps, {}, c.mu);
        r.affine = frozen.stress_change;
        r.predicted = frozen.predicted;
        results.push_back(r);
    }
    return results;
}

}  // namespace element_test
