#pragma once
/// @file
/// Contact mappers (SOFA's ContactMapper<Model, Vec3>, spec §8): each one turns
/// (element, world point P) of a collision model into a Vec3 *contact point* attached to the
/// model's DOFs, and moves displacements and forces between the contact points and those DOFs.
///
///   Identity    (Point, Sphere<Vec3>): the contact point IS the DOF (index = element index);
///               P is ignored; a sphere sets r = radius(element).
///   Barycentric (Line, Triangle incl. split quads, Tetrahedron): x = Σ w_i x_vi with weights
///               computed from P at add_point and frozen for the step (a ContactBarycentricRow, the
///               Jacobian BarycentricMapping uses too).
///   Rigid       (RigidSphere, Cylinder): local point L = R⁻¹(P − c), frozen for the step;
///               x = c + R·L, v = v_c + ω × (R·L); Jᵀ: force F and torque (R·L) × F (a
///               RigidPointRow, the Jacobian RigidMapping uses too).
///
/// Parent vectors are passed flat (std::span<double>): a Vec3 parent uses 3 scalars per DOF
/// (x y z), a Rigid3 parent 6 (linear x y z, then angular x y z, world frame), the layout of
/// MechanicalObject's flat views. J maps parent velocities/displacements to contact-point ones:
/// apply_j: out = J·dq;  apply_jt: parent_f += Jᵀ·f.  By construction f·(J·dq) = (Jᵀ·f)·dq.

#include "penalty/collision/models.hpp"
#include "penalty/core/index_types.hpp"
#include "penalty/core/types.hpp"
#include "penalty/mechanics/mapping.hpp"

#include <array>
#include <memory>
#include <span>
#include <vector>

namespace penalty {

/// How the radius of a RigidSphereModel enters the contact rest distance (spec §1, §7.3).
enum class RigidSphereRadius : std::uint8_t {
    sofa_head,    ///< default: r = radius (SOFA HEAD, PR #6204, 2026-08)
    sofa_v26_06,  ///< r = 0 (SOFA ≤ v26.06: the line was commented out)
};

/// Kind of mapper a model gets.
enum class ContactMapperKind : std::uint8_t { identity, barycentric, rigid };

/// Abstract contact mapper of one collision model (one per side of a model pair).
class ContactMapper {
public:
    virtual ~ContactMapper() = default;

    [[nodiscard]] virtual ContactMapperKind kind() const = 0;
    [[nodiscard]] virtual const CollisionModel& model() const = 0;

    /// Forgets every contact point, reserving `n` (SOFA's resize before a step's addPoint calls).
    virtual void resize(std::size_t n) = 0;
    /// Adds a contact point for `element` at world point P (m); returns its DOF in the contact
    /// state (the DOF the penalty spring acts on). May set r (m): the part of the rest distance the mapper accounts for
    /// (sphere radius), left untouched otherwise. Throws std::invalid_argument naming the model and the element for an
    /// element out of range or a non-finite P.
    virtual DofIndex add_point(const Vec3& P, ElementIndex element, double& r) = 0;
    /// Recomputes contact-point positions and velocities from the parent state (frozen weights
    /// / local points).
    virtual void update() = 0;

    /// Contact-point positions (m) and velocities (m/s) as of the last update() (identity: live).
    [[nodiscard]] virtual ConstVec3Span positions() const = 0;
    [[nodiscard]] virtual ConstVec3Span velocities() const = 0;
    /// Number of contact points (identity: number of parent DOFs).
    [[nodiscard]] std::size_t size() const { return positions().size(); }

    /// Scalars per parent DOF: 3 (Vec3) or 6 (Rigid3).
    [[nodiscard]] virtual int parent_deriv_size() const = 0;
    [[nodiscard]] virtual std::size_t parent_size() const = 0;
    [[nodiscard]] std::size_t parent_scalar_size() const {
        return parent_size() * static_cast<std::size_t>(parent_deriv_size());
    }

    /// out = J·dq (overwrites; out.size() == size(), dq.size() == parent_scalar_size()).
    virtual void apply_j(std::span<const double> dq, Vec3Span out) const = 0;
    /// parent_f += Jᵀ·f (f.size() == size(), parent_f.size() == parent_scalar_size()).
    virtual void apply_jt(ConstVec3Span f, std::span<double> parent_f) const = 0;
    /// J as triplets: row 3·i + a of contact point i, column of parent scalar, plus offsets.
    virtual void add_jacobian_triplets(TripletList& triplets, Index row_offset, Index col_offset) const = 0;

protected:
    void check_sizes(const char* function, std::size_t contact_size, std::size_t parent_scalars) const;
};

/// Point and Sphere<Vec3>: no new DOF; the spring acts on the model's own DOFs.
class IdentityContactMapper final : public ContactMapper {
public:
    /// `model` must be a PointModel or a SphereModel.
    explicit IdentityContactMapper(const CollisionModel& model);
    [[nodiscard]] ContactMapperKind kind() const override { return ContactMapperKind::identity; }
    [[nodiscard]] const CollisionModel& model() const override { return *model_; }
    void resize(std::size_t) override {}
    /// Returns the DOF of the same number as `element` (a point's or sphere's element is its DOF);
    /// a sphere sets r = radius(element); P is ignored.
    DofIndex add_point(const Vec3& P, ElementIndex element, double& r) override;
    void update() override {}
    [[nodiscard]] ConstVec3Span positions() const override { return state_->position; }
    [[nodiscard]] ConstVec3Span velocities() const override;
    [[nodiscard]] int parent_deriv_size() const override { return 3; }
    [[nodiscard]] std::size_t parent_size() const override { return state_->size(); }
    void apply_j(std::span<const double> dq, Vec3Span out) const override;
    void apply_jt(ConstVec3Span f, std::span<double> parent_f) const override;
    void add_jacobian_triplets(TripletList& triplets, Index row_offset, Index col_offset) const override;

private:
    const CollisionModel* model_;
    const Vec3State* state_;
    const SphereModel* sphere_ = nullptr;
    mutable std::vector<Vec3> zero_velocity_;  // when the state has no velocities
};

/// Line, Triangle (with split quads) and Tetrahedron: contact points are linear combinations of
/// the element's vertices (SOFA's BarycentricContactMapper over the model's topology, §8.1).
class BarycentricContactMapper final : public ContactMapper {
public:
    /// `model` must be a LineModel, TriangleModel or TetrahedronModel.
    explicit BarycentricContactMapper(const CollisionModel& model);
    [[nodiscard]] ContactMapperKind kind() const override { return ContactMapperKind::barycentric; }
    [[nodiscard]] const CollisionModel& model() const override { return *model_; }
    void resize(std::size_t n) override;
    /// Computes the weights of P in the element (r untouched) and returns the new point's index:
    ///  Line (v0,v1): f = ((P−x0)·(x1−x0))/|x1−x0|² (0 if |x1−x0|² < eps), not clamped;
    ///               weights (1−f, f).
    ///  Triangle t < nbTri: Gram solve for (a, b); outside → SOFA's projection on the closest
    ///               edge/vertex (thresholds 0 and 1); weights (1−a−b, a, b).
    ///  Triangle t ≥ nbTri (from quad k = (t − nbTri)/2, vertices q0..q3): (fx, fy) = first two
    ///               components of [u w u×w]⁻¹(P − x_q0), u = x_q1 − x_q0, w = x_q3 − x_q0, not
    ///               clamped; bilinear weights ((1−fx)(1−fy), fx(1−fy), fx·fy, (1−fx)fy).
    ///  Tetrahedron: (fx, fy, fz) = coord2bary·(P − x_p0), weights (1−fx−fy−fz, fx, fy, fz).
    DofIndex add_point(const Vec3& P, ElementIndex element, double& r) override;
    void update() override;
    [[nodiscard]] ConstVec3Span positions() const override { return positions_; }
    [[nodiscard]] ConstVec3Span velocities() const override { return velocities_; }
    [[nodiscard]] int parent_deriv_size() const override { return 3; }
    [[nodiscard]] std::size_t parent_size() const override { return state_->size(); }
    void apply_j(std::span<const double> dq, Vec3Span out) const override;
    void apply_jt(ConstVec3Span f, std::span<double> parent_f) const override;
    void add_jacobian_triplets(TripletList& triplets, Index row_offset, Index col_offset) const override;

    [[nodiscard]] const std::vector<ContactBarycentricRow>& rows() const { return rows_; }

private:
    [[nodiscard]] ContactBarycentricRow compute_row(const Vec3& P, Index element) const;
    const CollisionModel* model_;
    const Vec3State* state_;
    std::vector<ContactBarycentricRow> rows_;
    std::vector<Vec3> positions_;
    std::vector<Vec3> velocities_;
};

/// Weights (1−f, f) of P on segment (a, b), SOFA's line mapper (not clamped).
[[nodiscard]] std::array<double, 2> line_contact_weights(const Vec3& a, const Vec3& b, const Vec3& P);
/// (a, b) coordinates of P in triangle (p0, p1, p2), projected on the closest feature when the
/// projection is outside (SOFA's BarycentricMapperMeshTopology triangle rule).
[[nodiscard]] std::array<double, 2> triangle_contact_coordinates(const Vec3& p0, const Vec3& p1, const Vec3& p2,
                                                                 const Vec3& P);
/// (fx, fy) of P in the quad (q0, q1, q2, q3) frame, not clamped.
[[nodiscard]] std::array<double, 2> quad_contact_coordinates(const Vec3& q0, const Vec3& q1, const Vec3& q3,
                                                             const Vec3& P);

/// RigidSphere and Cylinder: contact points rigidly attached to a body frame (§8.3).
class RigidContactMapper final : public ContactMapper {
public:
    /// `model` must be a RigidSphereModel or a CylinderModel.
    explicit RigidContactMapper(const CollisionModel& model,
                                RigidSphereRadius radius_rule = RigidSphereRadius::sofa_head);
    [[nodiscard]] ContactMapperKind kind() const override { return ContactMapperKind::rigid; }
    [[nodiscard]] const CollisionModel& model() const override { return *model_; }
    void resize(std::size_t n) override;
    /// L = R_e⁻¹(P − c_e); rigid sphere: r = radius(e) under sofa_head, untouched (0) under
    /// sofa_v26_06; cylinder: r untouched.
    DofIndex add_point(const Vec3& P, ElementIndex element, double& r) override;
    /// x = c + R·L, v = v_c + ω × (R·L) (rotated points R·L kept for apply_j / apply_jt).
    void update() override;
    [[nodiscard]] ConstVec3Span positions() const override { return positions_; }
    [[nodiscard]] ConstVec3Span velocities() const override { return velocities_; }
    [[nodiscard]] int parent_deriv_size() const override { return 6; }
    [[nodiscard]] std::size_t parent_size() const override { return state_->size(); }
    /// out_i = dc + dω × (R·L_i)
    void apply_j(std::span<const double> dq, Vec3Span out) const override;
    /// force += F_i, torque += (R·L_i) × F_i
    void apply_jt(ConstVec3Span f, std::span<double> parent_f) const override;
    void add_jacobian_triplets(TripletList& triplets, Index row_offset, Index col_offset) const override;

    /// Frame (= element), local point L and R·L (at the last update) of each contact point.
    [[nodiscard]] const std::vector<RigidPointRow>& points() const { return rows_; }

private:
    const CollisionModel* model_;
    const Rigid3State* state_;
    const RigidSphereModel* sphere_ = nullptr;
    RigidSphereRadius radius_rule_;
    std::vector<RigidPointRow> rows_;
    std::vector<Vec3> positions_;
    std::vector<Vec3> velocities_;
};

/// The mapper SOFA uses for the model's type.
[[nodiscard]] std::unique_ptr<ContactMapper> make_contact_mapper(
    const CollisionModel& model, RigidSphereRadius radius_rule = RigidSphereRadius::sofa_head);

/// Flat views of Vec3 / RigidDeriv vectors (for the parent arguments of apply_j / apply_jt).
[[nodiscard]] inline std::span<double> flat_span(std::vector<Vec3>& v) {
    return {reinterpret_cast<double*>(v.data()), v.size() * 3};
}
[[nodiscard]] inline std::span<const double> flat_span(const std::vector<Vec3>& v) {
    return {reinterpret_cast<const double*>(v.data()), v.size() * 3};
}
[[nodiscard]] inline std::span<double> flat_span(std::vector<RigidDeriv>& v) {
    return {reinterpret_cast<double*>(v.data()), v.size() * 6};
}
[[nodiscard]] inline std::span<const double> flat_span(const std::vector<RigidDeriv>& v) {
    return {reinterpret_cast<const double*>(v.data()), v.size() * 6};
}

}  // namespace penalty
