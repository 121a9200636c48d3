#pragma once
/// @file
/// How components follow a TopologyContainer, each with SOFA's own rule
/// (docs/topological-changes.md, "What follows"):
///  - RebuildFollower: a component whose per-element data is a function of each element's rest
///    shape alone (SOFA's TopologyData with a creation callback: TetrahedralCorotationalFEM-,
///    HexahedralFEMForceField; the collision models' updateFromTopology) is rebuilt from the
///    container's final lists once an operation is done: the swap-and-pop order SOFA's data
///    follows is the container's, so the result is SOFA's;
///  - SubsetIndicesFollower: an index list over the points (TopologySubsetIndices:
///    FixedProjectiveConstraint, FixedPlaneProjectiveConstraint);
///  - TriangularBendingSpringsFollower: SOFA's TriangularBendingSprings edge data, event by event
///    (its rules differ from a rebuild: a spring is made only when an edge first gets two
///    triangles);
///  - MemberTopologyHandler: a component whose own member function follows the events
///    (DiagonalMass, TetrahedronFEMForceField, TriangularFEMForceField: handle_topology_changes).

#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/mechanics/topology_container.hpp"

#include <functional>
#include <initializer_list>
#include <memory>
#include <vector>

namespace penalty {

/// Calls `rebuild` at the end of each operation whose events name one of `types`.
class RebuildFollower final : public TopologyHandler {
public:
    RebuildFollower(std::function<void()> rebuild, std::initializer_list<ElementType> types);
    void handle_topology_changes(std::span<const TopologyChange> changes) override;
    void topology_change_done() override;

private:
    std::function<void()> rebuild_;
    std::uint8_t types_ = 0;
    bool dirty_ = false;
};

/// SOFA's TopologySubsetIndices over the points of `container`: removal (subset_indices_remove)
/// and renumbering; new points are not added (supportNewTopologyElements false, the default).
class SubsetIndicesFollower final : public TopologyHandler {
public:
    using Get = std::function<std::vector<Index>()>;
    using Set = std::function<void(std::vector<Index>)>;
    SubsetIndicesFollower(const TopologyContainer& container, Get get, Set set)
        : container_(&container), get_(std::move(get)), set_(std::move(set)) {}
    void handle_topology_changes(std::span<const TopologyChange> changes) override;

private:
    const TopologyContainer* container_;
    Get get_;
    Set set_;
};

/// The spring list of a SpringForceField that its followers (one per end's topology) edit
/// together during an operation; written back to the force field once it is done.
struct SpringListEdit {
    SpringForceField* springs = nullptr;
    std::vector<Spring> list;
    bool dirty = false;
};

/// SOFA HEAD's SpringForceField topology handling (SpringForceField::initializeTopologyHandler on
/// each end's topology, the topology of mstate1's context for the first ends, of mstate2's for the
/// second; SpringForceField, StiffSpringForceField, MeshSpringForceField):
/// applyRemovedPoints (the springs on a removed point leave the list, which keeps its order; an end
/// on the last point takes the removed index), for the first ends then the second ends;
/// applyRemovedEdges only on an edge topology (the first spring from the edge's first vertex to its
/// second is removed; for the second ends, the first from the second vertex to the first). The
/// spring list is rewritten when an operation is done. `ends`: the ends on `container`'s points
/// (both for springs inside one state); the followers of the two ends of springs between two
/// states share one SpringListEdit.
class SpringPointsFollower final : public TopologyHandler {
public:
    enum class Ends : std::uint8_t { first = 1, second = 2, both = 3 };
    /// Springs inside one state: both ends on `container`.
    SpringPointsFollower(SpringForceField& springs, const TopologyContainer& container);
    SpringPointsFollower(std::shared_ptr<SpringListEdit> edit, const TopologyContainer& container, Ends ends);
    void handle_topology_changes(std::span<const TopologyChange> changes) override;
    void topology_change_done() override;

private:
    std::shared_ptr<SpringListEdit> edit_;
    const TopologyContainer* container_;
    Ends ends_;
};

/// Forwards the events to `object.handle_topology_changes(container, changes)`.
template <class T>
class MemberTopologyHandler final : public TopologyHandler {
public:
    MemberTopologyHandler(T& object, const TopologyContainer& container) : object_(&object), container_(&container) {}
    void handle_topology_changes(std::span<const TopologyChange> changes) override {
        object_->handle_topology_changes(*container_, changes);
    }
    void topology_change_done() override {
        if constexpr (requires(T & t) { t.topology_change_done(); }) object_->topology_change_done();
    }

private:
    T* object_;
    const TopologyContainer* container_;
};

/// SOFA's TriangularBendingSprings (edgeInfo: a TopologyData<Edge> on the edge, point and
/// triangle events): applyEdgeCreation, applyTriangleCreation, applyTriangleDestruction,
/// applyPointDestruction, applyPointRenumbering, and the edge data's swap-and-pop. The spring
/// list of `springs` (one spring per activated edge, in edge order: what
/// TriangularBendingSprings::addForce visits) is rewritten when an operation is done.
class TriangularBendingSpringsFollower final : public TopologyHandler {
public:
    /// Builds the edge data as SOFA's reinit does (every edge, then every triangle in order).
    TriangularBendingSpringsFollower(SpringForceField& springs, const TopologyContainer& container,
                                     const Vec3Object& state, double ks, double kd);
    void handle_topology_changes(std::span<const TopologyChange> changes) override;
    void topology_change_done() override;

    struct EdgeInformation {
        PointId m1 = 0, m2 = 0;
        double ks = 0, kd = 0, rest_length = 0;
        bool activated = false, initialized = false;
    };
    [[nodiscard]] const std::vector<EdgeInformation>& edges() const { return edges_; }
    /// The springs of the activated edges, in edge order.
    [[nodiscard]] std::vector<Spring> springs() const;

private:
    void triangles_added(std::span<const ElementId> added);
    void triangles_removed(std::span<const ElementId> removed);
    void points_removed(std::span<const ElementId> removed);
    /// ei.m1, m2, rest length from the edge's other triangle t1 and triangle t2.
    void make_spring(EdgeInformation& ei, ElementId edge, ElementId t1, ElementId t2) const;

    SpringForceField* springs_;
    const TopologyContainer* container_;
    const Vec3Object* state_;
    double ks_, kd_;
    std::vector<EdgeInformation> edges_;
    bool dirty_ = false;
};

/// SOFA's QuadularBendingSprings (edgeInfo on the edge, point and quad events): two springs per
/// edge between two quads, across the edge (applyQuadCreation, applyQuadDestruction,
/// applyPointDestruction), rewritten into `springs` when an operation is done.
class QuadularBendingSpringsFollower final : public TopologyHandler {
public:
    QuadularBendingSpringsFollower(SpringForceField& springs, const TopologyContainer& container,
                                   const Vec3Object& state, double ks, double kd);
    void handle_topology_changes(std::span<const TopologyChange> changes) override;
    void topology_change_done() override;
    [[nodiscard]] std::vector<Spring> springs() const;

private:
    struct EdgeInformation {
        std::array<std::array<PointId, 2>, 2> springs{};
        std::array<double, 2> rest_length{};
        double ks = 0, kd = 0;
        bool activated = false, initialized = false;
    };
    void quads_added(std::span<const ElementId> added);
    void quads_removed(std::span<const ElementId> removed);
    void points_removed(std::span<const ElementId> removed);
    /// The two springs of `edge` between quads q1 (the other) and q2.
    void make_springs(EdgeInformation& ei, ElementId edge, ElementId q1, ElementId q2) const;

    SpringForceField* springs_;
    const TopologyContainer* container_;
    const Vec3Object* state_;
    double ks_, kd_;
    std::vector<EdgeInformation> edges_;
    bool dirty_ = false;
};

}  // namespace penalty
