// Engines over moving states, run on read (live_engines.hpp; docs/python.md, "Engines over moving
// states"): the run itself, the states that follow an engine, and the wiring of the built scene's
// readers (Scene::LiveEdits::wire_engines).
#include "scene/live_engines.hpp"

#include "penalty/mechanics/mass.hpp"
#include "penalty/scene/components.hpp"
#include "penalty/scene/scene.hpp"
#include "scene/builder/scene_builder.hpp"
#include "scene/live_edits.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace penalty::scene {

namespace {

bool same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0);  // NOLINT(bugprone-*)
}

bool is_fixed_constraint(const io::SceneComponent& c) {
    return c.type == "FixedProjectiveConstraint" || c.type == "FixedConstraint";
}

/// The FixedProjectiveConstraint built from `c` in `node`, or null.
FixedProjectiveConstraint* built_fixed_constraint(const Scene& scene, const Node& node, const io::SceneComponent& c) {
    for (const auto& k : node.constraints())
        if (auto* f = dynamic_cast<FixedProjectiveConstraint*>(k.get()); f != nullptr && scene.component_of(f) == &c)
            return f;
    return nullptr;
}

}  // namespace

bool LiveEngine::update_if_dirty() {
    if (runs_ != 0 && same_bits(input_->position, last_input_)) return false;
    last_input_ = input_->position;  // the buffer's capacity stays: no allocation once it has run
    evaluate_(last_input_, *this);
    ++runs_;
    return true;
}

void LiveEngines::update_linked_states() {
    for (LinkedState& s : linked_states) {
        if (!s.reader.pull()) continue;
        const auto it = s.reader.engine->meshes.find(s.reader.output);
        const std::vector<Vec3>& points = it->second.positions;
        if (points.size() != s.state->position.size())
            throw std::invalid_argument(
                "MechanicalObject '" + s.path + "': its position links " + s.reader.engine->component().describe() +
                "." + s.reader.output + ", which now has " + std::to_string(points.size()) + " points for " +
                std::to_string(s.state->position.size()) + " DOFs (a state keeps its size while the scene runs)");
        std::copy(points.begin(), points.end(), s.state->position.begin());
    }
}

const Vec3Object* SceneBuilder::moving_input(const Attributes& a, std::string_view attr) {
    if (!a.has(attr) || !a.is_link(attr)) return nullptr;
    std::vector<io::LinkTarget> targets;
    try {
        targets = io::resolve_links(a.component(), attr);
    } catch (const io::SceneError&) {
        return nullptr;  // the engine's own build reports it
    }
    if (targets.size() != 1 || targets[0].component == nullptr || targets[0].data != "position") return nullptr;
    const io::SceneComponent& source = *targets[0].component;
    if (source.type != "MechanicalObject") return nullptr;
    const auto it = nodes_.find(source.node);
    if (it == nodes_.end() || it->second.state_component != &source || it->second.node == nullptr) return nullptr;
    return dynamic_cast<const Vec3Object*>(it->second.node->state());
}

void SceneBuilder::add_live_engine(const io::SceneComponent& c, const Vec3Object& input,
                                   LiveEngine::Evaluate evaluate) {
    std::unique_ptr<LiveEngines>& engines = scene_.live_->engines;
    if (!engines) engines = std::make_unique<LiveEngines>();
    LiveEngines& live = *engines;
    live.engines.push_back(std::make_unique<LiveEngine>(c, input, std::move(evaluate)));
    live.by_component[&c] = live.engines.back().get();
}

void Scene::LiveEdits::wire_engines(Scene& scene) {
    if (!scene.live_->engines) return;
    LiveEngines& live = *scene.live_->engines;
    io::for_each_component(*scene.file_.root, [&](const io::SceneComponent& c) {
        for (const io::SceneAttribute& a : c.attributes) {
            if (!io::is_link(a.value)) continue;
            std::vector<io::LinkTarget> targets;
            try {
                targets = io::resolve_links(c, a.name);
            } catch (const io::SceneError&) {
                continue;
            }
            for (const io::LinkTarget& t : targets) {
                LiveEngine* engine = t.component != nullptr ? live.find(*t.component) : nullptr;
                if (engine == nullptr || t.data.empty()) continue;
                engine->update_if_dirty();  // its first run (the build's values): its outputs exist
                const Node* node = scene.node_of(*c.node);
                const bool index_output = engine->indices.count(t.data) != 0;
                const bool point_output =
                    engine->meshes.count(t.data) != 0 && !engine->meshes.find(t.data)->second.positions.empty();
                if (is_fixed_constraint(c) && a.name == "indices" && targets.size() == 1 && index_output &&
                    node != nullptr) {
                    if (FixedProjectiveConstraint* f = built_fixed_constraint(scene, *node, c)) {
                        const std::size_t size = f->state()->num_dofs();
                        f->set_index_source([reader = LiveEngineReader{engine, t.data, 0}, size,
                                             what = c.describe()](std::vector<Index>& indices) mutable {
                            if (!reader.pull()) return;
                            const std::vector<PointId>& out = reader.engine->indices.find(reader.output)->second;
                            for (PointId i : out)
                                if (i < 0 || std::size_t(i) >= size)
                                    throw std::invalid_argument(what + ": index " + std::to_string(i) + " of " +
                                                                reader.engine->component().describe() +
                                                                " is out of range (" + std::to_string(size) + " DOFs)");
                            indices.assign(out.begin(), out.end());
                        });
                        continue;
                    }
                }
                if (c.type == "MechanicalObject" && a.name == "position" && targets.size() == 1 && point_output &&
                    node != nullptr) {
                    if (auto* state = dynamic_cast<Vec3Object*>(node->state()); state != nullptr) {
                        live.linked_states.push_back(
                            {LiveEngineReader{engine, t.data, 0}, state, Scene::component_path(c)});
                        continue;
                    }
                }
                scene.build_warnings_.push_back(
                    c.file + ":" + std::to_string(a.line) + ": " + c.describe() + ": attribute '" + a.name +
                    "' links " + engine->component().describe() + "." + t.data +
                    ", an engine over moving positions: penalty reads it once, when the "
                    "scene is built (SOFA reads it again after each change of the positions)");
            }
        }
    });
    // the states take the outputs of the engines' first runs (the values the build gave them)
    live.update_linked_states();
}

}  // namespace penalty::scene
