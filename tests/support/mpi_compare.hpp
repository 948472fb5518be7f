#pragma once
// The MPI tests' measure of how far a distributed run is from the serial run of the same scene:
// the largest difference of any particle's state, found by global id.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <tuple>

#include <micromacro/mpi/distributed_run.hpp>

namespace mmtest {

namespace mm = micromacro;

/// The largest difference of `other`'s particles from `serial`'s, by global id (the serial
/// scene's particle id, Particles::id), in position (over a radius), velocity, angular velocity, force and torque
/// (over the serial run's largest).
template <class Sim, class Get>
double largest_difference(const Sim& serial, std::size_t n, Get&& get) {
    constexpr int dim = Sim::dimension;
    const auto& s = serial.particles();
    double v_scale = 0, f_scale = 0, w_scale = 0, t_scale = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
        v_scale = std::max(v_scale, s.velocity()[i].norm());
        f_scale = std::max(f_scale, s.force()[i].norm());
        w_scale = std::max(w_scale, std::sqrt(mm::DimTraits<dim>::squared_norm(s.template get<mm::field::AngularVelocity>()[i])));
        t_scale = std::max(t_scale, std::sqrt(mm::DimTraits<dim>::squared_norm(s.template get<mm::field::Torque>()[i])));
    }
    const auto index = s.index_by_id();
    double worst = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
        const auto [global, x, v, w, f, t] = get(k);
        const std::size_t id = index[global];
        const mm::Angular<dim> dw = w - s.template get<mm::field::AngularVelocity>()[id];
        const mm::Angular<dim> dt = t - s.template get<mm::field::Torque>()[id];
        worst = std::max({worst, serial.domain().separation(x, s.position()[id]).norm() / 1e-3,
                          (v - s.velocity()[id]).norm() / v_scale, (f - s.force()[id]).norm() / f_scale,
                          std::sqrt(mm::DimTraits<dim>::squared_norm(dw)) / w_scale,
                          std::sqrt(mm::DimTraits<dim>::squared_norm(dt)) / t_scale});
    }
    return worst;
}

template <class Sim>
double from_distributed(const Sim& serial, const mm::mpi::DistributedRun<Sim>& run) {
    const auto& p = run.local().particles();
    return largest_difference(serial, run.owned(), [&](std::size_t i) {
        return std::tuple{static_cast<std::size_t>(run.global_id(i)), p.position()[i], p.velocity()[i],
                          p.template get<mm::field::AngularVelocity>()[i], p.force()[i], p.template get<mm::field::Torque>()[i]};
    });
}

}  // namespace mmtest
