#pragma once
// The micro-macro transition with the box (Heaviside) kernel of the paper: fabric (Eq. 11-13,
// 31), stress (Eq. 14-15) and stiffness (Eq. 9, 16) averaged over a region.
//
// Each contact enters with a weight. Contact-point rule: weight 1 if its contact point lies in
// the region. Particle-centre rule: each partner inside brings its share of the branch (for
// stress and stiffness) or its own volume (for the fabric). Both give every contact of a
// periodic packing weight 1 over the whole box, so the rules agree there, and both count each
// contact once with the centre-to-centre branch vector l (a sum over particles, as Eq. 14 is
// written, would take the centre-to-contact-point vectors instead):
//   F       = 1/V sum w_V (n n),                     w_V = (V^p + V^q) inside (Eq. 31)
//   sigma   = 1/V sum w  l (x) f                     (compression positive)
//   C^n     = 1/V sum w  k   l^2 n_a n_b n_c n_d
//   C^t     = 1/V sum w  k_t l^2 n_a n_c (delta_bd - n_b n_d)    (= n_a t_b n_c t_d in 2D)
#include <cmath>
#include <utility>
#include <vector>

#include "micromacro/averaging/contact_sums.hpp"
#include "micromacro/averaging/region.hpp"
#include "micromacro/averaging/snapshot.hpp"
#include "micromacro/averaging/tensor.hpp"

namespace micromacro {

struct AveragingOptions {
    SelectionRule rule = SelectionRule::contact_point;
    /// Leave out particles with fewer than dim + 1 contacts (found iteratively) and their contacts.
    bool exclude_rattlers = false;
    /// Add the kinetic stress 1/V sum m v (x) v of the particles with centres inside, v measured
    /// against a moving periodic cell's flow L (x - centre) (Domain::velocity_gradient).
    bool kinetic_stress = false;
    /// Leave sliding contacts out of the tangential stiffness (their tangential spring is at the
    /// Coulomb limit and does not respond elastically).
    bool exclude_sliding_from_tangential_stiffness = false;
};

template <int dim>
struct MicroMacro {
    double volume = 0;
    std::size_t particles = 0;  ///< centres inside (rattlers included)
    std::size_t rattlers = 0;   ///< of those, particles with fewer than dim + 1 contacts
    std::size_t contacts = 0;   ///< contacts with a non-zero weight
    double coordination = 0;    ///< mean contacts per particle inside (rattlers left out if excluded)
    /// Mean contacts per particle inside among the particles that are not rattlers, contacts with
    /// rattlers left out: the coordination jamming studies count (isostatic 2 dim at jamming for
    /// frictionless particles), whatever `exclude_rattlers` says for the other averages.
    double coordination_without_rattlers = 0;
    double volume_fraction = 0;
    Tensor2<dim> fabric = Tensor2<dim>::Zero();
    double contact_number_density = 0;  ///< tr F
    double g2 = 0;                      ///< tr F / (nu C)
    double fabric_deviator = 0;         ///< see deviator_magnitude
    double fabric_angle = 0;            ///< 2D: major axis from axis 1 (rad); 3D: 0 (see fabric_axes)
    Tensor2<dim> fabric_axes = Tensor2<dim>::Identity();  ///< eigenvectors (columns, ascending eigenvalues)
    Tensor2<dim> stress_normal = Tensor2<dim>::Zero();
    Tensor2<dim> stress_tangential = Tensor2<dim>::Zero();
    Tensor2<dim> stress_kinetic = Tensor2<dim>::Zero();
    Tensor2<dim> stress = Tensor2<dim>::Zero();  ///< sum of the three
    double pressure = 0;                         ///< tr sigma / dim
    double stress_deviator = 0;                  ///< see deviator_magnitude
    Tensor4<dim> stiffness_normal, stiffness_tangential;
    double sliding_fraction = 0;  ///< of the counted contacts, weighted
};

namespace detail {
/// Particles with fewer than dim + 1 contacts, removing them repeatedly (a removal can make a
/// neighbour a rattler too). What remains is the largest set in which every particle keeps
/// dim + 1 contacts (wall contacts count and walls are never removed), the same whatever the
/// order of removal: a work list over the partners of each removed particle finds it in
/// O(contacts). (Rescanning every contact for each rattler cost 2.5% of the paper's biaxial run.)
template <int dim>
std::vector<char> find_rattlers(const PackingSnapshot<dim>& s) {
    const std::size_t n = s.size();
    std::vector<int> count(n, 0);
    std::vector<std::size_t> first(n + 1, 0);  // partners of p: partner[first[p] .. first[p + 1])
    for (const auto& c : s.contacts) {
        ++count[c.i];
        if (!c.wall) {
            ++count[c.j];
            ++first[c.i + 1];
            ++first[c.j + 1];
        }
    }
    for (std::size_t p = 0; p < n; ++p) first[p + 1] += first[p];
    std::vector<std::size_t> partner(first[n]), fill(first.begin(), first.end() - 1);
    for (const auto& c : s.contacts)
        if (!c.wall) {
            partner[fill[c.i]++] = c.j;
            partner[fill[c.j]++] = c.i;
        }
    std::vector<char> rattler(n, 0);
    std::vector<std::size_t> removed;  // marked when found, their partners' counts lowered in turn
    for (std::size_t p = 0; p < n; ++p)
        if (count[p] < dim + 1) {
            rattler[p] = 1;
            removed.push_back(p);
        }
    for (std::size_t k = 0; k < removed.size(); ++k)
        for (std::size_t e = first[removed[k]]; e < first[removed[k] + 1]; ++e) {
            const std::size_t q = partner[e];
            if (!rattler[q] && --count[q] < dim + 1) {
                rattler[q] = 1;
                removed.push_back(q);
            }
        }
    return rattler;
}

template <int dim>
Vec<dim> wrapped(const PackingSnapshot<dim>& s, Vec<dim> x) {
    s.domain.wrap(x);
    return x;
}
}  // namespace detail

/// Which particles an average counts and how much of each contact.
template <int dim>
struct ContactWeights {
    std::vector<char> inside;   ///< particle centre in the region
    std::vector<char> rattler;  ///< fewer than dim + 1 contacts (iteratively)
    std::vector<char> counted;  ///< contact counted at all (not a rattler's when those are excluded)
    std::vector<double> branch; ///< w: weight of l (x) f and of the stiffness terms
    std::vector<double> volume; ///< w_V: the fabric's volume weight
};

/// The weights with the rattlers given (one flag per particle), for a packing whose rattlers
/// cannot be found from the snapshot alone (one process's part of a split packing).
template <int dim>
ContactWeights<dim> contact_weights(const PackingSnapshot<dim>& s, const Region<dim>& region, const AveragingOptions& opt,
                                    std::vector<char> rattler) {
    ContactWeights<dim> cw;
    cw.inside.resize(s.size());
    for (std::size_t p = 0; p < s.size(); ++p) cw.inside[p] = region.contains(detail::wrapped(s, s.position[p]));
    cw.rattler = std::move(rattler);
    const std::size_t n = s.contacts.size();
    cw.counted.assign(n, 1);
    cw.branch.assign(n, 0.0);
    cw.volume.assign(n, 0.0);
    for (std::size_t q = 0; q < n; ++q) {
        const auto& c = s.contacts[q];
        if (opt.exclude_rattlers && (cw.rattler[c.i] || (!c.wall && cw.rattler[c.j]))) {
            cw.counted[q] = 0;
            continue;
        }
        const double vi = DimTraits<dim>::particle_volume(s.radius[c.i]);
        const double vj = c.wall ? 0.0 : DimTraits<dim>::particle_volume(s.radius[c.j]);
        if (opt.rule == SelectionRule::contact_point) {
            const bool in = region.contains(c.point);
            cw.branch[q] = in ? 1.0 : 0.0;
            cw.volume[q] = in ? vi + vj : 0.0;
        } else {
            const bool in_i = cw.inside[c.i], in_j = !c.wall && cw.inside[c.j];
            cw.branch[q] = (in_i ? c.share_i : 0.0) + (in_j ? 1.0 - c.share_i : 0.0);
            cw.volume[q] = (in_i ? vi : 0.0) + (in_j ? vj : 0.0);
        }
    }
    return cw;
}

template <int dim>
ContactWeights<dim> contact_weights(const PackingSnapshot<dim>& s, const Region<dim>& region, const AveragingOptions& opt) {
    return contact_weights(s, region, opt, detail::find_rattlers(s));
}

/// What an average adds up over particles and contacts before its tensors are derived: sums,
/// so that the parts of a packing split over processes add to the whole's.
template <int dim>
struct AverageSums {
    ContactSums<dim> contacts;                                  ///< per unit volume
    Tensor2<dim> stress_kinetic = Tensor2<dim>::Zero();         ///< per unit volume
    double particles = 0, rattlers = 0, contact_count = 0;      ///< counts
    double solid = 0, counted = 0, contact_sum = 0, weight_sum = 0, sliding_weight = 0;
    double backbone_contact_sum = 0;  ///< contacts between particles that are not rattlers (walls count), per particle's end

    /// Every number, in one order, for a reduction over processes.
    template <class F>
    void for_each_number(F&& f) {
        for (Tensor2<dim>* t : {&contacts.fabric, &contacts.stress_normal, &contacts.stress_tangential, &stress_kinetic})
            for (int k = 0; k < dim * dim; ++k) f(t->data()[k]);
        for (Tensor4<dim>* t : {&contacts.stiffness_normal, &contacts.stiffness_tangential})
            for (int k = 0; k < dim * dim * dim * dim; ++k) f(t->data()[k]);
        for (double* x : {&particles, &rattlers, &contact_count, &solid, &counted, &contact_sum, &weight_sum, &sliding_weight,
                          &backbone_contact_sum})
            f(*x);
    }
};

/// Which particles and contacts of a snapshot an average adds (null: all): each process of a
/// split packing adds its own particles and the contacts it is the one to count.
struct AveragingShare {
    std::vector<char> particle, contact;
};

/// The sums of the average over `region` with weights `cw` (contact_weights), of the share
/// given or of everything.
template <int dim>
AverageSums<dim> average_sums(const PackingSnapshot<dim>& s, const Region<dim>& region, const AveragingOptions& opt,
                              const ContactWeights<dim>& cw, const AveragingShare* share = nullptr) {
    AverageSums<dim> out;
    const double V = region.volume();
    // Particles: count, volume fraction, kinetic stress, coordination.
    std::vector<int> contacts_of(s.size(), 0), backbone_contacts_of(s.size(), 0);
    for (std::size_t q = 0; q < s.contacts.size(); ++q) {
        const auto& c = s.contacts[q];
        if (!cw.rattler[c.i] && (c.wall || !cw.rattler[c.j])) {
            ++backbone_contacts_of[c.i];
            if (!c.wall) ++backbone_contacts_of[c.j];
        }
        if (!cw.counted[q]) continue;
        ++contacts_of[c.i];
        if (!c.wall) ++contacts_of[c.j];
    }
    for (std::size_t p = 0; p < s.size(); ++p) {
        if (!cw.inside[p] || (share && !share->particle[p])) continue;
        out.particles += 1.0;
        out.rattlers += cw.rattler[p];
        if (!cw.rattler[p]) out.backbone_contact_sum += backbone_contacts_of[p];
        out.solid += DimTraits<dim>::particle_volume(s.radius[p]);
        if (opt.kinetic_stress && !s.velocity.empty()) {
            Vec<dim> v = s.velocity[p];
            if (s.domain.moving()) v -= s.domain.velocity_gradient() * (s.position[p] - s.domain.centre());
            out.stress_kinetic += s.mass[p] * v * v.transpose() / V;
        }
        if (opt.exclude_rattlers && cw.rattler[p]) continue;
        out.counted += 1.0;
        out.contact_sum += contacts_of[p];
    }
    // Contacts.
    for (std::size_t q = 0; q < s.contacts.size(); ++q) {
        const auto& c = s.contacts[q];
        const double w = cw.branch[q], w_fabric = cw.volume[q];
        if ((w == 0.0 && w_fabric == 0.0) || (share && !share->contact[q])) continue;
        out.contact_count += 1.0;
        out.contacts.add(c, w / V, w_fabric / V, !(opt.exclude_sliding_from_tangential_stiffness && c.sliding));
        out.weight_sum += w;
        out.sliding_weight += c.sliding ? w : 0.0;
    }
    return out;
}

/// The average from its sums over a region of volume V.
template <int dim>
MicroMacro<dim> finish_average(const AverageSums<dim>& sums, double V) {
    MicroMacro<dim> out;
    out.volume = V;
    out.particles = static_cast<std::size_t>(sums.particles);
    out.rattlers = static_cast<std::size_t>(sums.rattlers);
    out.contacts = static_cast<std::size_t>(sums.contact_count);
    out.stress_kinetic = sums.stress_kinetic;
    out.volume_fraction = sums.solid / V;
    out.coordination = sums.counted > 0 ? sums.contact_sum / sums.counted : 0.0;
    const double backbone = sums.particles - sums.rattlers;
    out.coordination_without_rattlers = backbone > 0 ? sums.backbone_contact_sum / backbone : 0.0;
    out.fabric = sums.contacts.fabric;
    out.stress_normal = sums.contacts.stress_normal;
    out.stress_tangential = sums.contacts.stress_tangential;
    out.stiffness_normal = sums.contacts.stiffness_normal;
    out.stiffness_tangential = sums.contacts.stiffness_tangential;
    out.sliding_fraction = sums.weight_sum > 0 ? sums.sliding_weight / sums.weight_sum : 0.0;

    out.contact_number_density = out.fabric.trace();
    out.g2 = out.volume_fraction * out.coordination > 0 ? out.contact_number_density / (out.volume_fraction * out.coordination) : 0.0;
    out.fabric_deviator = deviator_magnitude<dim>(out.fabric);
    out.fabric_axes = principal<dim>(out.fabric).eigenvectors();
    if constexpr (dim == 2) out.fabric_angle = major_axis_angle(out.fabric);
    out.stress = out.stress_normal + out.stress_tangential + out.stress_kinetic;
    out.pressure = out.stress.trace() / dim;
    out.stress_deviator = deviator_magnitude<dim>(out.stress);
    return out;
}

template <int dim>
MicroMacro<dim> average(const PackingSnapshot<dim>& s, const Region<dim>& region, const AveragingOptions& opt = {}) {
    return finish_average(average_sums(s, region, opt, contact_weights(s, region, opt)), region.volume());
}

/// Stress read from the walls of a box: sigma_aa = mean push of the two walls of axis a divided by
/// their area (the extents of the other axes between walls, or periodic lengths). Zero for an axis
/// without two walls.
template <int dim>
Tensor2<dim> wall_stress(const PackingSnapshot<dim>& s) {
    const auto [lo, hi] = s.bounds();
    Tensor2<dim> sigma = Tensor2<dim>::Zero();
    for (int a = 0; a < dim; ++a) {
        double push = 0.0;
        int walls = 0;
        for (const auto& w : s.walls)
            if (w.axis() == a) {
                push += -w.force.dot(w.normal);
                ++walls;
            }
        if (walls != 2) continue;
        double area = 1.0;
        for (int b = 0; b < dim; ++b)
            if (b != a) area *= hi[b] - lo[b];
        sigma(a, a) = 0.5 * push / area;
    }
    return sigma;
}

}  // namespace micromacro
