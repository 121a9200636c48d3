#pragma once
/// @file
/// Component interfaces seen by the solvers: force fields (on one state or between two states),
/// masses and projective constraints. SOFA's conventions:
///   - f(x, v) is the force (N); K = ∂f/∂x (N/m), B = ∂f/∂v, so K is negative semi-definite for
///     springs; potential energy E with f = −∂E/∂x;
///   - add_dforce(k, b): df += k·K·dx + b·B·dx, with K (and B) linearised at the last add_force;
///   - stiffness triplets: factor·K at scalar indices offset + deriv_size·dof + component; a
///     triplet whose row or column falls outside the system is dropped by the assembler (this is
///     how a static state, given an offset at or past the end of the system, is excluded).

#include "penalty/core/types.hpp"
#include "penalty/mechanics/mechanical_object.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace penalty {

/// Scalar offset of a state in the assembled system; a value >= system size means "not in it".
using StateOffsets = std::function<Index(const BaseState*)>;

/// The states a force field acts on: one, or two for an interaction (none when
/// default-constructed). A value, without allocation: the solvers list them each time a system
/// is built.
class ForceFieldStates {
public:
    ForceFieldStates() = default;  ///< none
    explicit ForceFieldStates(BaseState* only) : states_{only, nullptr}, count_(1) {}
    ForceFieldStates(BaseState* first, BaseState* second) : states_{first, second}, count_(2) {}
    [[nodiscard]] std::size_t size() const { return count_; }
    [[nodiscard]] BaseState* operator[](std::size_t i) const { return states_[i]; }
    [[nodiscard]] BaseState* const* begin() const { return states_.data(); }
    [[nodiscard]] BaseState* const* end() const { return states_.data() + count_; }

private:
    std::array<BaseState*, 2> states_{};
    std::size_t count_ = 0;
};

class BaseForceField {
public:
    virtual ~BaseForceField() = default;
    /// Precompute rest quantities; called after the states are initialised.
    virtual void init() {}
    /// f += F(x, v) into the `force` vector of its state(s).
    virtual void accumulate_force() = 0;
    /// df += k_factor·K·dx + b_factor·B·dx, reading dx and writing df of its state(s).
    virtual void accumulate_dforce(double k_factor, double b_factor) = 0;
    /// Appends factor·K as triplets (see file comment).
    virtual void add_stiffness(TripletList& triplets, const StateOffsets& offsets, double factor) const = 0;
    /// Appends factor·B (B = ∂f/∂v) as triplets, the layout of add_stiffness. Default: nothing,
    /// for the fields whose accumulate_dforce ignores b_factor (a field that reads it overrides
    /// this, so that an assembled m·M + b·B + k·K equals the matrix-free product).
    virtual void add_damping(TripletList& /*triplets*/, const StateOffsets& /*offsets*/, double /*factor*/) const {}
    /// Potential energy (J) at the positions of the last add_force (0 when not defined).
    [[nodiscard]] virtual double potential_energy() const { return 0.0; }
    /// Appends the states whose positions the field reads besides states(), never writing them
    /// (RestShapeSpringsForceField's external rest shape): a solver reading them touches them
    /// (OdeSolver::list_touched_states), so it never runs beside their solver.
    virtual void list_read_states(std::vector<const BaseState*>& /*out*/) const {}
    /// States this force field reads and writes (one, or two for an interaction).
    [[nodiscard]] virtual ForceFieldStates states() const = 0;
    /// True when the field acts between two distinct states.
    [[nodiscard]] bool is_interaction() const { return states().size() > 1; }
    /// True for SOFA's interaction force fields (BaseInteractionForceField: SpringForceField and
    /// the fields made of it, PairInteractionForceField, MixedInteractionForceField), on one state
    /// or two: SOFA's node keeps them in its interactionForceField list, which the mechanical
    /// visitors visit after its forceField list (BaseMechanicalVisitor::processNodeTopDown), so a
    /// node sums its other force fields first (Node::for_each_force_field).
    [[nodiscard]] virtual bool sofa_interaction() const { return false; }
    /// Appends to `rows` every DOF of `state` (one of states()) whose dx accumulate_dforce may
    /// read, in any order and possibly repeated, and returns true; false (the default): the field
    /// cannot tell, it may read any. The field writes force (accumulate_force) and df
    /// (accumulate_dforce) of `state` in those DOFs only. Lets a solver map dx only where it is
    /// read, and clear an outside state's scratch only where it is written.
    [[nodiscard]] virtual bool list_dx_read(const BaseState& /*state*/, std::vector<std::uint32_t>& /*rows*/) const {
        return false;
    }
};

/// A force field acting on one state of type DataTypes.
template <class DataTypes>
class ForceField : public BaseForceField {
public:
    using Coord = typename DataTypes::Coord;
    using Deriv = typename DataTypes::Deriv;

    explicit ForceField(MechanicalObject<DataTypes>& state) : state_(&state) {}

    /// f += F(x, v).
    virtual void add_force(std::span<Deriv> f, std::span<const Coord> x, std::span<const Deriv> v) = 0;
    /// df += k·K·dx + b·B·dx.
    virtual void add_dforce(std::span<Deriv> df, std::span<const Deriv> dx, double k_factor, double b_factor) const = 0;
    /// factor·K triplets at scalar offset `offset`.
    virtual void add_stiffness_triplets(TripletList& triplets, Index offset, double factor) const = 0;

    void accumulate_force() override { add_force(state_->force, state_->position, state_->velocity); }
    void accumulate_dforce(double k_factor, double b_factor) override {
        add_dforce(state_->df, state_->dx, k_factor, b_factor);
    }
    void add_stiffness(TripletList& triplets, const StateOffsets& offsets, double factor) const override {
        add_stiffness_triplets(triplets, offsets(state_), factor);
    }
    [[nodiscard]] ForceFieldStates states() const override { return ForceFieldStates(state_); }
    [[nodiscard]] MechanicalObject<DataTypes>& state() const { return *state_; }

protected:
    MechanicalObject<DataTypes>* state_;
};

/// A force field between two Vec3 states (SOFA's PairInteractionForceField); the span-based
/// virtuals have the signatures of penalty::PenaltyForceField so it can be adapted directly.
class Vec3InteractionForceField : public BaseForceField {
public:
    Vec3InteractionForceField(Vec3Object& state1, Vec3Object& state2) : s1_(&state1), s2_(&state2) {}
    /// True (SOFA's PairInteractionForceField, SpringForceField) unless set false for a field SOFA
    /// derives from ForceField that penalty builds as springs (TriangularBendingSprings,
    /// QuadularBendingSprings).
    [[nodiscard]] bool sofa_interaction() const final { return sofa_interaction_; }
    void set_sofa_interaction(bool interaction) { sofa_interaction_ = interaction; }

    virtual void add_force(Vec3Span f1, Vec3Span f2, ConstVec3Span x1, ConstVec3Span x2, ConstVec3Span v1,
                           ConstVec3Span v2) = 0;
    virtual void add_dforce(Vec3Span df1, Vec3Span df2, ConstVec3Span dx1, ConstVec3Span dx2, double k_factor,
                            double b_factor) const = 0;
    virtual void add_stiffness_triplets(TripletList& triplets, Index offset1, Index offset2, double factor) const = 0;

    void accumulate_force() override {
        add_force(s1_->force, s2_->force, s1_->position, s2_->position, s1_->velocity, s2_->velocity);
    }
    void accumulate_dforce(double k_factor, double b_factor) override {
        add_dforce(s1_->df, s2_->df, s1_->dx, s2_->dx, k_factor, b_factor);
    }
    void add_stiffness(TripletList& triplets, const StateOffsets& offsets, double factor) const override {
        add_stiffness_triplets(triplets, offsets(s1_), offsets(s2_), factor);
    }
    [[nodiscard]] ForceFieldStates states() const override { return {s1_, s2_}; }
    [[nodiscard]] Vec3Object& state1() const { return *s1_; }
    [[nodiscard]] Vec3Object& state2() const { return *s2_; }

protected:
    Vec3Object* s1_;
    Vec3Object* s2_;
    bool sofa_interaction_ = true;
};

/// Mass of one state: M (and gravity force M·g).
class BaseMass {
public:
    virtual ~BaseMass() = default;
    virtual void init() {}
    /// f += M·g (N) into the state's force.
    virtual void add_gravity_force(const Vec3& gravity) = 0;
    /// df += factor·M·dx (work vectors of the state).
    virtual void add_mdx(double factor) = 0;
    /// out = M⁻¹·in on flat vectors of the state's layout.
    virtual void apply_inverse(const Eigen::Ref<const Eigen::VectorXd>& in, Eigen::Ref<Eigen::VectorXd> out) const = 0;
    /// Appends factor·M as triplets at scalar offset `offset`.
    virtual void add_mass_triplets(TripletList& triplets, Index offset, double factor) const = 0;
    /// ½ vᵀ M v (J).
    [[nodiscard]] virtual double kinetic_energy() const = 0;
    /// −Σ m g·x (J), gravity's potential.
    [[nodiscard]] virtual double gravity_potential_energy(const Vec3& gravity) const = 0;
    /// Σ m over the DOFs (kg).
    [[nodiscard]] virtual double total_mass() const = 0;
    [[nodiscard]] virtual BaseState* state() const = 0;
};

/// The simulation time a component reads (s): SOFA's getContext()->getTime(), the time at the
/// start of the step during the whole step (the projections after the solve included), 0 at init.
using ContextClock = std::function<double()>;

/// Projective constraint on one state (SOFA's ProjectiveConstraintSet). Simulation::init and the
/// end of each step call, per constraint, project_position() then project_velocity() (SOFA's
/// MechanicalProjectPositionAndVelocityVisitor); the solvers project their vectors with
/// project_response.
class BaseProjectiveConstraint {
public:
    virtual ~BaseProjectiveConstraint() = default;
    virtual void init() {}
    /// Projects a flat derivative vector of the state's layout (b, q = A p, Δv, a).
    virtual void project_response(Eigen::Ref<Eigen::VectorXd> v) const = 0;
    /// Projects the state's velocity (SOFA: fixed DOFs get v = 0).
    virtual void project_velocity() = 0;
    /// Projects the state's positions (SOFA's projectPosition: a point put back on its line, a
    /// prescribed motion); the default leaves them.
    virtual void project_position() {}
    /// True when project_position may move positions.
    [[nodiscard]] virtual bool projects_positions() const { return false; }
    /// The rows (of the state's flat layout, any order) whose row and column an assembled matrix
    /// clears with 1 on the diagonal (SOFA's applyConstraint(ZeroDirichletCondition*),
    /// MatrixLinearSystem::applyProjectiveConstraints): appends them and returns true. false (the
    /// default): SOFA gives no such rows; an assembly then applies the constraint as the
    /// projector P it is, A ← P·A·P + (I − P) (global_matrix_assembly.hpp).
    [[nodiscard]] virtual bool list_discarded_rows(std::vector<Index>& /*rows*/) const { return false; }
    [[nodiscard]] virtual BaseState* state() const = 0;
};

}  // namespace penalty
