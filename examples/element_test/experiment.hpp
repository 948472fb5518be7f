#pragma once
// An element test in a periodic cell: a packing (a fresh gas, or particles read from a file)
// compressed isotropically to the pressure p by the cell's stress servo until it rests (the
// preparation), then driven along the preset's path by CellControl (engine/cell_control.hpp),
// one time-series row at a time. Every average is over the whole cell, kinetic stress included.
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <micromacro/io/packing_files.hpp>
#include <micromacro/micromacro.hpp>

#include "../timeseries_row.hpp"
#include "config.hpp"

namespace element_test {

using mm::cli::Row;
inline constexpr auto idx = &mm::cli::component;  ///< "13" for the indices (0, 2)

/// Particles in a periodic cell, before they become a scene.
template <int dim>
struct Packing {
    mm::Domain<dim> cell = mm::Domain<dim>::fully_periodic(mm::Vec<dim>::Zero(), mm::Vec<dim>::Ones());
    std::vector<mm::Vec<dim>> position;
    std::vector<double> radius;
};

/// A fresh packing: a gas of non-overlapping particles, radii uniform in [min, max], placed at
/// random in a cubic cell at the start volume fraction (random sequential addition, largest
/// first; the particles' order in the packing is no order in space).
template <int dim>
Packing<dim> random_gas(const Config& c) {
    using V = mm::Vec<dim>;
    Packing<dim> g;
    double volume = 0.0;  // of the particles, as drawn
    std::mt19937_64 rng(c.seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    std::vector<double> radii(c.particles);
    for (auto& a : radii) volume += mm::DimTraits<dim>::particle_volume(a = c.radius_min + (c.radius_max - c.radius_min) * U(rng));
    std::sort(radii.begin(), radii.end(), std::greater<>());  // the largest first: the small ones still find room
    const double L = std::pow(volume / c.start_volume_fraction, 1.0 / dim);
    g.cell = mm::Domain<dim>::fully_periodic(V::Zero(), V::Constant(L));
    // Random sequential placement, each particle checked against those already placed in its
    // cell of a grid (cells at least two largest radii wide) and the neighbouring cells.
    const int n = std::max(1, std::min(static_cast<int>(L / (2.0 * c.radius_max)), static_cast<int>(std::pow(1e7, 1.0 / dim))));
    const auto cell_index = [&](const std::array<int, dim>& at) {
        std::size_t i = 0;
        for (int k = dim - 1; k >= 0; --k) i = i * n + static_cast<std::size_t>(((at[k] % n) + n) % n);
        return i;
    };
    std::vector<std::vector<std::size_t>> grid(static_cast<std::size_t>(std::pow(n, dim)));
    for (std::size_t p = 0, tries = 0; p < radii.size(); ++tries) {
        if (tries > 1000 * radii.size())
            mm::throw_input_error("could not place ", radii.size(), " particles without overlap at volume fraction ",
                                  c.start_volume_fraction, "; lower --start-volume-fraction");
        V x;
        std::array<int, dim> home;
        for (int k = 0; k < dim; ++k) x[k] = L * U(rng), home[k] = std::min(n - 1, static_cast<int>(x[k] / L * n));
        bool free = true;
        for (int around = 0; around < (dim == 2 ? 9 : 27) && free; ++around) {
            std::array<int, dim> at = home;
            for (int k = 0, rest = around; k < dim; ++k, rest /= 3) at[k] += rest % 3 - 1;
            for (const std::size_t q : grid[cell_index(at)])
                if (g.cell.separation(x, g.position[q]).norm() <= radii[p] + g.radius[q]) free = false;
        }
        if (!free) continue;
        grid[cell_index(home)].push_back(g.position.size());
        g.position.push_back(x);
        g.radius.push_back(radii[p]);
        ++p;
    }
    return g;
}

/// The kinetic energy of the particles' motion relative to the cell's flow L (x - centre), the
/// motion a resting packing in a moving cell lacks (the translational part; rotation at rest is nil).
template <class Sim>
double kinetic_relative_to_flow(const Sim& sim) {
    const auto& p = sim.particles();
    const auto& L = sim.domain().velocity_gradient();
    const auto centre = sim.domain().centre();
    double e = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) e += 0.5 * p.mass()[i] * (p.velocity()[i] - L * (p.position()[i] - centre)).squaredNorm();
    return e;
}

template <int dim>
class Experiment {
public:
    using Sim = mm::Simulation<dim, mm::FrictionalLinear, mm::NoWalls, mm::VelocityVerlet, mm::LinkedCells, mm::AffineDamping>;
    using V = mm::Vec<dim>;
    using Matrix = Eigen::Matrix<double, dim, dim>;
    static constexpr int up = dim - 1;  // the loaded axis (the paper's z)

    /// A scene of `packing` (particles at rest, masses from the density); an empty packing for a
    /// scene a saved state will fill.
    Experiment(const Config& c, const Packing<dim>& packing)
        : c_(c), sim_(law(c.mu_prepare), packing.cell, {}, {}, {}, mm::AffineDamping(0.0, 0.0)), control_(mm::CellControl<dim>::following_stiffness(c.servo_relaxation(), c.max_rate())) {
        for (std::size_t i = 0; i < packing.position.size(); ++i)
            sim_.particles().add(packing.position[i], packing.radius[i], mm::sphere_mass(c_.density, packing.radius[i]));
    }

    Sim& simulation() { return sim_; }
    const Sim& simulation() const { return sim_; }
    const Config& config() const { return c_; }
    const mm::CellControl<dim>& control() const { return control_; }

    /// Compresses (or expands) isotropically to p with every shear stress at zero, until the
    /// servo holds p within 1e-3, the shear stresses are below 1e-3 p and the fluctuating kinetic
    /// energy is below rest_ratio of the elastic energy. `progress(m)` is called every 1000 steps
    /// with the cell's average then.
    template <class Progress>
    void prepare(Progress&& progress) {
        sim_.set_time_step(c_.time_step());
        sim_.template body_force<mm::AffineDamping>() = mm::AffineDamping(c_.gamma_b_prepare, rotational(c_.gamma_b_prepare));
        sim_.sort_spatially();
        sim_.prepare();
        const double max_rate = c_.rate_of(c_.prepare_inertial_number, c_.pressure);
        auto servo = mm::CellControl<dim>::following_stiffness(c_.servo_relaxation(), max_rate);
        servo.pressure(c_.pressure);
        // A gas takes about ln(phi_jammed / phi_start) / max_rate to close; rest within 200 times that.
        const double limit = 200.0 * std::log(1.0 / c_.start_volume_fraction) / max_rate;
        for (mm::MicroMacro<dim> m = servo.measure(sim_); !at_rest(m, c_.pressure); m = servo.measure(sim_)) {
            if (servo.time() > limit)
                mm::throw_input_error("the preparation did not come to rest at p = ", c_.pressure, " within ", limit,
                                      " s of simulated time (pressure now ", servo.measure(sim_).pressure,
                                      "); raise --gamma-b-prepare or lower --prepare-inertial-number");
            servo.run(sim_, 1000);
            progress(m);
        }
        sim_.set_velocity_gradient(Matrix::Zero());
    }

    /// Switches to the loading: the loading's friction, the preset's drive, the reference cell.
    void start_loading() {
        sim_.law() = law(c_.mu);
        sim_.set_time_step(c_.time_step());
        sim_.template body_force<mm::AffineDamping>() = mm::AffineDamping(c_.gamma_b, rotational(c_.gamma_b));
        control_ = mm::CellControl<dim>::following_stiffness(c_.servo_relaxation(), c_.max_rate());
        set_drive();
        load_start_ = sim_.time();
        volume0_ = sim_.domain().volume();
        relaxing_ = false;
    }

    /// The drive of the preset (and, for isotropic, of its relaxation at the target).
    void set_drive() {
        const double r = c_.rate();
        auto hold_all = [&] {
            for (int k = 0; k < dim; ++k)
                for (int i = 0; i <= k; ++i) control_.hold(i, k);
        };
        hold_all();
        if (c_.preset == "isotropic") {
            if (relaxing_)
                control_.pressure(c_.target_volume_fraction > 0 ? reached_pressure_ : c_.target_p());
            else
                for (int k = 0; k < dim; ++k) control_.rate(k, k, -r / dim);
        } else if (c_.preset == "oedometric") {
            control_.rate(up, up, -r);
        } else if (c_.preset == "triaxial") {
            control_.rate(up, up, -r);
            for (int k = 0; k < up; ++k) control_.stress(k, k, c_.pressure);
        } else if (c_.preset == "shear-p") {
            control_.rate(0, up, r).stress(up, up, c_.pressure);
        } else if (c_.preset == "shear-v") {
            control_.rate(0, up, r);
        }
    }

    /// The strain the preset drives (compression positive): the loaded axis's for oedometric and
    /// triaxial, the shear F_1z for shear-p and shear-v, the volumetric one for isotropic.
    double loading_strain() const {
        const Matrix& F = control_.deformation();
        if (c_.preset == "shear-p" || c_.preset == "shear-v") return F(0, up);
        if (c_.preset == "isotropic") return 1.0 - F.determinant();
        return 1.0 - F(up, up);
    }
    /// Steps between rows: the preset's path over --rows rows at the loading's rate (isotropic:
    /// --strain of volumetric strain, the bound of its compression).
    std::size_t steps_per_row() const {
        return std::max<std::size_t>(1, std::llround(c_.strain / c_.rate() / c_.rows / sim_.time_step()));
    }

    /// Whether the preset's path is complete after the latest rows. Isotropic: once the target is
    /// reached, the servo holds it until the packing rests.
    bool done() {
        if (c_.preset != "isotropic") return loading_strain() >= c_.strain * (1.0 - 1e-9);
        const auto m = control_.measure(sim_);
        if (relaxing_) return at_rest(m, control_.target(0, 0));
        if (c_.target_volume_fraction > 0 ? m.volume_fraction >= c_.target_volume_fraction : m.pressure >= c_.target_p()) {
            relaxing_ = true;
            reached_pressure_ = m.pressure;
            set_drive();
            return false;
        }
        if (loading_strain() > c_.strain)
            mm::throw_input_error("the isotropic compression reached a volumetric strain of ", loading_strain(), " (the bound --strain ",
                                  c_.strain, ") at p = ", m.pressure, " and volume fraction ", m.volume_fraction,
                                  " before the target; raise --strain");
        return false;
    }

    void run(std::size_t steps) { control_.run(sim_, steps); }

    double fluctuating_kinetic_energy() const { return kinetic_relative_to_flow(sim_); }

    /// The time-series row of the present state.
    Row row() const {
        Row r;
        const auto snapshot = mm::take_snapshot(sim_);
        const auto m = control_.measure(snapshot);
        const auto e = sim_.energy();
        const auto& books = sim_.books();
        const Matrix& F = control_.deformation();
        const Matrix& L = sim_.domain().velocity_gradient();
        r.add("time", sim_.time() - load_start_);
        r.add("loading_strain", loading_strain());
        for (int k = 0; k < dim; ++k) r.add("strain_" + idx({k, k}), 1.0 - F(k, k));
        for (int k = 0; k < dim; ++k)
            for (int i = 0; i < k; ++i) r.add("gamma_" + idx({i, k}), F(i, k));
        r.add("volumetric_strain", 1.0 - sim_.domain().volume() / volume0_);
        for (int k = 0; k < dim; ++k)
            for (int i = 0; i <= k; ++i) r.add("L_" + idx({i, k}), L(i, k));
        for (int a = 0; a < dim; ++a)
            for (int b = a; b < dim; ++b) {
                r.add("sigma_" + idx({a, b}), 0.5 * (m.stress(a, b) + m.stress(b, a)));
                r.add("sigma_n_" + idx({a, b}), m.stress_normal(a, b));
                r.add("sigma_t_" + idx({a, b}), m.stress_tangential(a, b));
                r.add("sigma_k_" + idx({a, b}), m.stress_kinetic(a, b));
            }
        r.add("pressure", m.pressure);
        r.add("deviatoric_stress", m.stress_deviator);
        r.add("stress_ratio", m.pressure > 0 ? m.stress_deviator / m.pressure : 0.0);
        const double s_up = m.stress(up, up);
        r.add("shear_stress_ratio", s_up > 0 ? -0.5 * (m.stress(0, up) + m.stress(up, 0)) / s_up : 0.0);
        for (int a = 0; a < dim; ++a)
            for (int b = a; b < dim; ++b) r.add("F_" + idx({a, b}), m.fabric(a, b));
        r.add("trF", m.contact_number_density);
        r.add("g2", m.g2);
        r.add("deviatoric_fabric", m.fabric_deviator);
        if constexpr (dim == 2) r.add("phi_F", m.fabric_angle);
        r.add("coordination", m.coordination);
        r.add("rattlers", double(m.rattlers));
        r.add("coordination_without_rattlers", m.coordination_without_rattlers);  // as jamming studies count it
        r.add("volume_fraction", m.volume_fraction);
        mm::cli::add_stiffness_columns(r, m);
        mm::cli::add_anisotropy_columns(r, mm::anisotropy(snapshot, mm::Region<dim>::whole(snapshot)));
        // I = (largest imposed strain rate) d sqrt(rho / p), with the pressure now.
        const double rate = L.cwiseAbs().maxCoeff();
        r.add("inertial_number", m.pressure > 0 ? rate * 2.0 * c_.mean_radius() * std::sqrt(c_.inertial_density() / m.pressure) : 0.0);
        r.add("kinetic_energy", e.kinetic());
        r.add("fluctuating_kinetic_energy", fluctuating_kinetic_energy());
        r.add("elastic_energy", e.elastic_normal + e.elastic_tangential);
        r.add("dissipated_energy", books.dissipated());
        r.add("dissipated_background", books.dissipated_background);
        r.add("work_by_cell", books.work_by_cell);
        r.add("sliding_fraction", m.sliding_fraction);
        return r;
    }

    /// What the experiment keeps beyond the simulation (for prepared states and checkpoints).
    nlohmann::ordered_json bookkeeping() const {
        const Matrix& F = control_.deformation();
        return {{"load_start", load_start_}, {"volume0", volume0_}, {"relaxing", relaxing_}, {"reached_pressure", reached_pressure_},
                {"control_time", control_.time()}, {"deformation", std::vector<double>(F.data(), F.data() + dim * dim)}};
    }
    void restore_bookkeeping(const nlohmann::ordered_json& j) {
        const auto f = j.at("deformation").get<std::vector<double>>();
        if (f.size() != dim * dim) mm::throw_input_error("the saved element test does not fit a ", dim, "D run");
        load_start_ = j.at("load_start");
        volume0_ = j.at("volume0");
        relaxing_ = j.at("relaxing");
        reached_pressure_ = j.at("reached_pressure");
        control_ = mm::CellControl<dim>::following_stiffness(c_.servo_relaxation(), c_.max_rate());
        set_drive();
        control_.resume_at(Eigen::Map<const Matrix>(f.data()), j.at("control_time").get<double>());
    }
    double load_start() const { return load_start_; }

private:
    mm::FrictionalLinear law(double mu) const {
        return {mm::LinearSpringDashpot(c_.k, c_.gamma0), mm::CundallStrack(c_.kt_ratio * c_.k, c_.gammat_ratio * c_.gamma0, mu)};
    }
    double rotational(double gamma) const { return 0.4 * gamma * c_.mean_radius() * c_.mean_radius(); }

    bool at_rest(const mm::MicroMacro<dim>& m, double p) const {
        double shear = 0.0;
        for (int k = 0; k < dim; ++k)
            for (int i = 0; i < k; ++i) shear = std::max(shear, std::abs(m.stress(i, k) + m.stress(k, i)) / 2);
        const auto e = sim_.energy();
        return std::abs(m.pressure / p - 1.0) < 1e-3 && shear < 1e-3 * p && e.elastic_normal > 0 &&
               fluctuating_kinetic_energy() < c_.rest_ratio * (e.elastic_normal + e.elastic_tangential);
    }

    Config c_;
    Sim sim_;
    mm::CellControl<dim> control_;
    double load_start_ = 0.0, volume0_ = 1.0, reached_pressure_ = 0.0;
    bool relaxing_ = false;
};

}  // namespace element_test
