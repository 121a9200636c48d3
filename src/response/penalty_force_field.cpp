#include "penalty/response/penalty_force_field.hpp"

#include "penalty/core/error.hpp"

#include <algorithm>
#include <cmath>

namespace penalty {

namespace {

/// P·w with P = I − n·nᵀ: the part of w in the tangent plane of n.
Vec3 tangential_part(const Vec3& w, const Vec3& n) { return w - w.dot(n) * n; }

/// ξ re-projected on the tangent plane of n with its length kept (LAMMPS / Chrono DEM history
/// rotation). A spring parallel to n has no tangential direction left and is dropped.
Vec3 rotate_onto_tangent_plane(const Vec3& shear, const Vec3& n) {
    const Vec3 projected = tangential_part(shear, n);
    const double projected_norm = projected.norm();
    if (projected_norm <= 1e-300) return Vec3::Zero();
    return projected * (shear.norm() / projected_norm);
}

bool finite_non_negative(double value) { return std::isfinite(value) && value >= 0.0; }

/// add_contact's error: the first of its checks that the contact fails (out of line: the checks,
/// made for every contact, stay compares and one branch).
[[noreturn, gnu::cold, gnu::noinline]] void throw_bad_contact(std::size_t id, Index m1, Index m2, const Vec3& normal,
                                                              double dist, double ks, double mu_s, double mu_v) {
    if (m1 < 0 || m2 < 0)
        throw_invalid_argument("PenaltyForceField::add_contact(): contact ", id, ": DOF index m1 = ", m1, ", m2 = ", m2,
                               " must be >= 0");
    if (!normal.allFinite() || std::abs(normal.norm() - 1.0) > 1e-6)
        throw_invalid_argument("PenaltyForceField::add_contact(): contact ", id, ": normal (", normal.x(), ", ",
                               normal.y(), ", ", normal.z(), ") must be a finite unit vector");
    if (!std::isfinite(dist))
        throw_invalid_argument("PenaltyForceField::add_contact(): contact ", id, ": dist = ", dist, " must be finite");
    const char* what = !finite_non_negative(ks)     ? "stiffness ks"
                       : !finite_non_negative(mu_s) ? "static friction mu_s"
                                                    : "dynamic friction mu_v";
    const double value = !finite_non_negative(ks) ? ks : !finite_non_negative(mu_s) ? mu_s : mu_v;
    throw_invalid_argument("PenaltyForceField::add_contact(): contact ", id, ": ", what, " = ", value,
                           " must be finite and >= 0");
}

}  // namespace

void PenaltyParameters::validate() const {
    if (!std::isfinite(damping) || damping < 0.0)
        throw_invalid_argument("PenaltyParameters: damping = ", damping, " must be finite and >= 0");
    if (!std::isfinite(tangential_damping) || tangential_damping < 0.0)
        throw_invalid_argument("PenaltyParameters: tangential_damping = ", tangential_damping,
                               " must be finite and >= 0");
    if (!std::isfinite(tangential_stiffness_ratio) || tangential_stiffness_ratio <= 0.0)
        throw_invalid_argument("PenaltyParameters: tangential_stiffness_ratio = ", tangential_stiffness_ratio,
                               " must be finite and > 0");
    if (!std::isfinite(time_step) || time_step <= 0.0)
        throw_invalid_argument("PenaltyParameters: time_step = ", time_step, " must be finite and > 0");
}

PenaltyForceField::PenaltyForceField(PenaltyParameters parameters) { set_parameters(parameters); }

void PenaltyForceField::set_parameters(const PenaltyParameters& parameters) {
    parameters.validate();
    parameters_ = parameters;
}

void PenaltyForceField::clear(std::size_t reserve) {
    previous_.swap(contacts_);
    contacts_.clear();
    if (reserve > 0) contacts_.reserve(reserve);
    checked_size1_ = checked_size2_ = kUnchecked;
}

void PenaltyForceField::add_contact(DofIndex dof1, DofIndex dof2, ElementIndex element1, ElementIndex element2,
                                    const Vec3& normal, double dist, double ks, double mu_s, double mu_v,
                                    Index old_index) {
    const Index m1 = dof1.value(), m2 = dof2.value();
    // DOF indices >= 0, a finite unit normal (|‖n‖ − 1| <= 1e-6), a finite dist, finite ks, mu_s,
    // mu_v >= 0 (NaN fails every comparison below)
    const bool valid = m1 >= 0 && m2 >= 0 && normal.allFinite() && std::abs(normal.norm() - 1.0) <= 1e-6 &&
                       std::isfinite(dist) && finite_non_negative(ks) && finite_non_negative(mu_s) &&
                       finite_non_negative(mu_v);
    if (!valid) [[unlikely]]
        throw_bad_contact(contacts_.size(), m1, m2, normal, dist, ks, mu_s, mu_v);

    // made whole, then copied: emplace_back() value-initialised the 240 bytes with `rep stos`
    // (a slow start for so few) before the fields were written
    PenaltyContact made{.m1 = m1,
                        .m2 = m2,
                        .normal = normal,
                        .dist = dist,
                        .ks = ks,
                        .index1 = element1.value(),
                        .index2 = element2.value(),
                        .mu_s = mu_s,
                        .mu_v = mu_v};
    PenaltyContact& contact = contacts_.emplace_back(made);
    // SOFA: age carries over only from a valid 1-based index into the previous list
    if (old_index >= 1 && static_cast<std::size_t>(old_index) <= previous_.size()) {
        const PenaltyContact& old = previous_[static_cast<std::size_t>(old_index - 1)];
        contact.age = old.age + 1;
        if (!old.step_started) {
            // never evaluated (two detections without a solve): pass its carried history on
            contact.shear_start = old.shear_start;
            contact.has_history = old.has_history;
            contact.slid_last_step = old.slid_last_step;
        } else if (old.friction_state != FrictionState::none) {
            // tangential spring history: kept only if the previous contact was active. It is the
            // spring of the previous step's FIRST evaluation (at x_n, after its slip): the next
            // step adds the step's motion h·P·v_{n+1} itself, so a later evaluation within the
            // step (Newton iterates, energy reports) must not be carried, or the motion would
            // count twice. With SOFA's single evaluation per step both are the same.
            contact.shear_start = old.shear_start;
            contact.has_history = true;
            contact.slid_last_step = old.friction_state == FrictionState::sliding;
        }
    }
    checked_size1_ = checked_size2_ = kUnchecked;
}

void PenaltyForceField::set_normal_law(std::size_t i, double ks, double dist) {
    if (i >= contacts_.size() || !finite_non_negative(ks) || !std::isfinite(dist))
        throw_invalid_argument("PenaltyForceField::set_normal_law: contact ", i, " of ", contacts_.size(), ", ks ", ks,
                               ", dist ", dist, ": needs an existing contact, a finite ks >= 0 and a finite dist");
    contacts_[i].ks = ks;
    contacts_[i].dist = dist;
}

void PenaltyForceField::renew_contacts() {
    clear(contacts_.size());
    for (std::size_t i = 0; i < previous_.size(); ++i) {
        const PenaltyContact& c = previous_[i];
        add_contact(DofIndex(c.m1), DofIndex(c.m2), ElementIndex(c.index1), ElementIndex(c.index2), c.normal, c.dist,
                    c.ks, c.mu_s, c.mu_v, static_cast<Index>(i + 1));
    }
}

void PenaltyForceField::check_indices(const char* function, std::size_t n1, std::size_t n2) const {
    if (checked_size1_ == n1 && checked_size2_ == n2) return;
    for (std::size_t i = 0; i < contacts_.size(); ++i) {
        const PenaltyContact& c = contacts_[i];
        if (static_cast<std::size_t>(c.m1) >= n1)
            throw_invalid_argument("PenaltyForceField::", function, "(): contact ", i, ": m1 = ", c.m1,
                                   " is outside state 1 (size ", n1, ")");
        if (static_cast<std::size_t>(c.m2) >= n2)
            throw_invalid_argument("PenaltyForceField::", function, "(): contact ", i, ": m2 = ", c.m2,
                                   " is outside state 2 (size ", n2, ")");
    }
    checked_size1_ = n1;
    checked_size2_ = n2;
}

void PenaltyForceField::add_force(Vec3Span f1, Vec3Span f2, ConstVec3Span x1, ConstVec3Span x2, ConstVec3Span v1,
                                  ConstVec3Span v2) {
    if (f1.size() != x1.size() || f2.size() != x2.size())
        throw_invalid_argument("PenaltyForceField::add_force(): force sizes (", f1.size(), ", ", f2.size(),
                               ") differ from position sizes (", x1.size(), ", ", x2.size(), ")");
    check_indices("add_force", x1.size(), x2.size());
    const bool damping = parameters_.damping > 0.0;
    const bool friction = parameters_.friction == FrictionModel::coulomb;
    if ((damping || friction) && (v1.size() != x1.size() || v2.size() != x2.size()))
        throw_invalid_argument("PenaltyForceField::add_force(): velocity sizes (", v1.size(), ", ", v2.size(),
                               ") differ from position sizes (", x1.size(), ", ", x2.size(),
                               "); damping and friction need velocities");
    if (damping) {
        if (friction) add_force_impl<true, true>(f1, f2, x1, x2, v1, v2);
        else add_force_impl<true, false>(f1, f2, x1, x2, v1, v2);
    } else {
        if (friction) add_force_impl<false, true>(f1, f2, x1, x2, v1, v2);
        else add_force_impl<false, false>(f1, f2, x1, x2, v1, v2);
    }
}

template <bool kDamping, bool kFriction>
void PenaltyForceField::add_force_impl(Vec3Span f1, Vec3Span f2, ConstVec3Span x1, ConstVec3Span x2, ConstVec3Span v1,
                                       ConstVec3Span v2) {
    const double c = parameters_.damping;
    const double c_t = parameters_.tangential_damping;
    const double h = parameters_.time_step;
    for (PenaltyContact& ct : contacts_) {
        const Vec3& n = ct.normal;
        const Vec3 u = x2[ct.m2] - x1[ct.m1];
        // pen = dist − (x2 − x1)·n  (m)
        const double pen = ct.dist - u.dot(n);
        ct.pen = pen;
        const bool first_evaluation_of_step = !ct.step_started;
        ct.step_started = true;
        if constexpr (!kDamping && !kFriction) {
            // SOFA's path, branch-free (half the contacts are typically inactive and the branch
            // would be unpredictable): f2 += ks·max(pen, 0)·n, adding zero when inactive
            const double normal_force = pen > 0.0 ? ct.ks * pen : 0.0;
            ct.normal_force = normal_force;
            const Vec3 force2 = normal_force * n;
            f1[ct.m1] -= force2;
            f2[ct.m2] += force2;
            continue;
        }
        if (!(pen > 0.0)) {
            ct.normal_force = 0.0;
            if constexpr (kFriction) {
                // out of contact: the tangential spring is dropped (anchor released)
                ct.tangential_force.setZero();
                ct.shear.setZero();
                ct.friction_state = FrictionState::none;
                if (first_evaluation_of_step) {
                    // the released spring's energy is lost
                    if (ct.has_history)
                        dissipated_sliding_ +=
                            0.5 * parameters_.tangential_stiffness_ratio * ct.ks * ct.shear_start.squaredNorm();
                    ct.has_history = false;
                    ct.shear_start.setZero();
                    ct.u_start = u;
                }
            }
            continue;
        }

        // normal force on side 2 along n: f_n = ks·pen − c·v_n  (N)
        double normal_force = ct.ks * pen;
        Vec3 v_rel = Vec3::Zero();
        if constexpr (kDamping || kFriction) v_rel = v2[ct.m2] - v1[ct.m1];
        if constexpr (kDamping) {
            const double v_n = v_rel.dot(n);
            normal_force -= c * v_n;
            if (first_evaluation_of_step) dissipated_damping_ += c * v_n * v_n * h;
        }
        ct.normal_force = normal_force;
        Vec3 force2 = normal_force * n;

        if constexpr (kFriction) {
            if (first_evaluation_of_step) {
                // ξ₀: the previous spring rotated onto this tangent plane plus the tangential motion
                // of the previous step (h·v_t); a new contact is anchored here with ξ₀ = 0.
                const Vec3 v_t = tangential_part(v_rel, n);
                ct.shear_start =
                    ct.has_history ? Vec3(rotate_onto_tangent_plane(ct.shear_start, n) + h * v_t) : Vec3::Zero();
                ct.u_start = u;
            }
            const double kt = parameters_.tangential_stiffness_ratio * ct.ks;
            const Vec3 v_t = tangential_part(v_rel, n);
            // ξ(x) = ξ₀ + P·(u − u₀); spring force f_s = −kt·ξ
            const Vec3 shear = ct.shear_start + tangential_part(u - ct.u_start, n);
            const double spring_norm = kt * shear.norm();
            const double abs_fn = std::abs(normal_force);
            const double cap = (ct.slid_last_step ? ct.mu_v : ct.mu_s) * abs_fn;
            if (spring_norm <= cap) {
                // sticking: spring plus damper, the damper scaled by α ∈ [0, 1] so that
                // |f_s + α·f_d| ≤ cap (Coulomb's bound holds for the whole tangential force)
                ct.friction_state = FrictionState::sticking;
                const Vec3 spring_force = -kt * shear;
                const Vec3 damper_force = -c_t * v_t;
                double alpha = 1.0;
                const double b2 = damper_force.squaredNorm();
                if (b2 > 0.0 && (spring_force + damper_force).norm() > cap) {
                    const double ab = spring_force.dot(damper_force);
                    const double discriminant = ab * ab - b2 * (spring_force.squaredNorm() - cap * cap);
                    alpha = std::clamp((-ab + std::sqrt(std::max(0.0, discriminant))) / b2, 0.0, 1.0);
                }
                ct.damper_scale = alpha;
                ct.tangential_force = spring_force + alpha * damper_force;
                ct.shear = shear;
                if (first_evaluation_of_step) dissipated_damping_ += alpha * c_t * v_t.squaredNorm() * h;
            } else {
                // sliding: the spring is cut back to the dynamic cap (never lengthened) and the
                // anchor moves by the slip
                ct.friction_state = FrictionState::sliding;
                ct.damper_scale = 0.0;
                const double sliding_force = std::min(ct.mu_v * abs_fn, spring_norm);
                ct.shear = (sliding_force / spring_norm) * shear;
                ct.tangential_force = -kt * ct.shear;
                // Coulomb work of the slip: sliding force × slip length (m)
                if (first_evaluation_of_step) dissipated_sliding_ += sliding_force * (shear.norm() - ct.shear.norm());
            }
            // the anchor moved at the step start belongs to the whole step
            if (first_evaluation_of_step) ct.shear_start = ct.shear;
            force2 += ct.tangential_force;
        }

        f1[ct.m1] -= force2;
        f2[ct.m2] += force2;
    }
}

void PenaltyForceField::add_dforce(Vec3Span df1, Vec3Span df2, ConstVec3Span dx1, ConstVec3Span dx2, double k_factor,
                                   double b_factor) const {
    if (df1.size() != dx1.size() || df2.size() != dx2.size())
        throw_invalid_argument("PenaltyForceField::add_dforce(): df sizes (", df1.size(), ", ", df2.size(),
                               ") differ from dx sizes (", dx1.size(), ", ", dx2.size(), ")");
    check_indices("add_dforce", dx1.size(), dx2.size());
    const double c = parameters_.damping;
    const double c_t = parameters_.tangential_damping;
    const double ratio = parameters_.tangential_stiffness_ratio;
    const bool friction = parameters_.friction == FrictionModel::coulomb;
    const bool sofa_path = c == 0.0 && !friction;
    for (const PenaltyContact& ct : contacts_) {
        if (!(ct.pen > 0.0)) continue;  // SOFA: the active set of the last add_force
        if (sofa_path) {
            add_sofa_contact_dforce(ct.normal, ct.ks, dx1[ct.m1], dx2[ct.m2], k_factor, df1[ct.m1], df2[ct.m2]);
            continue;
        }
        const Vec3& n = ct.normal;
        const Vec3 du = dx2[ct.m2] - dx1[ct.m1];
        // df2 = −(kF·ks + bF·c)·n·(n·du)  [normal spring and dashpot]
        Vec3 ddf2 = -(k_factor * ct.ks + b_factor * c) * n.dot(du) * n;
        if (friction && ct.friction_state == FrictionState::sticking) {
            // df2 −= (kF·kt + bF·c_t)·P·du  [sticking tangential spring and damper]
            ddf2 -= (k_factor * ratio * ct.ks + b_factor * ct.damper_scale * c_t) * tangential_part(du, n);
        }
        df1[ct.m1] -= ddf2;
        df2[ct.m2] += ddf2;
    }
}

namespace {

/// Appends the four 3×3 blocks of one contact: (1,1): −B, (1,2): +B, (2,1): +B, (2,2): −B.
void append_contact_blocks(TripletList& triplets, const Mat3& block, Index row1, Index row2) {
    for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) {
            const double value = block(a, b);
            if (value == 0.0) continue;
            triplets.emplace_back(row1 + a, row1 + b, -value);
            triplets.emplace_back(row1 + a, row2 + b, value);
            triplets.emplace_back(row2 + a, row1 + b, value);
            triplets.emplace_back(row2 + a, row2 + b, -value);
        }
    }
}

SparseMatrix to_matrix(const TripletList& triplets, Index n1, Index n2, bool same_state) {
    const Index size = same_state ? 3 * n1 : 3 * (n1 + n2);
    SparseMatrix matrix(size, size);
    matrix.setFromTriplets(triplets.begin(), triplets.end());
    return matrix;
}

}  // namespace

void PenaltyForceField::add_stiffness_triplets(TripletList& triplets, Index offset1, Index offset2,
                                               double factor) const {
    const bool friction = parameters_.friction == FrictionModel::coulomb;
    // at most 4 blocks of 3×3 per contact; geometric growth keeps repeated appends amortised
    const std::size_t needed = triplets.size() + 36 * contacts_.size();
    if (triplets.capacity() < needed) triplets.reserve(std::max(needed, 2 * triplets.capacity()));
    for (const PenaltyContact& ct : contacts_) {
        if (!(ct.pen > 0.0)) continue;
        const Vec3& n = ct.normal;
        // B = factor·(ks·n·nᵀ + kt·P while sticking)
        Mat3 block = ct.ks * n * n.transpose();
        if (friction && ct.friction_state == FrictionState::sticking)
            block += parameters_.tangential_stiffness_ratio * ct.ks * (Mat3::Identity() - n * n.transpose());
        append_contact_blocks(triplets, factor * block, offset1 + 3 * ct.m1, offset2 + 3 * ct.m2);
    }
}

void PenaltyForceField::add_damping_triplets(TripletList& triplets, Index offset1, Index offset2, double factor) const {
    const double c = parameters_.damping;
    const double c_t = parameters_.tangential_damping;
    const bool friction = parameters_.friction == FrictionModel::coulomb;
    if (c == 0.0 && (!friction || c_t == 0.0)) return;  // SOFA: empty damping matrix
    for (const PenaltyContact& ct : contacts_) {
        if (!(ct.pen > 0.0)) continue;
        const Vec3& n = ct.normal;
        Mat3 block = c * n * n.transpose();
        if (friction && ct.friction_state == FrictionState::sticking)
            block += ct.damper_scale * c_t * (Mat3::Identity() - n * n.transpose());
        append_contact_blocks(triplets, factor * block, offset1 + 3 * ct.m1, offset2 + 3 * ct.m2);
    }
}

void PenaltyForceField::check_matrix_sizes(const char* function, Index n1, Index n2, bool same_state) const {
    if (n1 < 0) throw_invalid_argument("PenaltyForceField::", function, "(): n1 = ", n1, " must be >= 0");
    if (!same_state && n2 < 0)
        throw_invalid_argument("PenaltyForceField::", function, "(): n2 = ", n2, " must be >= 0");
    // a contact outside its state would write outside the matrix
    check_indices(function, std::size_t(n1), std::size_t(same_state ? n1 : n2));
}

SparseMatrix PenaltyForceField::stiffness_matrix(Index n1, Index n2, bool same_state) const {
    check_matrix_sizes("stiffness_matrix", n1, n2, same_state);
    TripletList triplets;
    add_stiffness_triplets(triplets, 0, same_state ? 0 : 3 * n1);
    return to_matrix(triplets, n1, n2, same_state);
}

SparseMatrix PenaltyForceField::damping_matrix(Index n1, Index n2, bool same_state) const {
    check_matrix_sizes("damping_matrix", n1, n2, same_state);
    TripletList triplets;
    add_damping_triplets(triplets, 0, same_state ? 0 : 3 * n1);
    return to_matrix(triplets, n1, n2, same_state);
}

double PenaltyForceField::potential_energy() const {
    const double ratio = parameters_.tangential_stiffness_ratio;
    const bool friction = parameters_.friction == FrictionModel::coulomb;
    double energy = 0.0;
    for (const PenaltyContact& ct : contacts_) {
        if (!(ct.pen > 0.0)) continue;
        energy += 0.5 * ct.ks * ct.pen * ct.pen;                               // ½·ks·pen²
        if (friction) energy += 0.5 * ratio * ct.ks * ct.shear.squaredNorm();  // ½·kt·|ξ|²
    }
    return energy;
}

void PenaltyForceField::reset_dissipated_energy() {
    dissipated_damping_ = 0.0;
    dissipated_sliding_ = 0.0;
}

std::size_t PenaltyForceField::active_count() const {
    return static_cast<std::size_t>(
        std::count_if(contacts_.begin(), contacts_.end(), [](const PenaltyContact& c) { return c.pen > 0.0; }));
}

std::vector<ContactSegment> PenaltyForceField::export_contacts(ConstVec3Span x1, ConstVec3Span x2) const {
    check_indices("export_contacts", x1.size(), x2.size());
    std::vector<ContactSegment> segments;
    segments.reserve(contacts_.size());
    for (const PenaltyContact& ct : contacts_) {
        ContactSegment& s = segments.emplace_back();
        s.point1 = x1[ct.m1];
        s.point2 = x2[ct.m2];
        s.normal = ct.normal;
        s.pen = ct.dist - (s.point2 - s.point1).dot(ct.normal);
        s.age = ct.age;
        s.force = ct.pen > 0.0 ? Vec3(ct.normal_force * ct.normal + ct.tangential_force) : Vec3::Zero();
        s.index1 = ct.index1;
        s.index2 = ct.index2;
    }
    return segments;
}

std::vector<GrabbedPoint> PenaltyForceField::grab_points(ContactSide tool_side, std::span<const DofIndex> tool_dofs,
                                                         ConstVec3Span other_positions) const {
    std::vector<GrabbedPoint> grabbed;
    for (std::size_t i = 0; i < contacts_.size(); ++i) {
        const PenaltyContact& ct = contacts_[i];
        const DofIndex tool_dof(tool_side == ContactSide::first ? ct.m1 : ct.m2);
        const Index other_dof = tool_side == ContactSide::first ? ct.m2 : ct.m1;
        const ElementIndex other_element(tool_side == ContactSide::first ? ct.index2 : ct.index1);
        for (const DofIndex dof : tool_dofs) {
            if (dof != tool_dof) continue;
            if (static_cast<std::size_t>(other_dof) >= other_positions.size())
                throw_invalid_argument("PenaltyForceField::grab_points(): contact ", i, ": other-side DOF ", other_dof,
                                       " is outside the given positions (size ", other_positions.size(), ")");
            grabbed.push_back({other_positions[static_cast<std::size_t>(other_dof)], other_element, dof});
        }
    }
    return grabbed;
}

}  // namespace penalty
