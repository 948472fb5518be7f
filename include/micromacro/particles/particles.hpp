#pragma once
// Particle storage: one contiguous array per field, reached by a field tag.
//
//     particles.get<field::Position>()[i]
//
// Rotational fields (angular velocity, torque, moment of inertia) exist only when the scene
// needs rotation (`with_rotation`); asking for them otherwise is a compile error, so a
// frictionless scene carries no rotational storage and never updates it.
//
// A particle's index is where it is stored, and the engine may renumber the particles (to keep
// partners close in memory: BasicSimulation::sort_spatially, which it also calls on its own in
// scenes of 2048 particles or more). Its id is its index when it was added and follows it.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <type_traits>
#include <vector>

#include "micromacro/core/dim_traits.hpp"
#include "micromacro/core/error.hpp"
#include "micromacro/core/index.hpp"

namespace micromacro {

namespace field {
struct Position {};
struct Velocity {};
struct Force {};
struct Radius {};
struct Mass {};
struct InverseMass {};
struct AngularVelocity {};
struct Torque {};
struct Inertia {};         ///< moment of inertia
struct InverseInertia {};
}  // namespace field

/// Mass and moment of inertia of a sphere of density rho and radius a. The paper uses sphere
/// masses also in 2D (Sec. 4.3); `disk_inertia` gives the 2D alternative I = m a^2 / 2.
inline double sphere_mass(double rho, double a) { return 4.0 / 3.0 * std::numbers::pi * rho * a * a * a; }
inline double sphere_inertia(double m, double a) { return 0.4 * m * a * a; }
inline double disk_inertia(double m, double a) { return 0.5 * m * a * a; }

namespace detail {
struct Absent {};
template <bool present, class T>
using MaybeVector = std::conditional_t<present, std::vector<T>, Absent>;
}  // namespace detail

/// `Real` is the storage precision of the particles' state (float halves its memory and traffic;
/// positions then resolve only ~6e-8 of their magnitude, see BasicSimulation). Forces and torques
/// are sums of many contacts' forces, often nearly cancelling, and stay double: accumulated in
/// float they would lose the digits a packing at rest balances on, and the pair loop would round
/// every contact's force (in a float scene double sums ran 1.06x: docs/performance.md). Values go
/// in and out of add() in double.
template <int dim, bool with_rotation, class Real = double>
class Particles {
public:
    using V = Vec<dim, Real>;
    using A = Angular<dim, Real>;
    using FV = Vec<dim>;      ///< a force: double whatever Real is
    using FA = Angular<dim>;  ///< a torque: double whatever Real is
    using Scalar = Real;
    static constexpr bool has_rotation = with_rotation;

    std::size_t size() const { return position_.size(); }
    /// Whether every field has one entry per particle (after restoring a file).
    bool consistent() const {
        const std::size_t n = position_.size();
        bool same = velocity_.size() == n && force_.size() == n && radius_.size() == n && mass_.size() == n &&
                    inverse_mass_.size() == n && id_.size() == n;
        if constexpr (with_rotation)
            same = same && angular_velocity_.size() == n && torque_.size() == n && inertia_.size() == n && inverse_inertia_.size() == n;
        return same;
    }
    bool empty() const { return position_.empty(); }

    /// The tangential mobility of a contact point on particle i's surface: 1/m + a^2/I with
    /// rotation, 1/m without.
    double contact_point_mobility(std::size_t i) const {
        double mobility = inverse_mass_[i];
        if constexpr (with_rotation) {
            const double a = radius_[i];
            mobility += a * a * double(inverse_inertia_[i]);
        }
        return mobility;
    }

    /// sum 1/2 m v^2 over the first `count` particles (all by default).
    double translational_kinetic_energy(std::size_t count = std::numeric_limits<std::size_t>::max()) const {
        double e = 0.0;
        const std::size_t n = std::min(count, size());
        for (std::size_t i = 0; i < n; ++i) e += 0.5 * double(mass_[i]) * convert<double>(velocity_[i]).squaredNorm();
        return e;
    }
    /// sum 1/2 I w^2 (0 without rotation) over the first `count` particles (all by default).
    double rotational_kinetic_energy(std::size_t count = std::numeric_limits<std::size_t>::max()) const {
        double e = 0.0;
        const std::size_t n = std::min(count, size());
        if constexpr (with_rotation)
            for (std::size_t i = 0; i < n; ++i)
                e += 0.5 * double(inertia_[i]) * DimTraits<dim>::squared_norm(convert<double>(angular_velocity_[i]));
        return e;
    }

    /// Calls refuse(message parts...) when a restored particle set does not hold together: fields
    /// of different lengths, a position or velocity that is not finite, a radius or mass that is
    /// not finite and positive.
    template <class Refuse>
    void check_restored(Refuse&& refuse) const {
        if (!consistent()) refuse("particle fields of different lengths");
        for (std::size_t i = 0; i < size(); ++i) {
            if (!convert<double>(position_[i]).allFinite() || !convert<double>(velocity_[i]).allFinite())
                refuse("particle ", i, " has a position or velocity that is not finite");
            if (!(double(radius_[i]) > 0.0) || !(double(mass_[i]) > 0.0) || !std::isfinite(double(radius_[i])) ||
                !std::isfinite(double(mass_[i])))
                refuse("particle ", i, " has radius ", radius_[i], " and mass ", mass_[i]);
        }
        if (const std::size_t i = first_not_permuted(id_); i < size())
            refuse("particle ", i, " has id ", id_[i], ", not one of 0..", size() - 1, " once");
    }

    /// Adds a particle at rest and returns its index. With rotation, `inertia` <= 0 selects the
    /// sphere value 2/5 m a^2.
    std::size_t add(const Vec<dim>& position, double radius, double mass, double inertia = 0.0) {
        const std::size_t i = size();
        for (int k = 0; k < dim; ++k)
            if (!std::isfinite(position[k]))
                detail::throw_input_error("particle ", i, ": position component ", k, " = ", position[k],
                                          " is not finite; give every particle a finite position");
        if (!(radius > 0.0) || !std::isfinite(radius))
            detail::throw_input_error("particle ", i, ": radius = ", radius,
                                      " is invalid: it must be finite and > 0");
        if (!(mass > 0.0) || !std::isfinite(mass))
            detail::throw_input_error("particle ", i, ": mass = ", mass, " is invalid: it must be finite and > 0");
        position_.push_back(convert<Real>(position));
        id_.push_back(static_cast<Index>(i));
        velocity_.push_back(V::Zero());
        force_.push_back(FV::Zero());
        radius_.push_back(static_cast<Real>(radius));
        mass_.push_back(static_cast<Real>(mass));
        inverse_mass_.push_back(static_cast<Real>(1.0 / mass));
        if constexpr (with_rotation) {
            if (inertia <= 0.0) inertia = sphere_inertia(mass, radius);
            if (!std::isfinite(inertia))
                detail::throw_input_error("particle ", i, ": moment of inertia = ", inertia, " is not finite");
            angular_velocity_.push_back(zero_angular<dim, Real>());
            torque_.push_back(zero_angular<dim, double>());
            inertia_.push_back(static_cast<Real>(inertia));
            inverse_inertia_.push_back(static_cast<Real>(1.0 / inertia));
        }
        return i;
    }

    /// Room for n particles in every array, so that adding them one by one does not grow the
    /// arrays by doubling (up to twice the memory, and both copies alive while one grows).
    void reserve(std::size_t n) {
        position_.reserve(n);
        id_.reserve(n);
        velocity_.reserve(n);
        force_.reserve(n);
        radius_.reserve(n);
        mass_.reserve(n);
        inverse_mass_.reserve(n);
        if constexpr (with_rotation) {
            angular_velocity_.reserve(n);
            torque_.reserve(n);
            inertia_.reserve(n);
            inverse_inertia_.reserve(n);
        }
    }

    template <class Field>
    auto& get() { return select<Field>(*this); }
    template <class Field>
    const auto& get() const { return select<Field>(*this); }

    // Short names for the fields every scene has.
    std::vector<V>& position() { return position_; }
    const std::vector<V>& position() const { return position_; }
    std::vector<V>& velocity() { return velocity_; }
    const std::vector<V>& velocity() const { return velocity_; }
    const std::vector<FV>& force() const { return force_; }
    const std::vector<Real>& radius() const { return radius_; }
    const std::vector<Real>& mass() const { return mass_; }
    /// The id of the particle stored at index i: its index when it was added.
    Index id(std::size_t i) const { return id_[i]; }
    const std::vector<Index>& ids() const { return id_; }
    /// The index of every id: index_by_id()[id] is where that particle is stored now.
    std::vector<Index> index_by_id() const {
        std::vector<Index> index(id_.size());
        for (std::size_t i = 0; i < id_.size(); ++i) index[id_[i]] = static_cast<Index>(i);
        return index;
    }

    /// Changes a particle's mass (keeps the inverse consistent).
    void set_mass(std::size_t i, double mass) {
        detail::require_positive(mass, "mass", "give every particle a positive mass");
        mass_[i] = static_cast<Real>(mass);
        inverse_mass_[i] = static_cast<Real>(1.0 / mass);
    }

    /// Bytes of particle storage per particle (all fields).
    std::size_t bytes_per_particle() const {
        std::size_t b = 2 * sizeof(V) + sizeof(FV) + 3 * sizeof(Real) + sizeof(Index);
        if constexpr (with_rotation) b += sizeof(A) + sizeof(FA) + 2 * sizeof(Real);
        return b;
    }

    /// Visits every stored array (for saving and restoring a state).
    template <class Archive>
    void serialize(Archive& ar) {
        ar.array(position_);
        ar.array(velocity_);
        ar.array(force_);
        ar.array(radius_);
        ar.array(mass_);
        ar.array(inverse_mass_);
        if constexpr (with_rotation) {
            ar.array(angular_velocity_);
            ar.array(torque_);
            ar.array(inertia_);
            ar.array(inverse_inertia_);
        }
        ar.array(id_);
    }

private:
    template <class Field, class Self>
    static auto& select(Self& self) {
        if constexpr (std::is_same_v<Field, field::Position>) return self.position_;
        else if constexpr (std::is_same_v<Field, field::Velocity>) return self.velocity_;
        else if constexpr (std::is_same_v<Field, field::Force>) return self.force_;
        else if constexpr (std::is_same_v<Field, field::Radius>) return self.radius_;
        else if constexpr (std::is_same_v<Field, field::Mass>) return self.mass_;
        else if constexpr (std::is_same_v<Field, field::InverseMass>) return self.inverse_mass_;
        else {
            static_assert(with_rotation, "this field exists only in scenes with rotation (a tangential law that turns particles, e.g. CundallStrack)");
            if constexpr (std::is_same_v<Field, field::AngularVelocity>) return self.angular_velocity_;
            else if constexpr (std::is_same_v<Field, field::Torque>) return self.torque_;
            else if constexpr (std::is_same_v<Field, field::Inertia>) return self.inertia_;
            else {
                static_assert(std::is_same_v<Field, field::InverseInertia>, "unknown particle field");
                return self.inverse_inertia_;
            }
        }
    }

    std::vector<V> position_, velocity_;
    std::vector<FV> force_;
    std::vector<Real> radius_, mass_, inverse_mass_;
    std::vector<Index> id_;
    [[no_unique_address]] detail::MaybeVector<with_rotation, A> angular_velocity_;
    [[no_unique_address]] detail::MaybeVector<with_rotation, FA> torque_;
    [[no_unique_address]] detail::MaybeVector<with_rotation, Real> inertia_, inverse_inertia_;
};

}  // namespace micromacro
