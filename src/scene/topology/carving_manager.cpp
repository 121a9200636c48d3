// SOFA's CarvingManager (SofaCarving: doCarve at AnimateEndEvent) with its
// TopologicalChangeManager::removeItemsFromCollisionModel: every detection output of the last
// collision step between the tool model and a model tagged CarvingSurface whose value (distance
// minus contact distance) is below carvingDistance names a surface element; each becomes the
// topology element it belongs to (a triangle's only tetrahedron in a tetrahedral topology, ...),
// through the topological mappings down to the topology that holds it, and those are removed with
// the items they leave isolated. Unlike SOFA, which removes after each model pair (the next
// pair's elements then index the changed topology), every pair's elements are gathered first and
// removed once per topology.
#include "penalty/collision/models.hpp"
#include "penalty/mechanics/topological_mapping_changes.hpp"
#include "scene/topology/topology_changes.hpp"

#include <map>
#include <set>
#include <sstream>

namespace penalty::scene {

namespace {

bool has_tag(const io::SceneComponent& c, std::string_view tag) {
    std::istringstream in(io::get_string(c, "tags").value_or(""));
    for (std::string t; in >> t;)
        if (t == tag) return true;
    return false;
}

/// One carved model: the dynamic topology its elements index and how an element maps to it.
struct CarvedModel {
    CollisionModel* model = nullptr;
    DynamicTopology* topology = nullptr;
};

class CarvingSource final : public TopologyChangeSource {
public:
    CarvingSource(const io::SceneComponent& component, Scene& scene, CollisionModel& tool,
                  std::vector<CarvedModel> carved, double distance)
        : component_(&component), scene_(&scene), tool_(&tool), carved_(std::move(carved)), distance_(distance) {}

    void end_step(double) override {
        std::map<DynamicTopology*, std::set<ElementId>> items;
        for (const ScenePipeline& p : scene_->pipelines()) {
            for (const ModelPairDetection& d : p.pipeline->detections()) {
                const CarvedModel* target = nullptr;
                for (const CarvedModel& m : carved_)
                    if ((d.model1 == tool_ && d.model2 == m.model) || (d.model2 == tool_ && d.model1 == m.model))
                        target = &m;
                if (target == nullptr) continue;
                const bool tool_first = d.model1 == tool_;
                for (const DetectionOutput& o : d.outputs)
                    if (o.value < distance_)
                        add_item(*target, ElementId((tool_first ? o.elem2 : o.elem1).value()), items);
            }
        }
        // every topology checked before any changes (a step's carving applies whole or not at all)
        for (auto& [topology, set] : items) {
            const TopologyContainer& c = *topology->container;
            try {
                TopologyRuntime::check_keeps_elements(*topology, c.level(), c.count(c.level()) - set.size());
            } catch (const std::invalid_argument& e) {
                io::throw_element_error(*component_, e.what());
            }
        }
        for (auto& [topology, set] : items) {
            if (set.empty()) continue;
            TopologyContainer& c = *topology->container;
            c.remove_items(std::vector<ElementId>(set.rbegin(), set.rend()));
            c.notify_ending_event();
        }
    }

private:
    const io::SceneComponent* component_;
    /// removeItemsFromTriangleModel / PointModel / SphereModel: the element's item in the model's
    /// topology, then through each topological mapping whose output it is.
    void add_item(const CarvedModel& m, ElementId element,
                  std::map<DynamicTopology*, std::set<ElementId>>& items) const {
        DynamicTopology* t = m.topology;
        const MeshTopology& mesh = t->container->mesh();
        std::vector<ElementId> found;
        if (dynamic_cast<const TriangleModel*>(m.model) != nullptr) {
            const auto nt = ElementId(mesh.triangles().size());
            found.push_back(element < nt ? element : (element + nt) / 2);  // a split quad's triangles: its quad
        } else if (dynamic_cast<const PointModel*>(m.model) != nullptr) {
            if (std::size_t(element) < mesh.triangles_around_vertex().size())
                for (const auto tri : mesh.triangles_around_vertex()[std::size_t(element)]) found.push_back(tri);
        } else {
            found.push_back(element);  // SphereModel on a point topology
        }
        for (ElementId& e : found) {
            DynamicTopology* at = t;
            if (!mesh.tetrahedra().empty() && dynamic_cast<const TriangleModel*>(m.model) != nullptr) {
                e = t->container->tetrahedra_around_triangle()[std::size_t(e)][0];
            } else {
                while (at->fed_by != nullptr && at->input != nullptr) {  // down the topological mappings
                    const ElementId from = at->fed_by->input_cell_of(e);
                    if (from < 0) break;
                    e = from;
                    at = at->input;
                }
            }
            if (e >= 0 && std::size_t(e) < at->container->count(at->container->level())) items[at].insert(e);
        }
    }

    Scene* scene_;
    CollisionModel* tool_;
    std::vector<CarvedModel> carved_;
    double distance_;
};

}  // namespace

void add_carving_managers(TopologyWiring& w) {
    const auto visit = [&](const auto& self, const io::SceneNode& sn) -> void {
        for (const auto& cp : sn.components) {
            const io::SceneComponent& c = *cp;
            if (c.type != "CarvingManager") continue;
            const Attributes a(c);
            if (!a.boolean("active")) continue;  // SOFA carves only while active (keys, headless: never)
            CollisionModel* tool = nullptr;
            const io::SceneComponent* tool_component = a.has("toolModel") ? a.link("toolModel").component : nullptr;
            std::vector<CarvedModel> carved;
            const std::string path = a.text("surfaceModelPath");
            for (SceneCollisionModel& m : w.builder.collision_models()) {
                if (m.component == nullptr) continue;
                if (tool_component != nullptr ? m.component == tool_component
                                              : (tool == nullptr && has_tag(*m.component, "CarvingTool")))
                    tool = m.model.get();
                const bool surface = path.empty() ? has_tag(*m.component, "CarvingSurface")
                                                  : (m.component->node->path() + "/" + m.component->name == path ||
                                                     m.component->name == path);
                if (!surface) continue;
                const MeshTopology* mesh = nullptr;
                if (auto* tm = dynamic_cast<TriangleModel*>(m.model.get())) mesh = &tm->topology();
                else if (auto* pm = dynamic_cast<PointModel*>(m.model.get())) mesh = pm->topology();
                else mesh = w.topology_used(*m.component);
                DynamicTopology* t = w.runtime.find(mesh);
                if (t == nullptr)
                    io::throw_element_error(
                        c, "carved model " + m.component->describe() +
                               " is not over a topology that can change (a ...SetTopologyContainer with a "
                               "...SetTopologyModifier)");
                carved.push_back({m.model.get(), t});
            }
            if (tool == nullptr)
                a.fail("toolModel", "no tool: link toolModel to a collision model, or tag one CarvingTool");
            if (carved.empty())
                a.fail("surfaceModelPath", "nothing to carve: tag a collision model CarvingSurface (or give its path)");
            for (const CarvedModel& m : carved) {
                DynamicTopology* root = m.topology;
                while (root->input != nullptr) root = root->input;
                try {
                    w.runtime.check_can_change(*root);
                } catch (const std::invalid_argument& e) {
                    io::throw_element_error(c, e.what());
                }
            }
            w.runtime.sources.push_back(std::make_unique<CarvingSource>(c, w.builder.scene(), *tool, std::move(carved),
                                                                        a.real("carvingDistance")));
        }
        for (const auto& child : sn.children) self(self, *child);
    };
    visit(visit, *w.builder.scene().file().root);
}

}  // namespace penalty::scene
