// The components that follow a dynamic topology, each with SOFA's rule for its class
// (docs/topological-changes.md, "What follows"), registered in SOFA's init order: depth first,
// file order. Anything else that uses a dynamic topology, or a state whose points it changes,
// blocks it (TopologyRuntime::check_can_change names it).
#include "penalty/collision/models.hpp"
#include "penalty/mechanics/attach_constraint.hpp"
#include "penalty/mechanics/corotational_fem.hpp"
#include "penalty/mechanics/diagonal_mass.hpp"
#include "penalty/mechanics/fast_tetrahedral_corotational.hpp"
#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/fixed_plane_constraint.hpp"
#include "penalty/mechanics/hexahedral_fem.hpp"
#include "penalty/mechanics/hyperelastic_fem.hpp"
#include "penalty/mechanics/mapping.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/mesh_matrix_mass.hpp"
#include "penalty/mechanics/prescribed_motion_constraints.hpp"
#include "penalty/mechanics/pressure_loads.hpp"
#include "penalty/mechanics/projective_constraints.hpp"
#include "penalty/mechanics/topology_followers.hpp"
#include "penalty/mechanics/triangular_biquadratic_springs.hpp"
#include "penalty/mechanics/triangular_fem.hpp"
#include "penalty/mechanics/triangular_quadratic_springs.hpp"
#include "scene/topology/topology_changes.hpp"

#include <array>
#include <functional>
#include <iostream>
#include <memory>
#include <set>
#include <utility>

namespace penalty::scene {

using io::SceneComponent;
using io::SceneNode;

namespace {

/// What the builder made of a component: its objects in the graph.
struct Built {
    std::vector<BaseMass*> masses;
    std::vector<BaseForceField*> force_fields;
    std::vector<BaseProjectiveConstraint*> constraints;
    std::vector<BaseMapping*> mappings;
    [[nodiscard]] std::vector<BaseState*> states() const {
        std::vector<BaseState*> out;
        for (const auto* m : masses) out.push_back(m->state());
        for (const auto* f : force_fields)
            for (BaseState* s : f->states()) out.push_back(s);
        for (const auto* c : constraints) out.push_back(c->state());
        for (const auto* m : mappings) out.push_back(m->from());
        return out;
    }
};

std::unordered_map<const SceneComponent*, Built> built_objects(const Scene& scene, Node& root) {
    std::unordered_map<const SceneComponent*, Built> out;
    const auto visit = [&](const auto& self, Node& n) -> void {
        if (n.mass() != nullptr)
            if (const auto* c = scene.component_of(n.mass())) out[c].masses.push_back(n.mass());
        for (const auto& f : n.force_fields())
            if (const auto* c = scene.component_of(f.get())) out[c].force_fields.push_back(f.get());
        for (const auto& k : n.constraints())
            if (const auto* c = scene.component_of(k.get())) out[c].constraints.push_back(k.get());
        if (n.mapping() != nullptr)
            if (const auto* c = scene.component_of(n.mapping())) out[c].mappings.push_back(n.mapping());
        for (const auto& child : n.children()) self(self, *child);
    };
    visit(visit, root);
    return out;
}

/// A pressure load's subset data (TrianglePressureForceField's trianglePressureMap, ...): the
/// events forwarded to its handle_topology_changes; once the operation is done, the entries that
/// SOFA's stale last index left past the topology's end (SOFA HEAD reads past it and crashes)
/// are dropped with a warning naming the component and the quirk switch that gives the rule of
/// TopologySubsetIndices.
template <class T>
class PressureLoadFollower final : public TopologyHandler {
public:
    PressureLoadFollower(T& load, const TopologyContainer& container, std::string name)
        : load_(&load), container_(&container), name_(std::move(name)) {}
    void handle_topology_changes(std::span<const TopologyChange> changes) override {
        load_->handle_topology_changes(*container_, changes);
        dirty_ = true;
    }
    void topology_change_done() override {
        if (!dirty_) return;
        dirty_ = false;
        if (const std::size_t dropped = load_->drop_entries_past_end(); dropped > 0)
            std::cerr << "warning: " << name_ << ": " << dropped
                      << " pressure entries name elements past the topology's end after the change (SOFA's "
                         "TopologySubsetData::remove renames the entries of the last element at init, not the current "
                         "one; SOFA HEAD then reads past the topology): dropped (--fix-sofa-quirk "
                         "subset_data_last_index gives the current last element's rule)\n";
        if constexpr (requires(T & t) { t.topology_change_done(); }) load_->topology_change_done();
    }

private:
    T* load_;
    const TopologyContainer* container_;
    std::string name_;
    bool dirty_ = false;
};

/// The FEM force fields' followers (follow_force_field), or false.
bool follow_fem(TopologyWiring& w, const SceneComponent& c, BaseForceField* f, TopologyContainer& container) {
    const std::string& type = c.type;
    const MeshTopology& mesh = container.mesh();
    const auto rebuild = [&](std::function<void()> fn, std::initializer_list<ElementType> types) {
        container.add_handler(w.keep(std::make_unique<RebuildFollower>(std::move(fn), types)), types);
    };
    if (type == "TetrahedralCorotationalFEMForceField") {
        auto* ff = dynamic_cast<TetrahedralCorotationalFEMForceField*>(f);
        if (ff == nullptr || !ff->options().local_stiffness_factors.empty()) return false;
        rebuild([ff, &mesh] { ff->set_elements(mesh.tetrahedra()), ff->init(); },
                {ElementType::tetrahedron, ElementType::point});
        return true;
    }
    // FastTetrahedralCorotationalForceField: tetrahedronInfo's creation callback (rest information
    // from the rest positions), edgeInfo and pointInfo resized with the topology: rebuilt
    // TetrahedronHyperelasticityFEMForceField: tetrahedronInfo's creation callback
    // (createTetrahedronRestInformation: shape vectors and rest volume from the rest positions),
    // edgeInfo resized with the topology and refilled at each addForce: rebuilt
    if (type == "TetrahedronHyperelasticityFEMForceField") {
        auto* ff = dynamic_cast<TetrahedronHyperelasticityFEMForceField*>(f);
        if (ff == nullptr) return false;
        rebuild([ff, &mesh] { ff->set_tetrahedra(mesh.tetrahedra()), ff->init(); },
                {ElementType::tetrahedron, ElementType::point});
        return true;
    }
    if (type == "FastTetrahedralCorotationalForceField") {
        auto* ff = dynamic_cast<FastTetrahedralCorotationalForceField*>(f);
        if (ff == nullptr) return false;
        rebuild([ff] { ff->init(); }, {ElementType::tetrahedron, ElementType::edge, ElementType::point});
        return true;
    }
    if (type == "TetrahedronFEMForceField") {
        auto* ff = dynamic_cast<TetrahedronFEMForceField*>(f);
        if (ff == nullptr || (mesh.tetrahedra().empty() && !mesh.hexahedra().empty())) return false;
        // incremental (fem_changes.cpp): the data of the elements a change touches
        container.add_handler(w.keep(std::make_unique<MemberTopologyHandler<TetrahedronFEMForceField>>(*ff, container)),
                              {ElementType::tetrahedron, ElementType::point});
        return true;
    }
    if (type == "HexahedralFEMForceField" || type == "HexahedronFEMForceField") {
        if (auto* ff = dynamic_cast<HexahedralFEMForceField*>(f)) {
            rebuild([ff, &mesh] { ff->set_elements(mesh.hexahedra()), ff->init(); },
                    {ElementType::hexahedron, ElementType::point});
            return true;
        }
        auto* ff = dynamic_cast<HexahedronFEMForceField*>(f);
        if (ff == nullptr || !ff->stiffness_factors().empty()) return false;
        rebuild([ff, &mesh] { ff->set_elements(mesh.hexahedra()), ff->init(); },
                {ElementType::hexahedron, ElementType::point});
        return true;
    }
    if (type == "TriangularFEMForceField" || type == "TriangleFEMForceField") {
        auto* ff = dynamic_cast<TriangularFEMForceField*>(f);
        if (ff == nullptr || !mesh.quads().empty()) return false;
        if (type == "TriangularFEMForceField") {
            // triangleInfo, a TopologyData: event by event (triangular_fem_changes.cpp)
            container.add_handler(
                w.keep(std::make_unique<MemberTopologyHandler<TriangularFEMForceField>>(*ff, container)),
                {ElementType::triangle, ElementType::point});
            return true;
        }
        if (w.builder.options().sofa_quirk_fixes.fix_triangle_fem_slot_data) {
            rebuild([ff, &mesh] { ff->set_triangles(mesh.triangles()), ff->init(); },
                    {ElementType::triangle, ElementType::point});
            return true;
        }
        // SOFA's TriangleFEMForceField keeps no topology data: each slot keeps its data
        rebuild(
            [ff, &mesh, name = where(c)] {
                if (const std::size_t n = ff->take_triangles_keeping_slot_data(mesh.triangles()); n > 0)
                    std::cerr << "warning: " << name << ": " << n
                              << " triangles past the count at init (SOFA's TriangleFEMForceField reads past its "
                                 "vectors there): their data made from the rest positions (--fix-sofa-quirk "
                                 "triangle_fem_slot_data makes every triangle's data again)\n";
            },
            {ElementType::triangle, ElementType::point});
        return true;
    }
    return false;
}

/// Triangular/QuadularBendingSprings: their springs follow the edges and `faces`.
template <class Follower>
bool follow_bending_springs(TopologyWiring& w, const SceneComponent& c, BaseForceField* f, TopologyContainer& container,
                            ElementType faces) {
    auto* ff = dynamic_cast<SpringForceField*>(f);
    auto* state = ff != nullptr ? dynamic_cast<Vec3Object*>(ff->states()[0]) : nullptr;
    if (ff == nullptr || state == nullptr || ff->states().size() != 1) return false;
    const Attributes a(c);
    container.add_handler(
        w.keep(std::make_unique<Follower>(*ff, container, *state, a.real("stiffness"), a.real("damping"))),
        {ElementType::edge, ElementType::point, faces});
    return true;
}

/// A field whose edgeInfo and triangleInfo are TopologyData with creation and destruction
/// callbacks, followed event by event.
template <class Field>
bool follow_edge_and_triangle_data(TopologyWiring& w, BaseForceField* f, TopologyContainer& container) {
    auto* ff = dynamic_cast<Field*>(f);
    if (ff == nullptr) return false;
    container.add_handler(w.keep(std::make_unique<MemberTopologyHandler<Field>>(*ff, container)),
                          {ElementType::edge, ElementType::triangle});
    return true;
}

/// A pressure load on the elements of `type` (a TopologySubsetIndices).
template <class Load>
bool follow_pressure_load(TopologyWiring& w, const SceneComponent& c, BaseForceField* f, TopologyContainer& container,
                          ElementType type) {
    auto* ff = dynamic_cast<Load*>(f);
    if (ff == nullptr) return false;
    ff->set_current_last_index(w.builder.options().sofa_quirk_fixes.fix_subset_data_last_index);
    container.add_handler(w.keep(std::make_unique<PressureLoadFollower<Load>>(*ff, container, where(c))), {type});
    return true;
}

/// follow for a force field (its one force field), or false when its class has no rule here.
bool follow_force_field(TopologyWiring& w, const SceneComponent& c, const Built& b, DynamicTopology& t) {
    TopologyContainer& container = *t.container;
    const std::string& type = c.type;
    if (b.force_fields.size() != 1) return false;
    BaseForceField* f = b.force_fields[0];
    if (type == "TriangularBendingSprings")
        return follow_bending_springs<TriangularBendingSpringsFollower>(w, c, f, container, ElementType::triangle);
    if (type == "QuadularBendingSprings")
        return follow_bending_springs<QuadularBendingSpringsFollower>(w, c, f, container, ElementType::quad);
    // SOFA HEAD's SpringForceField::initializeTopologyHandler (applyRemovedPoints, applyRemovedEdges)
    if (type == "SpringForceField" || type == "MeshSpringForceField") {
        auto* ff = dynamic_cast<SpringForceField*>(f);
        if (ff == nullptr || ff->states().size() != 1) return false;
        container.add_handler(w.keep(std::make_unique<SpringPointsFollower>(*ff, container)),
                              {ElementType::point, ElementType::edge});
        return true;
    }
    if (type == "RestShapeSpringsForceField" || type == "SurfacePressureForceField" ||
        type == "TaitSurfacePressureForceField")
        return follow_surface_load_or_rest_springs(w, c, *f, t);  // load_followers.cpp
    if (type == "TriangularBiquadraticSpringsForceField")
        return follow_edge_and_triangle_data<TriangularBiquadraticSpringsForceField>(w, f, container);
    if (type == "TriangularQuadraticSpringsForceField")
        return follow_edge_and_triangle_data<TriangularQuadraticSpringsForceField>(w, f, container);
    if (type == "TrianglePressureForceField")
        return follow_pressure_load<TrianglePressureForceField>(w, c, f, container, ElementType::triangle);
    if (type == "QuadPressureForceField")
        return follow_pressure_load<QuadPressureForceField>(w, c, f, container, ElementType::quad);
    if (type == "EdgePressureForceField")
        return follow_pressure_load<EdgePressureForceField>(w, c, f, container, ElementType::edge);
    return follow_fem(w, c, f, container);
}

/// One component's follower on `t` (its topology), or false when its class has no rule here.
bool follow(TopologyWiring& w, const SceneComponent& c, const Built& b, DynamicTopology& t) {
    TopologyContainer& container = *t.container;
    const std::string& type = c.type;
    if (type == "DiagonalMass" && b.masses.size() == 1) {
        auto* m = dynamic_cast<DiagonalMass*>(b.masses[0]);
        if (m == nullptr) return false;
        container.add_handler(w.keep(std::make_unique<MemberTopologyHandler<DiagonalMass>>(*m, container)),
                              {ElementType::point, element_type_of(m->element_kind())});
        w.runtime.internal_updates.push_back([m] { m->update_internal_data(); });
        return true;
    }
    if (type == "MeshMatrixMass" && b.masses.size() == 1) {
        auto* m = dynamic_cast<MeshMatrixMass*>(b.masses[0]);
        if (m == nullptr || m->element_kind() == LumpedElementKind::edge) return false;
        container.add_handler(w.keep(std::make_unique<MemberTopologyHandler<MeshMatrixMass>>(*m, container)),
                              {ElementType::point, ElementType::edge, element_type_of(m->element_kind())});
        return true;
    }
    if (type == "UniformMass") return !io::get_bool_or(c, "preserveTotalMass", false);
    if ((type == "FixedProjectiveConstraint" || type == "FixedConstraint") && b.constraints.size() == 1) {
        auto* k = dynamic_cast<FixedProjectiveConstraint*>(b.constraints[0]);
        if (k == nullptr) return false;
        container.add_handler(
            w.keep(std::make_unique<SubsetIndicesFollower>(
                container, [k] { return k->indices(); }, [k](std::vector<Index> i) { k->set_indices(std::move(i)); })),
            {ElementType::point});
        return true;
    }
    if ((type == "FixedPlaneProjectiveConstraint" || type == "FixedPlaneConstraint") && b.constraints.size() == 1) {
        auto* k = dynamic_cast<FixedPlaneProjectiveConstraint*>(b.constraints[0]);
        if (k == nullptr) return false;
        container.add_handler(
            w.keep(std::make_unique<SubsetIndicesFollower>(
                container, [k] { return k->indices(); }, [k](std::vector<Index> i) { k->set_indices(std::move(i)); })),
            {ElementType::point});
        return true;
    }
    // LineProjectiveConstraint, PlaneProjectiveConstraint: TopologySubsetIndices, and the jacobian
    // made again for the new indices (projectResponse's updateJacobian when the size changed).
    // DirectionProjectiveConstraint: TopologySubsetIndices (init's createTopologyHandler); SOFA
    // keeps the jacobian of the old size (undefined once the state shrank), penalty makes it again
    // as Line does; the origins stay in their slots (m_origin is no topology data).
    if ((type == "LineProjectiveConstraint" || type == "PlaneProjectiveConstraint" ||
         type == "DirectionProjectiveConstraint") &&
        b.constraints.size() == 1) {
        auto* k = dynamic_cast<BlockProjectionConstraint*>(b.constraints[0]);
        if (k == nullptr) return false;
        container.add_handler(
            w.keep(std::make_unique<SubsetIndicesFollower>(
                container, [k] { return k->indices(); }, [k](std::vector<Index> i) { k->set_indices(std::move(i)); })),
            {ElementType::point});
        return true;
    }
    // LinearMovementProjectiveConstraint: TopologySubsetIndices (init's createTopologyHandler);
    // x0, indexed by point, is left as it is
    if (type == "LinearMovementProjectiveConstraint" && b.constraints.size() == 1) {
        const auto follow_subset = [&](auto* k) {
            container.add_handler(w.keep(std::make_unique<SubsetIndicesFollower>(
                                      container, [k] { return k->indices(); },
                                      [k](std::vector<Index> i) { k->set_indices(std::move(i)); })),
                                  {ElementType::point});
            return true;
        };
        if (auto* k = dynamic_cast<LinearMovementProjectiveConstraint<Vec3Types>*>(b.constraints[0]))
            return follow_subset(k);
        if (auto* k = dynamic_cast<LinearMovementProjectiveConstraint<Rigid3Types>*>(b.constraints[0]))
            return follow_subset(k);
        return false;
    }
    // PartialFixedProjectiveConstraint: FixedProjectiveConstraint's TopologySubsetIndices (it
    // inherits init); ParabolicProjectiveConstraint: its own (init's createTopologyHandler)
    if (type == "PartialFixedProjectiveConstraint" && b.constraints.size() == 1) {
        auto* k = dynamic_cast<PartialFixedProjectiveConstraint*>(b.constraints[0]);
        if (k == nullptr) return false;
        container.add_handler(
            w.keep(std::make_unique<SubsetIndicesFollower>(
                container, [k] { return k->indices(); }, [k](std::vector<Index> i) { k->set_indices(std::move(i)); })),
            {ElementType::point});
        return true;
    }
    if (type == "ParabolicProjectiveConstraint" && b.constraints.size() == 1) {
        const auto follow_subset = [&](auto* k) {
            container.add_handler(w.keep(std::make_unique<SubsetIndicesFollower>(
                                      container, [k] { return k->indices(); },
                                      [k](std::vector<Index> i) { k->set_indices(std::move(i)); })),
                                  {ElementType::point});
            return true;
        };
        if (auto* k = dynamic_cast<ParabolicProjectiveConstraint<Vec3Types>*>(b.constraints[0]))
            return follow_subset(k);
        if (auto* k = dynamic_cast<ParabolicProjectiveConstraint<Rigid3Types>*>(b.constraints[0]))
            return follow_subset(k);
        return false;
    }
    if (type == "PointProjectiveConstraint" && b.constraints.size() == 1) {
        auto* k = dynamic_cast<PointProjectiveConstraint*>(b.constraints[0]);
        if (k == nullptr) return false;
        container.add_handler(
            w.keep(std::make_unique<SubsetIndicesFollower>(
                container, [k] { return k->indices(); }, [k](std::vector<Index> i) { k->set_indices(std::move(i)); })),
            {ElementType::point});
        return true;
    }
    return follow_force_field(w, c, b, t);
}

/// A SpringForceField between two states (SpringForceField::init: initializeTopologyHandler of
/// d_springsIndices[0] on the topology of object1's context, of [1] on object2's): each end that
/// follows a dynamic topology's points follows its removals (SpringPointsFollower), the two ends
/// editing one spring list. An end whose context topology changes but whose state does not follow
/// it (a state mapped below it) has no rule: false.
bool follow_spring_ends(TopologyWiring& w, const SceneComponent& c, const Built& b) {
    if ((c.type != "SpringForceField" && c.type != "MeshSpringForceField") || b.force_fields.size() != 1) return false;
    auto* ff = dynamic_cast<SpringForceField*>(b.force_fields[0]);
    if (ff == nullptr || ff->states().size() != 2) return false;
    std::array<DynamicTopology*, 2> ends{};
    for (std::size_t k = 0; k < 2; ++k) {
        const BaseState* state = ff->states()[k];
        const auto f = w.followed_states.find(state);
        ends[k] = f != w.followed_states.end() ? f->second : nullptr;
        // the topology SOFA's handler listens to: the state's node's or the nearest ancestor's
        for (const auto& [sn, nb] : w.builder.node_builds()) {
            if (nb.node == nullptr || nb.node->state() != state) continue;
            for (const io::SceneNode* n = sn; n != nullptr; n = n->parent) {
                const NodeBuild& up = w.builder.node_build(*n);
                if (up.topology == nullptr) continue;
                if (DynamicTopology* t = w.runtime.find(up.topology); t != nullptr && t != ends[k]) return false;
                break;
            }
        }
    }
    if (ends[0] == nullptr && ends[1] == nullptr) return false;
    using Ends = SpringPointsFollower::Ends;
    const auto edit = std::make_shared<SpringListEdit>(SpringListEdit{ff, {}, false});
    const auto add = [&](DynamicTopology& t, Ends which) {
        t.container->add_handler(w.keep(std::make_unique<SpringPointsFollower>(edit, *t.container, which)),
                                 {ElementType::point, ElementType::edge});
    };
    if (ends[0] == ends[1]) {
        add(*ends[0], Ends::both);
    } else {
        if (ends[0] != nullptr) add(*ends[0], Ends::first);
        if (ends[1] != nullptr) add(*ends[1], Ends::second);
    }
    return true;
}

/// After each change, warns when pairs of an AttachProjectiveConstraint name points past their
/// state's end (they act on nothing: AttachProjectiveConstraint::in_range).
class AttachRangeCheck final : public TopologyHandler {
public:
    AttachRangeCheck(std::function<std::size_t()> pairs_past_end, std::string name)
        : pairs_past_end_(std::move(pairs_past_end)), name_(std::move(name)) {}
    void handle_topology_changes(std::span<const TopologyChange>) override { dirty_ = true; }
    void topology_change_done() override {
        if (!std::exchange(dirty_, false)) return;
        if (const std::size_t n = pairs_past_end_(); n > 0)
            std::cerr << "warning: " << name_ << ": " << n
                      << " attached pairs name points past their state's end after the topological change (SOFA's "
                         "AttachProjectiveConstraint keeps its indices; SOFA HEAD then reads and writes past the "
                         "state): they act on nothing\n";
    }

private:
    std::function<std::size_t()> pairs_past_end_;
    std::string name_;
    bool dirty_ = false;
};

/// AttachProjectiveConstraint: SOFA's indices1 and indices2 are TopologySubsetIndices without a
/// topology handler (AttachProjectiveConstraint::init creates none): nothing follows, each index
/// names the point now at it. The topologies whose points either state follows check the pairs
/// after each change (AttachRangeCheck). False for another component.
bool follow_attach(TopologyWiring& w, const SceneComponent& c, const Built& b) {
    if ((c.type != "AttachProjectiveConstraint" && c.type != "AttachConstraint") || b.constraints.size() != 1)
        return false;
    BaseProjectiveConstraint* k = b.constraints[0];
    BaseState* object1 = nullptr;
    std::function<std::size_t()> past_end;
    if (auto* a = dynamic_cast<AttachProjectiveConstraint<Vec3Types>*>(k)) {
        object1 = a->object1();
        past_end = [a] { return a->pairs_past_end(); };
    } else if (auto* r = dynamic_cast<AttachProjectiveConstraint<Rigid3Types>*>(k)) {
        object1 = r->object1();
        past_end = [r] { return r->pairs_past_end(); };
    } else {
        return false;
    }
    std::set<DynamicTopology*> topologies;
    for (const BaseState* s : {static_cast<const BaseState*>(object1), static_cast<const BaseState*>(k->state())})
        if (const auto f = w.followed_states.find(s); f != w.followed_states.end()) topologies.insert(f->second);
    for (DynamicTopology* t : topologies)
        t->container->add_handler(w.keep(std::make_unique<AttachRangeCheck>(past_end, where(c))), {ElementType::point});
    return true;
}

/// A BarycentricMapping whose input state follows `t` (a tetrahedral or hexahedral container):
/// SOFA's BarycentricMapping::handleTopologyChange → TopologyBarycentricMapper::
/// processTopologicalChanges, clear() and init(out, in) with both states' current positions, i.e.
/// every output point mapped again onto the remaining elements (the nearest one, extrapolated
/// outside), once the operation is done and the input state has followed.
bool follow_barycentric(TopologyWiring& w, const SceneComponent& c, BaseMapping* mapping, DynamicTopology& t) {
    auto* m = dynamic_cast<BarycentricMapping*>(mapping);
    if (c.type != "BarycentricMapping" || m == nullptr) return false;
    auto* in = dynamic_cast<Vec3Object*>(m->from());
    auto* out = dynamic_cast<Vec3Object*>(m->to());
    const MeshTopology& mesh = t.container->mesh();
    const bool volume =
        t.container->level() == ElementType::tetrahedron || t.container->level() == ElementType::hexahedron;
    if (in == nullptr || out == nullptr || !volume) return false;
    const bool tetrahedra = t.container->level() == ElementType::tetrahedron;
    const auto remap = [m, in, out, &mesh, tetrahedra] {
        if (tetrahedra) m->map_on_set_tetrahedra(mesh, in->position, out->position);
        else m->map_on_set_hexahedra(mesh, in->position, out->position);
    };
    const std::initializer_list<ElementType> all{ElementType::point, ElementType::edge,        ElementType::triangle,
                                                 ElementType::quad,  ElementType::tetrahedron, ElementType::hexahedron};
    t.container->add_handler(w.keep(std::make_unique<RebuildFollower>(remap, all)), all);
    t.needs_elements.push_back(where(c));
    return true;
}

}  // namespace

void wire_components(TopologyWiring& w) {
    const auto built = built_objects(w.builder.scene(), w.builder.simulation().root());
    const auto visit = [&](const auto& self, const SceneNode& sn) -> void {
        for (const auto& cp : sn.components) {
            const SceneComponent& c = *cp;
            const auto it = built.find(&c);
            if (it == built.end()) continue;
            const Built& b = it->second;
            DynamicTopology* by_topology = w.runtime.find(w.topology_used(c));
            std::set<DynamicTopology*> by_state;
            for (const BaseState* s : b.states()) {
                const auto f = w.followed_states.find(s);
                if (f != w.followed_states.end()) by_state.insert(f->second);
            }
            if (!b.mappings.empty()) {
                // the mapping's output follows the same points (IdentityMapping into a state of the same topology)
                const BaseMapping* m = b.mappings[0];
                const auto out = w.followed_states.find(m->to());
                const bool same = c.type == "IdentityMapping" && out != w.followed_states.end() &&
                                  by_state.size() == 1 && *by_state.begin() == out->second;
                if (!same && by_state.size() == 1 && out == w.followed_states.end() &&
                    (by_topology == nullptr || by_topology == *by_state.begin()) &&
                    follow_barycentric(w, c, b.mappings[0], **by_state.begin()))
                    continue;
                if (!same) {
                    for (DynamicTopology* t : by_state) t->blockers.push_back(where(c));
                    if (by_topology != nullptr && by_state.count(by_topology) == 0)
                        by_topology->blockers.push_back(where(c));
                }
                continue;
            }
            if (follow_attach(w, c, b)) continue;
            if (by_topology == nullptr && by_state.empty()) continue;
            if (follow_spring_ends(w, c, b)) continue;
            const bool follows = by_topology != nullptr && follow(w, c, b, *by_topology);
            if (!follows) {
                if (by_topology != nullptr) by_topology->blockers.push_back(where(c));
                for (DynamicTopology* t : by_state)
                    if (t != by_topology) t->blockers.push_back(where(c));
                continue;
            }
            // a follower of its topology whose state follows another topology's points
            for (DynamicTopology* t : by_state)
                if (t != by_topology &&
                    std::find(t->outputs.begin(), t->outputs.end(), by_topology) == t->outputs.end())
                    t->blockers.push_back(where(c) + " (its topology is " + by_topology->path + ")");
        }
        for (const auto& child : sn.children) self(self, *child);
    };
    visit(visit, *w.builder.scene().file().root);

    // an object built without a component of the file (none today) cannot be given a rule
    const Scene& scene = w.builder.scene();
    const auto orphans = [&](const auto& self, Node& n) -> void {
        const auto check = [&](const void* object, std::span<BaseState* const> states) {
            if (scene.component_of(object) != nullptr) return;
            for (BaseState* s : states) {
                const auto f = w.followed_states.find(s);
                if (f != w.followed_states.end())
                    f->second->blockers.push_back("a component of node '" + n.name() + "'");
            }
        };
        if (BaseMass* m = n.mass()) {
            BaseState* s = m->state();
            check(m, std::span<BaseState* const>(&s, 1));
        }
        for (const auto& f : n.force_fields()) {
            const ForceFieldStates st = f->states();
            check(f.get(), std::span<BaseState* const>(st.begin(), st.end()));
        }
        for (const auto& k : n.constraints()) {
            BaseState* s = k->state();
            check(k.get(), std::span<BaseState* const>(&s, 1));
        }
        if (BaseMapping* m = n.mapping()) {
            BaseState* s = m->from();
            check(m, std::span<BaseState* const>(&s, 1));
        }
        for (const auto& child : n.children()) self(self, *child);
    };
    orphans(orphans, w.builder.simulation().root());
}

namespace {

/// A TriangleCollisionModel on a triangle topology without quads, following it in time
/// proportional to the change: the slots a removal fills (swap-and-pop), the new triangles, and
/// every triangle around a vertex of a removed, moved or new triangle or of a renumbered point
/// (their flags, or vertices, may change) are refreshed once the operation is done
/// (TriangleModel::refresh_triangles). A points renumbering rebuilds the model.
class TriangleModelFollower final : public TopologyHandler {
public:
    TriangleModelFollower(TriangleModel& model, std::function<void()> remake)
        : model_(&model), remake_(std::move(remake)) {}

    void handle_topology_changes(std::span<const TopologyChange> changes) override {
        const MeshTopology& mesh = model_->topology();
        for (const TopologyChange& c : changes) {
            if (c.is(TopologyChangeKind::removed, ElementType::triangle)) {
                // sent before the removal: the indices are valid, their vertices are the mesh's
                for (const ElementId id : c.indices) {
                    slots_.push_back(std::size_t(id));
                    const Triangle& t = mesh.triangles()[std::size_t(id)];
                    vertices_.insert(vertices_.end(), t.begin(), t.end());
                }
            } else if (c.is(TopologyChangeKind::added, ElementType::triangle)) {
                for (const ElementId id : c.indices) slots_.push_back(std::size_t(id));
                vertices_.insert(vertices_.end(), c.vertices.begin(), c.vertices.end());
            } else if (c.is(TopologyChangeKind::removed, ElementType::point)) {
                vertices_.insert(vertices_.end(), c.indices.begin(), c.indices.end());  // they take the last points
            } else if (c.kind == TopologyChangeKind::renumbered) {
                rebuild_ = true;
            }
        }
        dirty_ = true;
    }

    void topology_change_done() override {
        if (!dirty_) return;
        dirty_ = false;
        const MeshTopology& mesh = model_->topology();
        if (rebuild_ || !mesh.quads().empty()) {
            remake_();
        } else {
            const auto& triangles = mesh.triangles();
            std::vector<std::size_t> touched = std::move(slots_);
            for (const std::size_t slot : std::vector<std::size_t>(touched))  // a moved triangle's vertices
                if (slot < triangles.size())
                    vertices_.insert(vertices_.end(), triangles[slot].begin(), triangles[slot].end());
            std::sort(vertices_.begin(), vertices_.end());
            vertices_.erase(std::unique(vertices_.begin(), vertices_.end()), vertices_.end());
            const auto& around = mesh.triangles_around_vertex();
            for (const PointId v : vertices_)
                if (std::size_t(v) < around.size())
                    for (const auto t : around[std::size_t(v)]) touched.push_back(std::size_t(t));
            std::sort(touched.begin(), touched.end());
            touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
            model_->refresh_triangles(touched);
        }
        slots_.clear();
        vertices_.clear();
        rebuild_ = false;
    }

private:
    TriangleModel* model_;
    std::function<void()> remake_;
    std::vector<std::size_t> slots_;
    std::vector<PointId> vertices_;
    bool rebuild_ = false;
    bool dirty_ = false;
};

}  // namespace

void wire_collision_models(TopologyWiring& w) {
    for (SceneCollisionModel& sm : w.builder.collision_models()) {
        if (sm.component == nullptr) continue;
        CollisionModel* model = sm.model.get();
        const MeshTopology* mesh = nullptr;
        if (auto* tm = dynamic_cast<TriangleModel*>(model)) mesh = &tm->topology();
        else if (auto* lm = dynamic_cast<LineModel*>(model)) mesh = &lm->topology();
        else if (dynamic_cast<TetrahedronModel*>(model) != nullptr) mesh = w.topology_used(*sm.component);
        DynamicTopology* t = w.runtime.find(mesh);
        if (t == nullptr) continue;
        // SOFA's updateFromTopology: the model takes the topology's elements again
        auto remake = [model, mesh] {
            if (auto* tm = dynamic_cast<TriangleModel*>(model)) {
                TriangleModel fresh(tm->state(), *mesh, tm->params());
                fresh.compute_normals = tm->compute_normals;
                *tm = std::move(fresh);
            } else if (auto* lm = dynamic_cast<LineModel*>(model)) {
                *lm = LineModel(lm->state(), *mesh, lm->params());
            } else if (auto* te = dynamic_cast<TetrahedronModel*>(model)) {
                *te = TetrahedronModel(te->state(), *mesh, te->params());
            }
        };
        const std::initializer_list<ElementType> all{ElementType::point,       ElementType::edge,
                                                     ElementType::triangle,    ElementType::quad,
                                                     ElementType::tetrahedron, ElementType::hexahedron};
        if (auto* tm = dynamic_cast<TriangleModel*>(model); tm != nullptr && mesh->quads().empty()) {
            t->container->add_handler(w.keep(std::make_unique<TriangleModelFollower>(*tm, remake)), all);
            continue;
        }
        t->container->add_handler(w.keep(std::make_unique<RebuildFollower>(remake, all)), all);
    }
}

}  // namespace penalty::scene
