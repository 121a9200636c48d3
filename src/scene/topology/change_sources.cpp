// The components that change topologies while the scene runs, made from the scene file once it is
// built: TopologicalChangeProcessor (its file, or its lists with useDataInputs) and
// TopologyBoundingTrasher. Each names the dynamic topology it changes (its `topology` link, else its
// node's, as SOFA's getMeshTopologyLink); one that cannot change is refused here, naming the
// component that cannot follow.
#include "penalty/io/data_path.hpp"
#include "penalty/mechanics/regions.hpp"
#include "penalty/mechanics/regions_of_interest.hpp"
#include "scene/topology/topological_change_processor.hpp"
#include "scene/topology/topology_changes.hpp"

#include <fstream>
#include <sstream>

namespace penalty::scene {

using io::SceneComponent;

namespace {

DynamicTopology& target_topology(TopologyWiring& w, const SceneComponent& c) {
    DynamicTopology* t = w.runtime.find(w.topology_used(c));
    if (t == nullptr)
        io::throw_element_error(
            c,
            "needs a topology that can change: a ...SetTopologyContainer with a ...SetTopologyModifier "
            "in its node (or a `topology` link to one)");
    return *t;
}

void check_changeable(const TopologyWiring& w, const SceneComponent& c, const DynamicTopology& t) {
    try {
        w.runtime.check_can_change(t);
    } catch (const std::invalid_argument& e) {
        io::throw_element_error(c, e.what());
    }
}

/// The current points of the state a `position` link names.
const Vec3Object* linked_state(TopologyWiring& w, const SceneComponent& c, std::string_view attr) {
    if (!io::get_string(c, attr) || !io::is_link(*io::get_string(c, attr))) return nullptr;
    const io::LinkTarget t = io::resolve_link(c, attr);
    if (t.component == nullptr || t.component->type != "MechanicalObject" || (t.data != "position" && !t.data.empty()))
        io::throw_attribute_error(c, attr, "must link to a MechanicalObject's position");
    const NodeBuild& nb = w.builder.node_build(*t.component->node);
    return nb.node != nullptr ? dynamic_cast<const Vec3Object*>(nb.node->state()) : nullptr;
}

/// A removal list linked to a BoxROI's output: BoxROI::doUpdate again when the list is used (SOFA's
/// engine updates when its inputs, the current positions, changed), on the topology's current elements.
std::function<std::vector<ElementId>()> box_roi_source(TopologyWiring& w, const SceneComponent& tcp,
                                                       std::string_view attr, const io::LinkTarget& link,
                                                       DynamicTopology& target) {
    const SceneComponent& roi = *link.component;
    static constexpr std::pair<std::string_view, ElementType> kOutputs[] = {
        {"indices", ElementType::point},
        {"edgeIndices", ElementType::edge},
        {"triangleIndices", ElementType::triangle},
        {"quadIndices", ElementType::quad},
        {"tetrahedronIndices", ElementType::tetrahedron},
        {"hexahedronIndices", ElementType::hexahedron}};
    std::optional<ElementType> type;
    for (const auto& [name, t] : kOutputs)
        if (link.data == name) type = t;
    if (roi.type != "BoxROI" || !type)
        io::throw_attribute_error(tcp, attr,
                                  "a link must name a BoxROI's indices, edgeIndices, triangleIndices, "
                                  "quadIndices, tetrahedronIndices or hexahedronIndices");
    const std::vector<double> numbers = io::get_doubles(roi, "box");
    if (numbers.empty() || numbers.size() % 6 != 0)
        io::throw_attribute_error(roi, "box", "penalty follows a BoxROI's output over time only with explicit boxes");
    std::vector<AlignedBox> boxes;
    for (std::size_t i = 0; i + 5 < numbers.size(); i += 6)
        boxes.push_back(AlignedBox::from_corners(Vec3(numbers[i], numbers[i + 1], numbers[i + 2]),
                                                 Vec3(numbers[i + 3], numbers[i + 4], numbers[i + 5])));
    const Vec3Object* state = linked_state(w, roi, "position");
    if (state == nullptr) {
        const NodeBuild& nb = w.builder.node_build(*roi.node);
        state = nb.node != nullptr ? dynamic_cast<const Vec3Object*>(nb.node->state()) : nullptr;
        if (state == nullptr) io::throw_attribute_error(roi, "position", "needs the state whose points it selects");
    }
    const bool strict = io::get_bool_or(roi, "strict", true);
    const MeshTopology& mesh = target.container->mesh();
    const ElementType wanted = *type;
    return [boxes, state, strict, &mesh, wanted] {
        RoiElements elements;
        switch (wanted) {
            case ElementType::point:
                break;
            case ElementType::edge:
                elements.edges = mesh.edges();
                break;
            case ElementType::triangle:
                elements.triangles = mesh.triangles();
                break;
            case ElementType::quad:
                elements.quads = mesh.quads();
                break;
            case ElementType::tetrahedron:
                elements.tetrahedra = mesh.tetrahedra();
                break;
            case ElementType::hexahedron:
                elements.hexahedra = mesh.hexahedra();
                break;
        }
        const auto inside = [&](const Vec3& p) {
            return std::any_of(boxes.begin(), boxes.end(), [&](const AlignedBox& b) { return b.contains(p); });
        };
        const RoiSelection s =
            select_in_region(state->position, elements, inside, strict ? ElementTest::all_points : ElementTest::center);
        const std::vector<PointId>& picked = wanted == ElementType::point         ? s.points
                                             : wanted == ElementType::edge        ? s.edges
                                             : wanted == ElementType::triangle    ? s.triangles
                                             : wanted == ElementType::quad        ? s.quads
                                             : wanted == ElementType::tetrahedron ? s.tetrahedra
                                                                                  : s.hexahedra;
        return std::vector<ElementId>(picked.begin(), picked.end());
    };
}

void add_processor(TopologyWiring& w, const SceneComponent& c) {
    DynamicTopology& target = target_topology(w, c);
    auto tcp = std::make_unique<TopologicalChangeProcessorSource>(c, target, w.runtime);
    const Attributes a(c);
    tcp->shift_ = a.real("shift");
    tcp->loop_ = a.boolean("loop");
    tcp->interval_ = a.real("interval");
    tcp->data_inputs_ = a.boolean("useDataInputs");
    tcp->refuse_out_of_range_ = w.builder.options().sofa_quirk_fixes.fix_topology_removal_out_of_range;
    tcp->refuse_invalid_incision_ = w.builder.options().sofa_quirk_fixes.fix_incision_invalid_path;
    if (tcp->data_inputs_) {
        tcp->time_to_remove_ = a.real("timeToRemove");
        static constexpr std::pair<const char*, ElementType> kLists[] = {
            {"hexahedraToRemove", ElementType::hexahedron}, {"tetrahedraToRemove", ElementType::tetrahedron},
            {"quadsToRemove", ElementType::quad},           {"trianglesToRemove", ElementType::triangle},
            {"edgesToRemove", ElementType::edge},           {"pointsToRemove", ElementType::point}};
        for (const auto& [name, type] : kLists) {
            if (!a.has(name)) continue;
            TopologicalChangeProcessorSource::RemovalList list{type, std::size_t(c.find(name)->line), {}, {}};
            if (a.is_link(name)) {
                list.source = box_roi_source(w, c, name, a.link(name), target);
            } else {
                for (const PointId i : a.indices(name)) list.values.push_back(i);
            }
            tcp->lists_.push_back(std::move(list));
        }
        if (!tcp->lists_.empty()) check_changeable(w, c, target);
    } else {
        if (!a.has("filename")) a.fail("filename", "names the file of topological changes (or set useDataInputs)");
        const std::string name = a.text("filename");
        std::filesystem::path path;
        try {
            path = io::resolve_data_file(name, w.builder.scene_dir(), w.builder.options().data_dirs);
        } catch (const std::exception& e) {
            a.fail("filename", std::string("cannot open ") + name + " (" + e.what() + ")");
        }
        std::ifstream in(path, std::ios::binary);
        if (!in) a.fail("filename", "cannot open " + path.string());
        std::ostringstream text;
        text << in.rdbuf();
        w.builder.guarded(c, [&] { tcp->file_.emplace(text.str(), path.string()); });
        for (const std::string& note : tcp->file_->notes()) w.builder.warn(note);
        if (tcp->file_->has_incisions() && a.boolean("saveIndicesAtInit")) {
            // SOFA's inciseWithSavedIndices snaps with the attributes (its file mode with 0.1, 0.25)
            tcp->save_indices_at_init_ = true;
            tcp->epsilon_snap_path_ = a.real("epsilonSnapPath");
            tcp->epsilon_snap_border_ = a.real("epsilonSnapBorder");
            w.builder.guarded(c, [&] { (void)tcp->file_->timed_incisions(); });
        }
        check_changeable(w, c, target);
    }
    w.runtime.sources.push_back(std::move(tcp));
}

/// TopologyBoundingTrasher: at each step's end, the elements of its type whose barycentre is
/// outside the box (isPointOutside: strictly beyond a bound) are removed.
class BoundingTrasherSource final : public TopologyChangeSource {
public:
    BoundingTrasherSource(DynamicTopology& target, const Vec3Object& state, const std::array<double, 6>& box)
        : target_(&target), state_(&state), box_(box) {
        const TopologyContainer& c = *target.container;
        for (const ElementType t : {ElementType::hexahedron, ElementType::tetrahedron, ElementType::quad,
                                    ElementType::triangle, ElementType::edge})
            if (c.keeps(t) && c.count(t) > 0) {
                type_ = t;
                break;
            }
    }
    void end_step(double) override {
        if (!type_) return;
        TopologyContainer& c = *target_->container;
        const auto& x = state_->position;
        std::vector<ElementId> outside;
        for (std::size_t e = 0; e < c.count(*type_); ++e) {
            const auto v = c.vertices(*type_, ElementId(e));
            Vec3 bary = Vec3::Zero();
            for (const PointId p : v) bary += x[std::size_t(p)];
            bary /= double(v.size());
            bool out = false;
            for (int k = 0; k < 3; ++k)
                out = out || bary[k] < box_[std::size_t(k)] || bary[k] > box_[std::size_t(k) + 3];
            if (out) outside.push_back(ElementId(e));
        }
        if (outside.empty()) return;
        switch (*type_) {
            case ElementType::hexahedron:
                c.remove_hexahedra(outside);
                break;
            case ElementType::tetrahedron:
                c.remove_tetrahedra(outside);
                break;
            case ElementType::quad:
                c.remove_quads(outside, true, true);
                break;
            case ElementType::triangle:
                c.remove_triangles(outside, true, true);
                break;
            default:
                c.remove_edges(outside);
                break;
        }
    }

private:
    DynamicTopology* target_;
    const Vec3Object* state_;
    std::array<double, 6> box_;
    std::optional<ElementType> type_;
};

void add_trasher(TopologyWiring& w, const SceneComponent& c) {
    DynamicTopology& target = target_topology(w, c);
    const Attributes a(c);
    const std::vector<double> b = a.numbers("box");
    if (b.size() != 6) a.fail("box", "expected 6 numbers: xmin ymin zmin xmax ymax zmax");
    const Vec3Object* state = linked_state(w, c, "position");
    if (state == nullptr) {
        const NodeBuild* owner = w.builder.state_owner(w.builder.node_build(*c.node));
        state = owner != nullptr ? dynamic_cast<const Vec3Object*>(owner->node->state()) : nullptr;
        if (state == nullptr) a.fail("position", "needs the Vec3d state of the topology's points");
    }
    check_changeable(w, c, target);
    w.runtime.sources.push_back(std::make_unique<BoundingTrasherSource>(
        target, *state, std::array<double, 6>{b[0], b[1], b[2], b[3], b[4], b[5]}));
}

}  // namespace

void add_topology_change_sources(TopologyWiring& w) {
    const auto visit = [&](const auto& self, const io::SceneNode& sn) -> void {
        for (const auto& c : sn.components) {
            if (c->type == "TopologicalChangeProcessor") add_processor(w, *c);
            else if (c->type == "TopologyBoundingTrasher") add_trasher(w, *c);
        }
        for (const auto& child : sn.children) self(self, *child);
    };
    visit(visit, *w.builder.scene().file().root);
}

}  // namespace penalty::scene
