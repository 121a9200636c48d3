#include "penalty/mechanics/joint_spring_force_field.hpp"

#include "sofa_quaternion.hpp"
#include "sofa_vector_ops.hpp"

#include <charconv>
#include <cmath>
#include <numbers>
#include <string>

namespace penalty {

using sofa_vec::dot3;

// ---- parsing ----------------------------------------------------------------------------------
namespace {

class Tokens {
public:
    explicit Tokens(std::string_view text) : text_(text) {}
    /// The next blank-separated token ("" at the end).
    std::string_view next() {
        while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
        const std::size_t start = pos_;
        while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
        return text_.substr(start, pos_ - start);
    }
    double number(std::string_view what) {
        const std::string_view t = next();
        double v = 0;
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        if (t.empty() || ec != std::errc() || end != t.data() + t.size() || !std::isfinite(v))
            throw_invalid_argument("JointSpringForceField: spring: ", what, ": expected a number, found '", t, "'");
        return v;
    }
    Index index(std::string_view what) {
        const double v = number(what);
        if (!(v >= 0) || v != std::floor(v) || v > 4294967295.0)
            throw_invalid_argument("JointSpringForceField: spring: ", what, ": expected an index, found ", v);
        return static_cast<Index>(v);
    }
    bool flag(std::string_view what) {
        const double v = number(what);
        if (v != 0 && v != 1)
            throw_invalid_argument("JointSpringForceField: spring: ", what, ": expected 0 or 1, found ", v);
        return v != 0;
    }

private:
    std::string_view text_;
    std::size_t pos_ = 0;
};

}  // namespace

std::vector<JointSpring> parse_joint_springs(std::string_view text) {
    std::vector<JointSpring> springs;
    Tokens in(text);
    JointSpring s;  // one object read in turn, as type::vector::read (see the header)
    for (std::string_view word = in.next(); !word.empty(); word = in.next()) {
        if (word != "BEGIN_SPRING")
            throw_invalid_argument("JointSpringForceField: spring: expected BEGIN_SPRING, found '", word, "'");
        s.free_movements = {false, false, false, true, true, true};
        s.init_trans = Vec3::Zero();
        s.init_rot = Quat::Identity();
        s.bloc_rotation = 0.0;
        s.limit_angles = {-100000., 100000., -100000., 100000., -100000., 100000.};
        bool rest_found = false;
        s.m1 = in.index("m1");
        s.m2 = in.index("m2");
        for (word = in.next(); word != "END_SPRING"; word = in.next()) {
            if (word.empty()) throw_invalid_argument("JointSpringForceField: spring: missing END_SPRING");
            if (word == "FREE_AXIS") {
                for (bool& f : s.free_movements) f = in.flag("FREE_AXIS");
            } else if (word == "KS_T") {
                s.soft_translation = in.number("KS_T");
                s.hard_translation = in.number("KS_T");
            } else if (word == "KS_R") {
                s.soft_rotation = in.number("KS_R");
                s.hard_rotation = in.number("KS_R");
            } else if (word == "KS_B") {
                s.bloc_rotation = in.number("KS_B");
            } else if (word == "KD") {
                s.kd = in.number("KD");
            } else if (word == "R_LIM_X" || word == "R_LIM_Y" || word == "R_LIM_Z") {
                const std::size_t axis = static_cast<std::size_t>(word.back() - 'X');
                s.limit_angles[2 * axis] = in.number(word);
                s.limit_angles[2 * axis + 1] = in.number(word);
            } else if (word == "REST_T") {
                for (int k = 0; k < 3; ++k) s.init_trans[k] = in.number("REST_T");
                rest_found = true;
            } else if (word == "REST_R") {
                const double x = in.number("REST_R"), y = in.number("REST_R"), z = in.number("REST_R");
                s.init_rot = Quat(in.number("REST_R"), x, y, z);
            } else {
                throw_invalid_argument("JointSpringForceField: spring: unknown keyword '", word, "'");
            }
        }
        s.init_from_positions = rest_found;
        if (s.bloc_rotation == 0.0) s.bloc_rotation = s.hard_rotation / 100;
        for (std::size_t i = 0; i < 3; ++i)
            if (s.limit_angles[2 * i] == s.limit_angles[2 * i + 1]) s.free_movements[3 + i] = false;
        springs.push_back(s);
    }
    return springs;
}

// ---- force field ------------------------------------------------------------------------------
JointSpringForceField::JointSpringForceField(Rigid3Object& state1, Rigid3Object& state2,
                                             std::vector<JointSpring> springs)
    : s1_(&state1), s2_(&state2), springs_(std::move(springs)) {}

ForceFieldStates JointSpringForceField::states() const {
    if (s1_ == s2_) return ForceFieldStates(s1_);
    return {s1_, s2_};
}

void JointSpringForceField::init() {
    for (std::size_t k = 0; k < springs_.size(); ++k) {
        JointSpring& s = springs_[k];
        if (s.m1 < 0 || static_cast<std::size_t>(s.m1) >= s1_->num_dofs() || s.m2 < 0 ||
            static_cast<std::size_t>(s.m2) >= s2_->num_dofs())
            throw_invalid_argument("JointSpringForceField: spring ", k, " joins frames ", s.m1, " and ", s.m2,
                                   ", out of range (", s1_->num_dofs(), " and ", s2_->num_dofs(), " frames)");
        if (!s.init_from_positions) continue;  // JointSpringForceField::bwdInit
        const RigidFrame& x1 = s1_->position[static_cast<std::size_t>(s.m1)];
        const RigidFrame& x2 = s2_->position[static_cast<std::size_t>(s.m2)];
        s.init_trans = x2.center - x1.center;
        s.init_rot = sofa_quat::product(x2.orientation, sofa_quat::inverse(x1.orientation));
    }
}

namespace {

/// JointSpringForceField::projectTorsion: the torsion kept inside the limits of each free axis.
void project_torsion(JointSpring& s) {
    for (std::size_t i = 0; i < 3; ++i) {
        const double t = s.torsion[static_cast<Eigen::Index>(i)];
        const double lo = s.limit_angles[2 * i], hi = s.limit_angles[2 * i + 1];
        double& lawful = s.lawful_torsion[static_cast<Eigen::Index>(i)];
        if (!s.free_movements[3 + i]) {
            lawful = 0;
        } else if (t > lo && t < hi) {
            lawful = t;
        } else if (t > 0) {
            const double d1 = t - hi, d2 = lo + 2 * std::numbers::pi - t;
            lawful = d1 < d2 ? hi : lo;
        } else {
            const double d1 = t - hi + 2 * std::numbers::pi, d2 = lo - t;
            lawful = d1 < d2 ? hi : lo;
        }
    }
}

/// The pivot torque about free axis `a` (0, 1, 2) with the two others locked: the locked
/// components from the rotated axis column of M (SOFA's "pivot /x", "/y", "/z").
Vec3 pivot_torque(const JointSpring& s, const Quat& q, int a) {
    const Mat3 m = sofa_quat::to_matrix(q);
    Vec3 t = Vec3::Zero();
    if (a == 0) {
        const double cross_norm = std::sqrt(m(1, 0) * m(1, 0) + m(2, 0) * m(2, 0));
        const double theta = std::atan2(cross_norm, m(0, 0));
        t[0] = s.torsion[0] * s.kr[0];
        t[1] = -m(2, 0) * theta * s.kr[1];
        t[2] = m(1, 0) * theta * s.kr[2];
    } else if (a == 1) {
        const double cross_norm = std::sqrt(m(0, 1) * m(0, 1) + m(2, 1) * m(2, 1));
        const double theta = std::atan2(cross_norm, m(1, 1));
        t[0] = m(2, 1) * theta * s.kr[0];
        t[1] = s.torsion[1] * s.kr[1];
        t[2] = -m(0, 1) * theta * s.kr[2];
    } else {
        const double cross_norm = std::sqrt(m(1, 2) * m(1, 2) + m(0, 2) * m(0, 2));
        const double theta = std::atan2(cross_norm, m(2, 2));
        t[0] = -m(1, 2) * theta * s.kr[0];
        t[1] = m(0, 2) * theta * s.kr[1];
        t[2] = s.torsion[2] * s.kr[2];
    }
    return t;
}

bool inside(const JointSpring& s, int a) {
    return s.torsion[a] > s.limit_angles[2 * static_cast<std::size_t>(a)] &&
           s.torsion[a] < s.limit_angles[2 * static_cast<std::size_t>(a) + 1];
}

}  // namespace

// JointSpringForceField::addSpringForce, operation by operation (no input file: the constant
// force is zero, and 0 + a = a).
RigidDeriv JointSpringForceField::spring_force(JointSpring& s, const RigidFrame& x1, const RigidFrame& x2,
                                               const RigidDeriv& v1, const RigidDeriv& v2, double& energy) {
    s.ref = x1.orientation;
    const Vec3 d = (x2.center - x1.center) - s.init_trans;
    const Quat relative = sofa_quat::normalized(
        sofa_quat::product(sofa_quat::product(sofa_quat::inverse(x1.orientation), x2.orientation), s.init_rot));
    const Vec3 dv = v2.linear - v1.linear, dw = v2.angular - v1.angular;
    Vec3 axis = Vec3::Zero();
    double phi = 0;
    sofa_quat::to_axis_angle(relative, axis, phi);
    while (phi < -std::numbers::pi) phi += 2 * std::numbers::pi;
    while (phi > std::numbers::pi) phi -= 2 * std::numbers::pi;
    s.torsion = sofa_vec::scaled(axis, phi);

    const auto& free = s.free_movements;
    for (int i = 0; i < 3; ++i) s.kt[i] = free[static_cast<std::size_t>(i)] ? s.soft_translation : s.hard_translation;
    const Vec3 local = sofa_quat::inverse_rotate(s.ref, d);
    const Vec3 stretched(s.kt[0] * local[0], s.kt[1] * local[1], s.kt[2] * local[2]);
    const Vec3 constant = Vec3::Zero();  // SOFA's constant force (its `infile`, not supported)
    const Vec3 force = sofa_quat::rotate(s.ref, Vec3(constant + stretched)) + sofa_vec::scaled(dv, s.kd);

    for (int i = 0; i < 3; ++i) s.kr[i] = free[3 + static_cast<std::size_t>(i)] ? s.soft_rotation : s.hard_rotation;
    Vec3 tau = Vec3::Zero();
    if (!free[3] && !free[4] && !free[5]) {  // clamped
        for (int i = 0; i < 3; ++i) tau[i] = s.torsion[i] * s.kr[i];
    } else if (free[3] && !free[4] && !free[5] && inside(s, 0)) {
        tau = pivot_torque(s, relative, 0);
    } else if (!free[3] && free[4] && !free[5] && inside(s, 1)) {
        tau = pivot_torque(s, relative, 1);
    } else if (!free[3] && !free[4] && free[5] && inside(s, 2)) {
        tau = pivot_torque(s, relative, 2);
    } else {  // general case: beyond a limit, the bloc stiffness on the rotation past it
        project_torsion(s);
        Vec3 extra = s.torsion - s.lawful_torsion;
        double psi = std::sqrt(dot3(extra, extra));
        extra = Vec3(extra[0] / psi, extra[1] / psi, extra[2] / psi);
        while (psi < -std::numbers::pi) psi += 2 * std::numbers::pi;
        while (psi > std::numbers::pi) psi -= 2 * std::numbers::pi;
        extra = sofa_vec::scaled(extra, psi);
        for (int i = 0; i < 3; ++i) {
            if (free[3 + static_cast<std::size_t>(i)] && s.torsion[i] != s.lawful_torsion[i]) {
                s.kr[i] = s.bloc_rotation;
                tau[i] = extra[i] * s.kr[i];
            } else {
                tau[i] = s.torsion[i] * s.kr[i];
            }
        }
    }
    const Vec3 torque = sofa_quat::rotate(s.ref, Vec3(constant + tau)) + sofa_vec::scaled(dw, s.kd);
    for (int i = 0; i < 3; ++i) energy += 0.5 * (s.kt[i] * local[i] * local[i] + s.kr[i] * s.torsion[i] * s.torsion[i]);
    return {force, torque};
}

void JointSpringForceField::accumulate_force() {
    energy_ = 0;
    for (JointSpring& s : springs_) {
        const auto a = static_cast<std::size_t>(s.m1), b = static_cast<std::size_t>(s.m2);
        const RigidDeriv f =
            spring_force(s, s1_->position[a], s2_->position[b], s1_->velocity[a], s2_->velocity[b], energy_);
        s1_->force[a].linear += f.linear;
        s1_->force[a].angular += f.angular;
        s2_->force[b].linear -= f.linear;
        s2_->force[b].angular -= f.angular;
    }
}

// JointSpringForceField::addSpringDForce: dF = ref·(KT ⊙ ref⁻¹·Δ), Δ = dx2 − dx1, times k.
void JointSpringForceField::accumulate_dforce(double k_factor, double /*b_factor*/) {
    for (const JointSpring& s : springs_) {
        const auto a = static_cast<std::size_t>(s.m1), b = static_cast<std::size_t>(s.m2);
        const Vec3 dl = s2_->dx[b].linear - s1_->dx[a].linear;
        const Vec3 da = s2_->dx[b].angular - s1_->dx[a].angular;
        const Vec3 ll = sofa_quat::inverse_rotate(s.ref, dl), la = sofa_quat::inverse_rotate(s.ref, da);
        const Vec3 df = sofa_quat::rotate(s.ref, Vec3(s.kt[0] * ll[0], s.kt[1] * ll[1], s.kt[2] * ll[2]));
        const Vec3 dr = sofa_quat::rotate(s.ref, Vec3(s.kr[0] * la[0], s.kr[1] * la[1], s.kr[2] * la[2]));
        const Vec3 fl = sofa_vec::scaled(df, k_factor), fa = sofa_vec::scaled(dr, k_factor);
        s1_->df[a].linear += fl;
        s1_->df[a].angular += fa;
        s2_->df[b].linear -= fl;
        s2_->df[b].angular -= fa;
    }
}

void JointSpringForceField::add_stiffness(TripletList& t, const StateOffsets& offsets, double factor) const {
    const Index o1 = offsets(s1_), o2 = offsets(s2_);
    for (const JointSpring& s : springs_) {
        const Mat3 r = sofa_quat::to_matrix(s.ref);
        const Mat3 kt = r * s.kt.asDiagonal() * r.transpose();
        const Mat3 kr = r * s.kr.asDiagonal() * r.transpose();
        const Index rows[2] = {o1 + 6 * s.m1, o2 + 6 * s.m2};
        const double sign[2] = {-1.0, 1.0};  // df1 = K (dx2 − dx1), df2 = −K (dx2 − dx1)
        for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j) {
                const double sg = -sign[i] * sign[j] * factor;
                for (Index p = 0; p < 3; ++p)
                    for (Index q = 0; q < 3; ++q) {
                        t.emplace_back(rows[i] + p, rows[j] + q, sg * kt(p, q));
                        t.emplace_back(rows[i] + 3 + p, rows[j] + 3 + q, sg * kr(p, q));
                    }
            }
    }
}

}  // namespace penalty
