#pragma once
/// @file
/// SOFA's UniformMass (spec §10.4) for Vec3d and Rigid3d, and FixedProjectiveConstraint.

#include "penalty/mechanics/followed_indices.hpp"
#include "penalty/mechanics/force_field.hpp"

#include <functional>
#include <optional>

namespace penalty {

/// UniformMass: the same mass m (kg) on every DOF.
///  - `vertexMass` m, or `totalMass` M with m = M / n; when both are set totalMass wins; when
///    neither is set init() throws (SOFA marks the component invalid);
///  - Vec3: M = m·I₃ per DOF, gravity force m·g;
///  - Rigid3: linear part m·I₃; angular part m·J with J the body inertia per unit mass (SOFA's
///    Rigid3Mass `inertiaMatrix`, default I₃), applied as SOFA does, without rotating J to the
///    world frame; gravity gives no torque.
template <class DataTypes>
class UniformMass final : public BaseMass {
public:
    explicit UniformMass(MechanicalObject<DataTypes>& state) : state_(&state) {}

    /// Mass per DOF (kg); must be finite and > 0.
    void set_vertex_mass(double m);
    /// Total mass (kg), spread uniformly; must be finite and > 0.
    void set_total_mass(double m);
    /// Rigid3 only: body inertia per unit mass (m²), symmetric positive definite.
    void set_inertia(const Mat3& inertia_per_unit_mass);

    /// Resolves the vertex mass from the data (throws std::invalid_argument if unset).
    void init() override;
    [[nodiscard]] double vertex_mass() const { return mass_; }
    /// SOFA's lazy update of a mass written after init (SofaQuirkFixes::fix_uniform_mass_lazy_write):
    /// the weight (add_gravity_force) uses `m` (kg per DOF) until the mass is next used as a mass
    /// (add_mdx, apply_inverse, add_mass_triplets: SOFA's isComponentStateValid() runs the update
    /// callback there), then vertex_mass() again.
    void set_lagging_weight_mass(double m) { lagging_weight_mass_ = m; }
    [[nodiscard]] std::optional<double> lagging_weight_mass() const { return lagging_weight_mass_; }

    void add_gravity_force(const Vec3& gravity) override;
    void add_mdx(double factor) override;
    void apply_inverse(const Eigen::Ref<const Eigen::VectorXd>& in, Eigen::Ref<Eigen::VectorXd> out) const override;
    void add_mass_triplets(TripletList& triplets, Index offset, double factor) const override;
    [[nodiscard]] double kinetic_energy() const override;
    [[nodiscard]] double gravity_potential_energy(const Vec3& gravity) const override;
    [[nodiscard]] BaseState* state() const override { return state_; }
    [[nodiscard]] double total_mass() const override { return mass_ * double(state_->num_dofs()); }

private:
    MechanicalObject<DataTypes>* state_;
    std::optional<double> vertex_mass_;
    std::optional<double> total_mass_;
    Mat3 inertia_ = Mat3::Identity();
    double mass_ = 0.0;
    mutable std::optional<double> lagging_weight_mass_;  ///< see set_lagging_weight_mass
};

/// FixedProjectiveConstraint: the listed DOFs (or all with fix_all) have zero response: projected
/// vectors get 0 at those DOFs; positions are not altered. Their velocity is set to 0 only with
/// project_velocity (SOFA's `activate_projectVelocity`, default false: FixedProjectiveConstraint::
/// projectVelocity returns at once, so a DOF keeps the velocity it had when it became fixed).
/// Its indices may follow an engine's output while the scene runs (followed_indices.hpp).
class FixedProjectiveConstraint final : public BaseProjectiveConstraint, public FollowedIndices {
public:
    explicit FixedProjectiveConstraint(BaseState& state) : state_(&state) {}
    void set_indices(std::vector<Index> indices) { indices_ = std::move(indices); }
    void set_fix_all(bool fix_all) { fix_all_ = fix_all; }
    void set_project_velocity(bool on) { project_velocity_ = on; }
    /// The indices as of their last read (the index source is not called).
    [[nodiscard]] const std::vector<Index>& indices() const { return indices_; }

    /// Checks the indices against the state size (std::invalid_argument when out of range).
    void init() override;
    void project_response(Eigen::Ref<Eigen::VectorXd> v) const override;
    void project_velocity() override;
    /// Every component of the fixed DOFs (FixedProjectiveConstraint::applyConstraint).
    [[nodiscard]] bool list_discarded_rows(std::vector<Index>& rows) const override;
    [[nodiscard]] BaseState* state() const override { return state_; }

private:
    /// The indices, from the index source when there is one.
    const std::vector<Index>& read_indices() const;
    BaseState* state_;
    mutable std::vector<Index> indices_;
    bool fix_all_ = false;
    bool project_velocity_ = false;
};

template <>
void UniformMass<Vec3Types>::add_gravity_force(const Vec3&);
template <>
void UniformMass<Vec3Types>::add_mdx(double);
template <>
void UniformMass<Vec3Types>::apply_inverse(const Eigen::Ref<const Eigen::VectorXd>&, Eigen::Ref<Eigen::VectorXd>) const;
template <>
void UniformMass<Vec3Types>::add_mass_triplets(TripletList&, Index, double) const;
template <>
double UniformMass<Vec3Types>::kinetic_energy() const;
template <>
double UniformMass<Vec3Types>::gravity_potential_energy(const Vec3&) const;
template <>
void UniformMass<Rigid3Types>::add_gravity_force(const Vec3&);
template <>
void UniformMass<Rigid3Types>::add_mdx(double);
template <>
void UniformMass<Rigid3Types>::apply_inverse(const Eigen::Ref<const Eigen::VectorXd>&,
                                             Eigen::Ref<Eigen::VectorXd>) const;
template <>
void UniformMass<Rigid3Types>::add_mass_triplets(TripletList&, Index, double) const;
template <>
double UniformMass<Rigid3Types>::kinetic_energy() const;
template <>
double UniformMass<Rigid3Types>::gravity_potential_energy(const Vec3&) const;
extern template class UniformMass<Vec3Types>;
extern template class UniformMass<Rigid3Types>;

}  // namespace penalty
