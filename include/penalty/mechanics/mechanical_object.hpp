#pragma once
/// @file
/// SOFA's MechanicalObject: a MechanicalState plus the solver work vectors (dx, df) and a
/// type-erased interface (BaseState) through which solvers see every state as flat vectors of
/// scalars. Flat layout: DOF i occupies scalars [i*deriv_size, (i+1)*deriv_size); Vec3 = x y z;
/// Rigid3 = linear x y z then angular x y z (world frame).

#include "penalty/core/error.hpp"
#include "penalty/core/types.hpp"
#include "penalty/mechanics/state.hpp"

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace penalty {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be 3 packed doubles");
static_assert(sizeof(RigidDeriv) == 6 * sizeof(double), "RigidDeriv must be 6 packed doubles");

using FlatVector = Eigen::Map<Eigen::VectorXd>;
using ConstFlatVector = Eigen::Map<const Eigen::VectorXd>;

/// Type-erased mechanical state seen by solvers, mappings and constraints.
class BaseState {
public:
    virtual ~BaseState() = default;
    [[nodiscard]] virtual std::string_view state_name() const = 0;
    [[nodiscard]] virtual std::size_t num_dofs() const = 0;
    [[nodiscard]] virtual int deriv_size() const = 0;
    [[nodiscard]] std::size_t scalar_size() const { return num_dofs() * static_cast<std::size_t>(deriv_size()); }

    /// Flat views of the derivative-sized vectors (length scalar_size()).
    virtual FlatVector velocity_flat() = 0;
    virtual FlatVector force_flat() = 0;
    virtual FlatVector external_force_flat() = 0;
    virtual FlatVector dx_flat() = 0;  ///< solver work vector: a displacement / velocity increment
    virtual FlatVector df_flat() = 0;  ///< solver work vector: a force increment

    /// x <- x + h·v for the flat velocity-like vector v (Rigid3: SOFA HEAD's Coord + Deriv,
    /// the exponential q ← exp(h·ω/2) ⊗ q, rigid_add).
    virtual void add_to_position(double h, const Eigen::Ref<const Eigen::VectorXd>& v) = 0;

    /// Sizes every vector to the number of positions (velocity, force ... zero-filled).
    virtual void init() = 0;

    /// A static state: outside every ODE solver's subtree, not a mapping's output, and read by no
    /// explicit force field (Simulation::solve_plan marks them; false until then). Only the solves
    /// that read it as an outside state write its force, dx and df, as scratch (SubtreeSystem):
    /// each then clears only the rows it and the solves before it may have written, recorded
    /// here, instead of passing over the whole vectors (a large static obstacle).
    [[nodiscard]] bool is_static() const { return static_; }
    /// Changing the mark forgets the records (the next solve clears the whole vectors).
    void set_static(bool is_static) {
        if (is_static == static_) return;
        static_ = is_static;
        static_force_rows = {};
        static_work_rows = {};
    }
    /// The rows of a static state's vectors that may be non-zero: outside them, every value is 0.
    struct ScratchRows {
        bool known = false;               ///< false: any row may be non-zero
        std::size_t dofs = 0;             ///< num_dofs() when `rows` was recorded
        std::vector<std::uint32_t> rows;  ///< DOFs, any order, possibly repeated
        /// The record holds for a state of `n` DOFs.
        [[nodiscard]] bool holds_for(std::size_t n) const { return known && dofs == n; }
    };
    ScratchRows static_force_rows;  ///< of force
    ScratchRows static_work_rows;   ///< of dx and df

private:
    bool static_ = false;
};

/// Applies SOFA's MechanicalObject init transform to a point: scale3d, then the rotation given as
/// Euler angles in degrees (R = Rz·Ry·Rx), then translation.
struct InitialTransform {
    Vec3 translation = Vec3::Zero();
    Vec3 rotation_deg = Vec3::Zero();
    Vec3 scale3d = Vec3::Ones();
    [[nodiscard]] bool is_identity() const {
        return translation.isZero(0) && rotation_deg.isZero(0) && scale3d == Vec3::Ones();
    }
    /// Rotation of the Euler angles (degrees, x then y then z, i.e. R = Rz(z)·Ry(y)·Rx(x)), computed
    /// as SOFA's Quat::createQuaterFromEuler(angles · π / 180) (ZYX order), operation by operation.
    [[nodiscard]] Quat rotation() const;
};

/// MechanicalObject<Vec3d | Rigid3d | Vec1d>. Fill `position` (and optionally `velocity`,
/// `rest_position`, `transform`) then call init(), which follows SOFA: rest positions given
/// without positions become the positions; missing velocities repeat the last given one (zero if
/// none); `transform` (scale3d, rotation, translation) is applied to the positions only; rest
/// positions not given (or of another size) are copied from the transformed positions.
template <class DataTypes>
class MechanicalObject final : public BaseState, public MechanicalState<DataTypes> {
public:
    using Coord = typename DataTypes::Coord;
    using Deriv = typename DataTypes::Deriv;
    using State = MechanicalState<DataTypes>;

    // NOLINTNEXTLINE(performance-unnecessary-value-param): a sink, moved into the dependent base's name
    explicit MechanicalObject(std::string object_name = "dofs") { this->name = std::move(object_name); }

    InitialTransform transform;  ///< applied once by init() to the positions
    std::vector<Deriv> dx;       ///< solver work vector
    std::vector<Deriv> df;       ///< solver work vector

    [[nodiscard]] std::string_view state_name() const override { return this->name; }
    [[nodiscard]] std::size_t num_dofs() const override { return this->position.size(); }
    [[nodiscard]] int deriv_size() const override { return DataTypes::kDerivSize; }

    FlatVector velocity_flat() override { return flat(this->velocity); }
    FlatVector force_flat() override { return flat(this->force); }
    FlatVector external_force_flat() override { return flat(this->external_force); }
    FlatVector dx_flat() override { return flat(dx); }
    FlatVector df_flat() override { return flat(df); }

    void add_to_position(double h, const Eigen::Ref<const Eigen::VectorXd>& v) override;
    void init() override;

    /// Flat view of a vector of Deriv.
    static FlatVector flat(std::vector<Deriv>& v) {
        return FlatVector(reinterpret_cast<double*>(v.data()),
                          static_cast<Eigen::Index>(v.size()) * DataTypes::kDerivSize);
    }
    static ConstFlatVector flat(const std::vector<Deriv>& v) {
        return ConstFlatVector(reinterpret_cast<const double*>(v.data()),
                               static_cast<Eigen::Index>(v.size()) * DataTypes::kDerivSize);
    }

private:
    bool initialized_ = false;
};

using Vec3Object = MechanicalObject<Vec3Types>;
using Rigid3Object = MechanicalObject<Rigid3Types>;
using Vec1Object = MechanicalObject<Vec1Types>;

/// SOFA's Rigid3 Coord + Deriv·h (RigidCoord::operator+=, R³ × SO(3) exponential integration):
/// centre += v·h; with ω = (ω·h)/2 and θ = |ω|: q ← (sin θ/θ·ω, cos θ) ⊗ q, or for θ < ε the
/// gnomonic (ω, 1)/|(ω, 1)| ⊗ q (unit quaternions stay unit: no normalisation of the result).
RigidFrame rigid_add(const RigidFrame& x, const RigidDeriv& v, double h);

/// Views a flat vector as Derivs (the length must be a multiple of kDerivSize).
template <class DataTypes>
std::span<typename DataTypes::Deriv> as_derivs(Eigen::Ref<Eigen::VectorXd> v) {
    PENALTY_ASSERT(v.size() % DataTypes::kDerivSize == 0);
    return {reinterpret_cast<typename DataTypes::Deriv*>(v.data()),
            static_cast<std::size_t>(v.size() / DataTypes::kDerivSize)};
}

template <>
void MechanicalObject<Vec3Types>::add_to_position(double, const Eigen::Ref<const Eigen::VectorXd>&);
template <>
void MechanicalObject<Rigid3Types>::add_to_position(double, const Eigen::Ref<const Eigen::VectorXd>&);
template <>
void MechanicalObject<Vec3Types>::init();
/// Checks the frames (finite centres, finite non-zero quaternions) and applies the initial
/// transform; the orientations stay as given, as SOFA's (not normalized: a non-unit quaternion
/// maps a frame's points by a matrix that is not a rotation, and the integration keeps its norm).
template <>
void MechanicalObject<Rigid3Types>::init();
template <>
void MechanicalObject<Vec1Types>::add_to_position(double, const Eigen::Ref<const Eigen::VectorXd>&);
template <>
void MechanicalObject<Vec1Types>::init();

}  // namespace penalty
