// Engines over moving states, run on read (live_engines.hpp; docs/python.md, "Engines over moving
// states"): the run itself, the states that follow an engine, and the wiring of the built scene's
// readers (Scene::LiveEdits::wire_engines).
#include "scene/live_engines.hpp"

#include "penalty/mechanics/fixed_plane_constraint.hpp"
#include "penalty/mechanics/followed_indices.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/scene/components.hpp"
#include "penalty/scene/scene.hpp"
#include "scene/builder/scene_builder.hpp"
#include "scene/live_edits.hpp"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <optional>
#include <stdexcept>

namespace penalty::scene {

namespace {

/// The engines penalty runs again on read (SOFA's DataEngine::update over an input linked to moving
/// positions): the Data of their input points and the flag that switches re-runs off.
/// BoxROI, SphereROI, MeshROI: BaseROI::doUpdate selects again only with `doUpdate` (BaseROI::init
/// runs it once whatever the flag). PlaneROI::doUpdate, ProximityROI::doUpdate,
/// TransformEngine::doUpdate, TransformPosition::doUpdate: always.
/// MergePoints::doUpdate: unless `noUpdate` (a flag written `!noUpdate`: the engine runs again
/// unless it is 1). SubsetTopology::doUpdate, ValuesFromPositions::doUpdate: always.
/// Followed besides the points (their builders read them through LiveEngine::followed), inputs of
/// SOFA's engines (addInput: a change runs the engine again): BoxROI's `box` (BoxROI's constructor;
/// a list of points converted to boxes as BaseData::genericCopyValueFrom does), ProximityROI's `centers`,
/// MergePoints' `position2`, MeshROI's `ROIposition` (MeshROI's constructor; its bounding box stays
/// that of init, MeshROI::roiInit), TransformEngine's `translation`, `rotation` and `scale`
/// (TransformEngine's constructor; a Data linked to a state's positions takes its first point,
/// BaseData::genericCopyValueFrom), TransformPosition's `translation`, `rotation`, `scale` and
/// `origin` (its `normal`, which TransformPosition::init normalises once, is not followed),
/// ValuesFromPositions' `direction` (its constructor; a list of points gives its first). SphereROI's `centers` (`~`:
/// SOFA HEAD's SphereROI does not add them as an input, so they are read when the points run the engine again: a
/// state's as of the step's start).
constexpr LiveEngineKind kLiveEngineKinds[] = {
    {"BoxROI", "position", "rest_position", "doUpdate", {"box"}},
    {"SphereROI", "position", "rest_position", "doUpdate", {"~centers"}},
    {"MeshROI", "position", "rest_position", "doUpdate", {"ROIposition"}},
    {"PlaneROI", "position", "rest_position", "", {}},
    {"ProximityROI", "position", "rest_position", "", {"centers"}},
    {"TransformEngine", "input_position", "", "", {"translation", "rotation", "scale"}},
    {"TransformPosition", "input_position", "inputPosition", "", {"translation", "rotation", "scale", "origin"}},
    {"MergePoints", "position1", "", "!noUpdate", {"position2"}},
    {"SubsetTopology", "rest_position", "", "", {}},
    {"ValuesFromPositions", "position", "rest_position", "", {"direction"}},
};

/// The readers penalty follows, by type and Data: a projective constraint's `indices`, which SOFA
/// reads at each projection and matrix application (FixedProjectiveConstraint::projectResponse,
/// FixedPlaneProjectiveConstraint::projectResponse / applyConstraint,
/// PartialFixedProjectiveConstraint::projectResponseT / applyConstraint: d_indices.getValue());
/// ConstantForceField's `indices`, which its addForce reads after its component state
/// (isComponentStateValid runs the update callbacks of a changed d_indices);
/// RestShapeSpringsForceField's `points`, which its addForce reads in recomputeIndices (with
/// recompute_indices, the default).
struct IndexFollower {
    std::string_view type;
    std::string_view data;
};
constexpr IndexFollower kIndexFollowers[] = {
    {"FixedProjectiveConstraint", "indices"},
    {"FixedConstraint", "indices"},
    {"FixedPlaneProjectiveConstraint", "indices"},
    {"FixedPlaneConstraint", "indices"},
    {"PartialFixedProjectiveConstraint", "indices"},
    {"PartialFixedConstraint", "indices"},
    {"ConstantForceField", "indices"},
    {"RestShapeSpringsForceField", "points"},
};

bool same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0);  // NOLINT(bugprone-*)
}

/// True when `output` of `engine` is a list of points (`output_position`, `pointsInROI`), not
/// indices or elements.
bool is_point_output(const LiveEngine& engine, std::string_view output) {
    return engine.meshes.count(output) != 0 &&
           (output.find("osition") != std::string_view::npos || output.find("oints") != std::string_view::npos);
}

/// False when `kind`'s flag keeps the outputs of init (BaseROI's `doUpdate` 0, MergePoints'
/// `noUpdate` 1: a flag written `!name`).
bool runs_again(const LiveEngineKind& kind, const Attributes& a) {
    if (kind.update_flag.empty()) return true;
    if (kind.update_flag.front() == '!') return !a.boolean(kind.update_flag.substr(1));
    return a.boolean(kind.update_flag);
}

/// True when `c` is an engine that SOFA runs once only (BaseROI with doUpdate 0): it reads its
/// inputs at init, as penalty's build does.
bool runs_once(const io::SceneComponent& c) {
    const LiveEngineKind* kind = find_live_engine_kind(c.type);
    return kind != nullptr && !runs_again(*kind, Attributes(c));
}

/// True when `self` reads `output` of `engine` at each of its runs (its points or a followed input).
bool reads_on_each_run(const LiveEngine& self, const LiveEngine& engine, std::string_view output) {
    const auto reads = [&engine, output](const LivePoints& p) { return p.engine == &engine && p.output == output; };
    return reads(self.input()) || std::any_of(self.followed_inputs().begin(), self.followed_inputs().end(),
                                              [&reads](const FollowedInput& f) { return reads(f.source); });
}

/// True when penalty follows `data` of `c` (kIndexFollowers); RestShapeSpringsForceField without
/// recompute_indices reads its points at init only (SOFA's addForce keeps m_indices).
bool follows_indices(const io::SceneComponent& c, std::string_view data) {
    if (c.type == "RestShapeSpringsForceField" && !Attributes(c).boolean("recompute_indices")) return false;
    return std::any_of(std::begin(kIndexFollowers), std::end(kIndexFollowers),
                       [&c, data](const IndexFollower& f) { return f.type == c.type && f.data == data; });
}

/// The projective constraint or force field built from `c` in `node` whose indices can follow a
/// source, with its state, or {null, null}.
std::pair<FollowedIndices*, const BaseState*> built_index_follower(const Scene& scene, const Node& node,
                                                                   const io::SceneComponent& c) {
    const auto from = [&scene, &c](const auto& component) -> FollowedIndices* {
        auto* followed = dynamic_cast<FollowedIndices*>(component.get());
        return followed != nullptr && scene.component_of(dynamic_cast<const void*>(component.get())) == &c ? followed
                                                                                                           : nullptr;
    };
    for (const auto& k : node.constraints())
        if (FollowedIndices* f = from(k)) return {f, k->state()};
    for (const auto& ff : node.force_fields())
        if (FollowedIndices* f = from(ff)) return {f, node.state()};
    return {nullptr, nullptr};
}

}  // namespace

const LiveEngineKind* find_live_engine_kind(std::string_view type) {
    for (const LiveEngineKind& k : kLiveEngineKinds)
        if (k.type == type) return &k;
    return nullptr;
}

const std::vector<Vec3>& LivePoints::current() const {
    if (state != nullptr) return state->position;
    if (engine == nullptr) return points;
    engine->update_if_dirty();
    return engine->meshes.find(output)->second.positions;
}

const std::vector<Vec3>* LiveEngine::followed(std::string_view name) const {
    for (const FollowedInput& f : followed_)
        if (f.name == name) return &f.last;
    return nullptr;
}

bool LiveEngine::update_if_dirty() {
    // DataEngine::update reads every input (running the engines before it); it runs when one is dirty
    const std::vector<Vec3>& x = input_.current();
    bool dirty = runs_ == 0 || !same_bits(x, last_input_);
    for (const FollowedInput& f : followed_)
        if (f.runs_engine) dirty = !same_bits(f.source.current(), f.last) || dirty;
    if (!dirty) return false;
    last_input_ = x;  // the buffers' capacity stays: no allocation once it has run
    for (FollowedInput& f : followed_) f.last = f.source.current();
    evaluate_(last_input_, *this);
    ++runs_;
    return true;
}

void LiveEngines::update_linked_states() {
    for (const std::unique_ptr<LiveEngine>& engine : engines)
        for (FollowedInput& f : engine->followed_inputs())
            if (f.source.snapshot_of != nullptr) f.source.points = f.source.snapshot_of->position;
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

std::optional<LivePoints> SceneBuilder::moving_input(const Attributes& a, std::string_view attr) {
    if (!a.has(attr) || !a.is_link(attr)) return std::nullopt;
    std::vector<io::LinkTarget> targets;
    try {
        targets = io::resolve_links(a.component(), attr);
    } catch (const io::SceneError&) {
        return std::nullopt;  // the engine's own build reports it
    }
    if (targets.size() != 1 || targets[0].component == nullptr) return std::nullopt;
    const io::SceneComponent& source = *targets[0].component;
    // an engine read through the link before its turn in the file is built now (SOFA evaluates
    // engines on demand); nothing for another component or a node not built yet
    if (nodes_.count(source.node) != 0) build_data_engine(source);
    // a chain: the point output of an engine that runs on read (built first: its output was read)
    if (LiveEngine* upstream = scene_.live_->engine(source)) {
        upstream->update_if_dirty();
        if (!is_point_output(*upstream, targets[0].data)) return std::nullopt;
        return LivePoints{nullptr, upstream, targets[0].data, {}};
    }
    if (targets[0].data != "position" || source.type != "MechanicalObject") return std::nullopt;
    const auto it = nodes_.find(source.node);
    if (it == nodes_.end() || it->second.state_component != &source || it->second.node == nullptr) return std::nullopt;
    const auto* state = dynamic_cast<const Vec3Object*>(it->second.node->state());
    if (state == nullptr) return std::nullopt;
    return LivePoints{state, nullptr, {}, {}};
}

const BoxRoiWrite* SceneBuilder::box_roi_write(const io::SceneComponent& c) const {
    const auto it = scene_.live_->box_roi_writes.find(Scene::component_path(c));
    return it == scene_.live_->box_roi_writes.end() ? nullptr : &it->second;
}

namespace {

/// True when link target `t` changes while the scene runs: a MechanicalObject's Data other than its
/// rest positions (the solve and the controllers write them), or an output of a live engine.
bool changes_while_running(const io::LinkTarget& t, const LiveEngines* live) {
    if (t.component == nullptr) return false;
    if (live != nullptr && live->find(*t.component) != nullptr) return true;
    return t.component->type == "MechanicalObject" && !t.data.empty() && t.data != "rest_position" &&
           t.data != "reset_position";
}

}  // namespace

void SceneBuilder::add_live_engine(const Attributes& a, const std::vector<Vec3>& points,
                                   LiveEngine::Evaluate evaluate) {
    const io::SceneComponent& c = a.component();
    const LiveEngineKind* kind = find_live_engine_kind(c.type);
    if (kind == nullptr) throw std::logic_error(c.type + " is not in kLiveEngineKinds");
    if (!runs_again(*kind, a)) return;  // the selection of init stays
    const std::string_view attr = !a.has(kind->input) && !kind->input_alias.empty() ? kind->input_alias : kind->input;
    std::optional<LivePoints> input = moving_input(a, attr);
    std::vector<FollowedInput> followed;
    for (std::string_view name : kind->followed) {
        if (name.empty()) break;
        const bool read_on_run = name.front() == '~';  // not an input of SOFA's engine
        if (read_on_run) name.remove_prefix(1);
        if (std::optional<LivePoints> source = moving_input(a, name)) {
            if (read_on_run && source->state != nullptr)  // read as of the step's start (FollowedInput)
                source = LivePoints{nullptr, nullptr, {}, source->state->position, source->state};
            followed.push_back({std::string(name), std::move(*source), {}, !read_on_run});
        }
    }
    // SOFA's DataEngine::addInput: any input linked to data that changes runs the engine again
    for (const io::SceneAttribute& link : c.attributes) {
        const bool is_followed = std::any_of(followed.begin(), followed.end(),
                                             [&link](const FollowedInput& f) { return f.name == link.name; });
        if (!io::is_link(link.value) || link.name == attr || is_followed) continue;
        std::vector<io::LinkTarget> targets;
        try {
            targets = io::resolve_links(c, link.name);
        } catch (const io::SceneError&) {
            continue;  // the engine's own build reports it
        }
        for (const io::LinkTarget& t : targets)
            if (changes_while_running(t, scene_.live_->engines.get()))
                warn(c.file + ":" + std::to_string(link.line) + ": " + c.describe() + ": input '" + link.name +
                     "' links " + t.component->describe() + "." + t.data +
                     ", which changes while the scene runs: penalty reads it once, when the scene is built (SOFA "
                     "runs the engine again when it changes)");
    }
    if (!input && followed.empty()) return;
    if (!input) input = LivePoints{nullptr, nullptr, {}, points};
    std::unique_ptr<LiveEngines>& engines = scene_.live_->engines;
    if (!engines) engines = std::make_unique<LiveEngines>();
    LiveEngines& live = *engines;
    live.engines.push_back(
        std::make_unique<LiveEngine>(c, std::move(*input), std::move(followed), std::move(evaluate)));
    live.by_component[&c] = live.engines.back().get();
}

namespace {

/// Connects `c`'s `indices`, which link `t` of `engine`, to the engine when penalty follows that
/// reader: true when it does.
bool follow_index_reader(Scene& scene, const io::SceneComponent& c, const io::SceneAttribute& a,
                         std::size_t num_targets, LiveEngine& engine, const std::string& output) {
    const Node* node = scene.node_of(*c.node);
    if (!follows_indices(c, a.name) || num_targets != 1 || engine.indices.count(output) == 0 || node == nullptr)
        return false;
    const auto [follower, state] = built_index_follower(scene, *node, c);
    if (follower == nullptr || state == nullptr) return false;
    const std::size_t size = state->num_dofs();
    // The constraint takes the output at its first read; a FixedPlaneProjectiveConstraint with
    // dmin != dmax keeps the points between its planes that its init appended to the output of
    // init until the engine runs again (SOFA: its Data is then dirty and takes its parent's value).
    const bool appended = dynamic_cast<FixedPlaneProjectiveConstraint*>(follower) != nullptr &&
                          Attributes(c).real("dmin") != Attributes(c).real("dmax");
    const std::uint64_t seen = appended ? engine.runs() : 0;
    follower->set_index_source([reader = LiveEngineReader{&engine, output, seen}, size,
                                what = c.describe()](std::vector<Index>& indices) mutable {
        if (!reader.pull()) return;
        const std::vector<PointId>& out = reader.engine->indices.find(reader.output)->second;
        for (PointId i : out)
            if (i < 0 || std::size_t(i) >= size)
                throw std::invalid_argument(what + ": index " + std::to_string(i) + " of " +
                                            reader.engine->component().describe() + " is out of range (" +
                                            std::to_string(size) + " DOFs)");
        indices.assign(out.begin(), out.end());
    });
    return true;
}

}  // namespace

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
                engine->update_if_dirty();  // its first run (the positions after init): its outputs exist
                if (const LiveEngine* self = live.find(c); self != nullptr && reads_on_each_run(*self, *engine, t.data))
                    continue;                // a chain: the engine reads its input on each run
                if (runs_once(c)) continue;  // SOFA reads it once too
                // an engine that runs on read: its build followed the input or named it (add_live_engine)
                if (find_live_engine_kind(c.type) != nullptr) continue;
                if (follow_index_reader(scene, c, a, targets.size(), *engine, t.data)) continue;
                const Node* node = scene.node_of(*c.node);
                const bool point_output =
                    engine->meshes.count(t.data) != 0 && !engine->meshes.find(t.data)->second.positions.empty();
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
