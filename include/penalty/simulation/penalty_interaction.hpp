#pragma once
/// @file
/// The one adapter that puts a penalty::PenaltyForceField (response layer) into the scene graph:
/// an interaction force field between two Vec3 states (or inside one state: pass it twice) over
/// a field it does not own (e.g. the one of a BarycentricPenaltyContact, rebuilt by
/// set_detection_outputs each step, or one the caller keeps). Where it is stored decides
/// implicit vs explicit treatment (spec §2.1, see node.hpp).

#include "penalty/mechanics/force_field.hpp"
#include "penalty/response/penalty_force_field.hpp"

namespace penalty {

class PenaltyInteraction final : public Vec3InteractionForceField {
public:
    /// `field` must outlive the adapter.
    PenaltyInteraction(Vec3Object& state1, Vec3Object& state2, PenaltyForceField& field)
        : Vec3InteractionForceField(state1, state2), field_(&field) {}

    /// The wrapped contact list (clear / add_contact between steps, from the collision hook).
    [[nodiscard]] PenaltyForceField& field() const { return *field_; }

    void add_force(Vec3Span f1, Vec3Span f2, ConstVec3Span x1, ConstVec3Span x2, ConstVec3Span v1,
                   ConstVec3Span v2) override {
        field_->add_force(f1, f2, x1, x2, v1, v2);
    }
    void add_dforce(Vec3Span df1, Vec3Span df2, ConstVec3Span dx1, ConstVec3Span dx2, double k_factor,
                    double b_factor) const override {
        field_->add_dforce(df1, df2, dx1, dx2, k_factor, b_factor);
    }
    void add_stiffness_triplets(TripletList& triplets, Index offset1, Index offset2, double factor) const override {
        field_->add_stiffness_triplets(triplets, offset1, offset2, factor);
    }
    void add_damping(TripletList& triplets, const StateOffsets& offsets, double factor) const override {
        field_->add_damping_triplets(triplets, offsets(s1_), offsets(s2_), factor);
    }
    [[nodiscard]] double potential_energy() const override { return field_->potential_energy(); }
    [[nodiscard]] ForceFieldStates states() const override {
        if (s1_ == s2_) return ForceFieldStates(s1_);
        return {s1_, s2_};
    }
    /// The contacts' DOFs on `state` (m1 on state 1, m2 on state 2; add_force and add_dforce
    /// touch no other).
    [[nodiscard]] bool list_dx_read(const BaseState& state, std::vector<std::uint32_t>& rows) const override {
        for (const PenaltyContact& c : field_->contacts()) {
            if (&state == s1_) list(rows, c.m1);
            if (&state == s2_) list(rows, c.m2);
        }
        return true;
    }

private:
    static void list(std::vector<std::uint32_t>& rows, Index dof) {
        PENALTY_DEMAND(dof >= 0);
        rows.push_back(static_cast<std::uint32_t>(dof));
    }
    PenaltyForceField* field_;
};

}  // namespace penalty
