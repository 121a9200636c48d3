#pragma once
/// @file
/// DiagonalMass<Rigid3> (SOFA's DiagonalMass.cpp, initRigidImpl): one rigid mass per frame as the
/// scene gives it (`vertexMass`: mass m_i, volume, inertia J_i per unit mass), no lumping from a
/// topology. Per frame, as SOFA's RigidMass operators: M_i·d = (m_i·d_lin, (J_i·m_i)·d_ang) with
/// J_i·m_i not rotated to the world frame; gravity f_lin += g·m_i, no torque. Frames past the
/// list have no mass (SOFA's DiagonalMass does not pad a Rigid3 list: its padding test is never
/// true).
#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/mechanical_object.hpp"

#include <vector>

namespace penalty {

class RigidDiagonalMass final : public BaseMass {
public:
    /// One frame's mass: m (kg) and the inertia per unit mass J (m²).
    struct FrameMass {
        double mass = 1.0;
        Mat3 inertia = Mat3::Identity();
    };
    /// `masses`: each mass finite and > 0, each J symmetric with a positive determinant
    /// (std::invalid_argument otherwise).
    RigidDiagonalMass(Rigid3Object& state, std::vector<FrameMass> masses);

    void add_gravity_force(const Vec3& gravity) override;
    void add_mdx(double factor) override;
    void apply_inverse(const Eigen::Ref<const Eigen::VectorXd>& in, Eigen::Ref<Eigen::VectorXd> out) const override;
    void add_mass_triplets(TripletList& triplets, Index offset, double factor) const override;
    [[nodiscard]] double kinetic_energy() const override;
    [[nodiscard]] double gravity_potential_energy(const Vec3& gravity) const override;
    [[nodiscard]] double total_mass() const override;
    [[nodiscard]] BaseState* state() const override { return state_; }
    [[nodiscard]] const std::vector<FrameMass>& masses() const { return masses_; }

private:
    /// The frames with a mass: min(list, state).
    [[nodiscard]] std::size_t count() const;
    Rigid3Object* state_;
    std::vector<FrameMass> masses_;
    std::vector<Mat3> inertia_mass_;  ///< J_i·m_i (SOFA's inertiaMassMatrix)
};

}  // namespace penalty
