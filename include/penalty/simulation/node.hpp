#pragma once
/// @file
/// Scene graph (SOFA's Node): a tree of nodes, each holding at most one mechanical state, one
/// mass, one mapping (whose output is the node's state), force fields (on one state or between
/// two), projective constraints and at most one ODE solver. Context (gravity, dt) is inherited
/// from the parent unless set on the node.
///
/// Solver subtrees (spec §2.1): the first node on a path from the root that owns an ODE solver
/// integrates its whole subtree implicitly (every force field stored in the subtree, including
/// interaction force fields, enters the linear system). An interaction force field stored in a node
/// above any solver (typically the root) is evaluated explicitly once per step, with the
/// start-of-step positions, and its forces are added to its states' external_force. A state
/// outside every solver subtree (a static object) never moves; in a solve it has dx = 0.

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/mapping.hpp"
#include "penalty/mechanics/mechanical_object.hpp"

#include <cstdint>
#include <initializer_list>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace penalty {

class OdeSolver;

class Node {
public:
    explicit Node(std::string name, Node* parent = nullptr);
    Node(const Node&) = delete;
    Node& operator=(const Node&) = delete;

    [[nodiscard]] const std::string& name() const { return name_; }
    [[nodiscard]] Node* parent() const { return parent_; }
    /// Identity of the node in its graph: 0 for a root, then 1, 2, … in creation order; unique
    /// among the nodes ever created under the same root, never reused (ContactPipeline's
    /// same-node rule).
    [[nodiscard]] int id() const { return id_; }
    /// Adds a child node and returns it (owned by this node).
    Node& add_child(std::string name);
    [[nodiscard]] const std::vector<std::unique_ptr<Node>>& children() const { return children_; }
    /// Removes (and destroys, with its whole subtree) a direct child; returns false if `child`
    /// is not a child of this node. Pointers into the removed subtree dangle afterwards.
    bool remove_child(const Node* child);
    /// Removes (and destroys) the listed direct children in one pass (a pile of bodies loses
    /// hundreds of contact-point nodes a step: one remove_child each was quadratic); the others
    /// keep their order. Returns how many were children of this node; a pointer listed twice
    /// counts once.
    std::size_t remove_children(std::span<const Node* const> removed);

    /// Context: gravity (m/s², default (0, −9.81, 0)) and time step (s, default 0.01), inherited.
    void set_gravity(const Vec3& g);
    void set_dt(double dt);
    [[nodiscard]] Vec3 gravity() const;
    [[nodiscard]] double dt() const;

    /// Creates the node's mechanical state (one per node).
    template <class DataTypes>
    MechanicalObject<DataTypes>& add_state(std::string state_name = "dofs") {
        if (state_) throw_invalid_argument("Node '", name_, "': already has a mechanical state");
        auto s = std::make_unique<MechanicalObject<DataTypes>>(std::move(state_name));
        auto& ref = *s;
        state_ = std::move(s);
        structure_changed();
        return ref;
    }
    [[nodiscard]] BaseState* state() const { return state_.get(); }

    /// Adds a component of type C constructed from args (returns it; owned by the node).
    template <class C, class... Args>
    C& add_force_field(Args&&... args) {
        auto c = std::make_unique<C>(std::forward<Args>(args)...);
        auto& ref = *c;
        force_fields_.push_back(std::move(c));
        structure_changed();
        return ref;
    }
    template <class C, class... Args>
    C& set_mass(Args&&... args) {
        // One per node, as in SOFA: replacing would leave dangling pointers to the old one.
        if (mass_) throw_invalid_argument("Node '", name_, "': already has a mass");
        auto c = std::make_unique<C>(std::forward<Args>(args)...);
        auto& ref = *c;
        mass_ = std::move(c);
        mass_place_ = force_fields_.size();
        structure_changed();
        return ref;
    }
    template <class C, class... Args>
    C& set_mapping(Args&&... args) {
        if (mapping_) throw_invalid_argument("Node '", name_, "': already has a mapping");
        auto c = std::make_unique<C>(std::forward<Args>(args)...);
        auto& ref = *c;
        mapping_ = std::move(c);
        structure_changed();
        return ref;
    }
    template <class C, class... Args>
    C& add_constraint(Args&&... args) {
        auto c = std::make_unique<C>(std::forward<Args>(args)...);
        auto& ref = *c;
        constraints_.push_back(std::move(c));
        structure_changed();
        return ref;
    }
    template <class C, class... Args>
    C& set_ode_solver(Args&&... args) {
        if (solver_) throw_invalid_argument("Node '", name_, "': already has an ODE solver");
        auto c = std::make_unique<C>(std::forward<Args>(args)...);
        auto& ref = *c;
        solver_ = std::move(c);
        structure_changed();
        return ref;
    }
    /// Takes ownership of an already-built force field (e.g. a contact adapter).
    BaseForceField& add_force_field_ptr(std::unique_ptr<BaseForceField> ff);
    /// Removes (and destroys) a force field of this node; returns false if not found.
    bool remove_force_field(const BaseForceField* ff);
    /// Removes (and destroys) the listed force fields of this node in one pass; the others keep
    /// their order. Returns how many were force fields of this node.
    std::size_t remove_force_fields(std::span<const BaseForceField* const> removed);
    /// Moves the listed force fields of this node (each once) to the end of its list, in the
    /// given order; the others keep their order. Nothing changes (and nothing is allocated) when
    /// the list already ends with them in that order. Throws std::invalid_argument if one is not
    /// a force field of this node. (SOFA re-adds every contact force field to its node at each
    /// collision step, SubCollisionPipeline::computeCollisionResponse: the node's addForce then
    /// visits them in the contact manager's order.)
    void move_force_fields_to_end(std::span<BaseForceField* const> moved);

    [[nodiscard]] const std::vector<std::unique_ptr<BaseForceField>>& force_fields() const { return force_fields_; }
    /// Calls fn(BaseForceField&) for each force field in SOFA's visiting order: the fields that
    /// are not SOFA interaction force fields first, then those that are
    /// (BaseForceField::sofa_interaction; BaseMechanicalVisitor::processNodeTopDown visits a
    /// node's forceField list before its interactionForceField list), each group in list order.
    template <class Fn>
    void for_each_force_field(Fn&& fn) const {
        for (const bool interaction : {false, true})
            for (const auto& ff : force_fields_)
                if (ff->sofa_interaction() == interaction) fn(*ff);
    }
    /// Calls mass_fn(BaseMass&) and field_fn(BaseForceField&) for the node's mass and force
    /// fields in SOFA's order. SOFA's mass is also in its node's forceField list, at its place of
    /// declaration (Mass::insertInNode adds it to both lists). With `interaction_last`, SOFA's
    /// visitors' order: the non-interaction fields with the mass among them where it was set,
    /// then the interaction fields (for_each_force_field). Without, the order in which SOFA HEAD's
    /// MappingGraph lists them (Node::getObjects, the node's objects as written): every field in
    /// list order with the mass at its place.
    template <class MassFn, class FieldFn>
    void for_each_mass_and_force_field(bool interaction_last, MassFn&& mass_fn, FieldFn&& field_fn) const {
        for (std::size_t i = 0; i < force_fields_.size(); ++i) {
            if (i == mass_place_ && mass_) mass_fn(*mass_);
            if (!interaction_last || !force_fields_[i]->sofa_interaction()) field_fn(*force_fields_[i]);
        }
        if (mass_place_ >= force_fields_.size() && mass_) mass_fn(*mass_);
        if (!interaction_last) return;
        for (const auto& ff : force_fields_)
            if (ff->sofa_interaction()) field_fn(*ff);
    }
    [[nodiscard]] BaseMass* mass() const { return mass_.get(); }
    [[nodiscard]] BaseMapping* mapping() const { return mapping_.get(); }
    [[nodiscard]] const std::vector<std::unique_ptr<BaseProjectiveConstraint>>& constraints() const {
        return constraints_;
    }
    [[nodiscard]] OdeSolver* ode_solver() const { return solver_.get(); }

    /// Version of the structure of the whole graph (kept by the root): changes whenever a node,
    /// state, mass, mapping, force field, constraint or solver is added or removed anywhere, or
    /// a gravity is set. Solvers cache what they build from the graph (SubtreeSystem) and build
    /// it again when this changes; contact pipelines change the graph only through these calls.
    [[nodiscard]] std::uint64_t structure_version() const;
    /// Bumps structure_version() without adding or removing anything: a topological change
    /// resized some components' data (docs/topological-changes.md), so what the solvers built
    /// from the graph must be built again.
    void mark_structure_changed() { structure_changed(); }

    ~Node();

private:
    /// Bumps the root's structure version (see structure_version()).
    void structure_changed();
    /// How many of `listed` are among the force fields before the mass (mass_place_).
    [[nodiscard]] std::size_t listed_before_mass(std::span<const BaseForceField* const> listed) const;
    std::string name_;
    Node* parent_;
    int id_ = 0;
    int ids_issued_ = 0;  ///< on a root: ids given to the nodes created under it
    std::optional<Vec3> gravity_;
    std::optional<double> dt_;
    std::unique_ptr<BaseState> state_;
    std::unique_ptr<BaseMass> mass_;
    /// The mass's place in SOFA's forceField list: how many of force_fields_ come before it (set
    /// by set_mass; a force field removed or moved to the end from before it lowers it).
    std::size_t mass_place_ = 0;
    std::unique_ptr<BaseMapping> mapping_;
    std::vector<std::unique_ptr<BaseForceField>> force_fields_;
    std::vector<std::unique_ptr<BaseProjectiveConstraint>> constraints_;
    std::unique_ptr<OdeSolver> solver_;
    std::vector<std::unique_ptr<Node>> children_;
    std::uint64_t structure_version_ = 0;  ///< used on the root only
};

}  // namespace penalty
