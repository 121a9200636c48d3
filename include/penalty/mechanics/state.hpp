#pragma once
/// @file
/// Mechanical states: SOFA's MechanicalObject for Vec3d and Rigid3d.
/// A state owns the per-DOF vectors of one simulated object. Layout: one Coord / Deriv per DOF.
///   Vec3d:   Coord = Vec3 (m),        Deriv = Vec3 (m/s or N).
///   Rigid3d: Coord = RigidFrame,       Deriv = RigidDeriv (linear part, then angular part,
///            both in world frame; force part = force (N) and torque (N·m)).
///   Vec1d:   Coord = Deriv = double (a distance, its rate, its force).

#include "penalty/core/types.hpp"

#include <string>
#include <vector>

namespace penalty {

struct Vec3Types {
    using Coord = Vec3;
    using Deriv = Vec3;
    static constexpr int kDerivSize = 3;  ///< scalar DOFs per Deriv
    static constexpr const char* kName = "Vec3d";
};

/// A scalar per DOF (SOFA's Vec1d): the output of distance mappings.
struct Vec1Types {
    using Coord = double;
    using Deriv = double;
    static constexpr int kDerivSize = 1;
    static constexpr const char* kName = "Vec1d";
};

struct Rigid3Types {
    using Coord = RigidFrame;
    using Deriv = RigidDeriv;
    static constexpr int kDerivSize = 6;
    static constexpr const char* kName = "Rigid3d";
};

/// Per-DOF vectors of one object. Plain data: solvers and force fields read and write the
/// vectors directly; `resize` keeps every vector the same length.
template <class DataTypes>
struct MechanicalState {
    using Coord = typename DataTypes::Coord;
    using Deriv = typename DataTypes::Deriv;

    std::string name;
    std::vector<Coord> position;       ///< x
    std::vector<Deriv> velocity;       ///< v
    std::vector<Coord> rest_position;  ///< x0 (springs, FEM)
    std::vector<Deriv> force;          ///< f, accumulated by force fields
    /// Explicit forces applied for one step, cleared after it (Simulation::step) in the states a
    /// step applies them to: in a solver's subtree, mapped, or read by an explicit force field.
    /// A static state's (none of these) are never applied, and are left as they are.
    std::vector<Deriv> external_force;

    [[nodiscard]] std::size_t size() const { return position.size(); }

    void resize(std::size_t n) {
        position.resize(n);
        velocity.resize(n);
        rest_position.resize(n);
        force.resize(n);
        external_force.resize(n);
    }
};

using Vec3State = MechanicalState<Vec3Types>;
using Rigid3State = MechanicalState<Rigid3Types>;
using Vec1State = MechanicalState<Vec1Types>;

}  // namespace penalty
