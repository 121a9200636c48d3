// SurfacePressureForceField, TaitSurfacePressureForceField and RestShapeSpringsForceField on a
// changing topology, each with its SOFA class's rule (docs/topological-changes.md, "What follows").
#include "penalty/mechanics/pressure_loads.hpp"
#include "penalty/mechanics/rest_shape_springs.hpp"
#include "penalty/mechanics/tait_surface_pressure.hpp"
#include "penalty/mechanics/topology_followers.hpp"
#include "scene/topology/topology_changes.hpp"

#include <iostream>
#include <memory>

namespace penalty::scene {

namespace {

std::string component_at(const io::SceneComponent& c) {
    return c.describe() + " (" + c.file + ":" + std::to_string(c.line) + ")";
}

/// SOFA's RestShapeSpringsForceField on a changing topology: `points` is a TopologySubsetIndices
/// (bwdInit's d_points.createTopologyHandler: a removed point leaves the list, the last point's
/// entries take its index); `stiffness`, `external_points` and an external rest shape are no
/// topology data. With recompute_indices (the default) the springs are resolved again once the
/// operation is done (the states followed), as addForce's recomputeIndices does; when SOFA's
/// checkOutOfBoundsIndices then fails (external points that no longer match) the springs go off,
/// as in SOFA, with a warning naming the component. Without it addForce keeps init's springs
/// (m_indices, which nothing recomputes: the updateIndices callback on `points` runs only when
/// the component state is read, which a headless run never does): a spring left past its
/// state's end acts on nothing, with a warning (SOFA HEAD reads and writes past the vectors).
template <class DataTypes>
class RestShapeSpringsFollower final : public TopologyHandler {
public:
    RestShapeSpringsFollower(RestShapeSpringsForceField<DataTypes>& ff, const TopologyContainer& container,
                             std::string name)
        : ff_(&ff),
          points_(
              container, [f = &ff] { return f->point_list(); },
              [f = &ff](std::vector<Index> i) { f->follow_points(std::move(i)); }),
          name_(std::move(name)) {}
    void handle_topology_changes(std::span<const TopologyChange> changes) override {
        points_.handle_topology_changes(changes);
        dirty_ = true;
    }
    void topology_change_done() override {
        if (!dirty_) return;
        dirty_ = false;
        if (!ff_->recompute_indices()) {
            if (const std::size_t lost = ff_->springs_past_end(); lost > 0)
                std::cerr << "warning: " << name_ << ": after the topological change " << lost
                          << " of its springs (recompute_indices=\"0\": init's point indices) name a point past the "
                             "state's end (SOFA HEAD reads and writes past the state's vectors there): they act on "
                             "nothing\n";
            return;
        }
        const bool was_active = ff_->active();
        if (!ff_->resolve_after_change() && was_active)
            std::cerr
                << "warning: " << name_ << ": after the topological change " << ff_->inactive_reason()
                << ": its springs are off, as SOFA's RestShapeSpringsForceField::checkOutOfBoundsIndices leaves them\n";
    }

private:
    RestShapeSpringsForceField<DataTypes>* ff_;
    SubsetIndicesFollower points_;
    std::string name_;
    bool dirty_ = false;
};

/// SOFA's SurfacePressureForceField has no topology data: addForce presses the topology's current
/// triangles and quads, or the elements now in the slots its triangleIndices / quadIndices name
/// (plain Data, never renumbered). Once an operation is done the last tangent stiffness is dropped
/// and a listed index past the topology's end is reported (SOFA HEAD reads outside the topology
/// there and crashes; penalty presses nothing for it).
class SurfacePressureFollower final : public TopologyHandler {
public:
    SurfacePressureFollower(SurfacePressureForceField& ff, std::string name) : ff_(&ff), name_(std::move(name)) {}
    void handle_topology_changes(std::span<const TopologyChange>) override { dirty_ = true; }
    void topology_change_done() override {
        if (!dirty_) return;
        dirty_ = false;
        if (const std::size_t past = ff_->topology_changed(); past > 0)
            std::cerr << "warning: " << name_ << ": after the topological change " << past
                      << " of its listed triangleIndices / quadIndices are past the topology's end (SOFA's lists are "
                         "no topology data: SOFA HEAD reads outside the topology there and crashes): they press "
                         "nothing\n";
    }

private:
    SurfacePressureForceField* ff_;
    std::string name_;
    bool dirty_ = false;
};

constexpr std::initializer_list<ElementType> kEveryElementType{ElementType::point,       ElementType::edge,
                                                               ElementType::triangle,    ElementType::quad,
                                                               ElementType::tetrahedron, ElementType::hexahedron};

}  // namespace

bool follow_surface_load_or_rest_springs(TopologyWiring& w, const io::SceneComponent& c, BaseForceField& f,
                                         DynamicTopology& t) {
    TopologyContainer& container = *t.container;
    if (c.type == "SurfacePressureForceField") {
        auto* ff = dynamic_cast<SurfacePressureForceField*>(&f);
        if (ff == nullptr) return false;
        container.add_handler(w.keep(std::make_unique<SurfacePressureFollower>(*ff, component_at(c))),
                              {ElementType::triangle, ElementType::quad, ElementType::point});
        return true;
    }
    // TaitSurfacePressureForceField::updateFromTopology at the next addForce (or AnimateBeginEvent
    // while injecting) once the topology's revision moved: any event of the container
    if (c.type == "TaitSurfacePressureForceField") {
        auto* ff = dynamic_cast<TaitSurfacePressureForceField*>(&f);
        if (ff == nullptr) return false;
        container.add_handler(
            w.keep(std::make_unique<RebuildFollower>([ff] { ff->topology_changed(); }, kEveryElementType)),
            kEveryElementType);
        return true;
    }
    if (c.type == "RestShapeSpringsForceField") {
        const auto follow_points = [&]<class D>(RestShapeSpringsForceField<D>* ff) {
            container.add_handler(
                w.keep(std::make_unique<RestShapeSpringsFollower<D>>(*ff, container, component_at(c))),
                {ElementType::point});
            return true;
        };
        if (auto* ff = dynamic_cast<RestShapeSpringsForceField<Vec3Types>*>(&f)) return follow_points(ff);
        if (auto* ff = dynamic_cast<RestShapeSpringsForceField<Rigid3Types>*>(&f)) return follow_points(ff);
    }
    return false;
}

}  // namespace penalty::scene
