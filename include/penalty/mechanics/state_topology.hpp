#pragma once
/// @file
/// A MechanicalObject following the points of its topology (SOFA's
/// MechanicalObject::handleStateChange): on removal, each removed point takes the values of the
/// last one (replaceValue, indices in decreasing order) and every vector shrinks; on addition,
/// every vector grows and a new point with ancestors takes Σ c_k·value(ancestor_k) (c_k = 1/n when
/// no coefficients are given; computeWeightedValue); on renumbering, new i takes old index[i].
/// Every vector of the state follows: position, velocity, rest position, force, external force,
/// dx, df. Memory a view of a vector may hold stays valid: a removal shrinks in place (the rows past
/// the new size stay allocated), and an addition that needs more room keeps the old buffer (with
/// the values before the addition) for the follower's lifetime instead of freeing it.

#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/mechanics/topology_change.hpp"

namespace penalty {

template <class DataTypes>
class StateTopologyFollower final : public StateFollower {
public:
    explicit StateTopologyFollower(MechanicalObject<DataTypes>& state) : state_(&state) {}
    void handle_state_change(const TopologyChange& change) override;
    [[nodiscard]] MechanicalObject<DataTypes>& state() const { return *state_; }

private:
    MechanicalObject<DataTypes>* state_;
    std::vector<std::vector<typename DataTypes::Coord>> retired_coords_;  ///< buffers views may still see
    std::vector<std::vector<typename DataTypes::Deriv>> retired_derivs_;
};

extern template class StateTopologyFollower<Vec3Types>;
extern template class StateTopologyFollower<Rigid3Types>;

}  // namespace penalty
