#include "penalty/scene/viewer.hpp"

#include "penalty/collision/models.hpp"
#include "penalty/mechanics/mechanical_object.hpp"

#include <algorithm>
#include <map>
#include <stdexcept>

namespace penalty::scene {

namespace {

/// Index of the record whose state is `state` in `states`, appending it on first use.
template <class State>
std::size_t state_index(const Scene& scene, const State& state, const CollisionModel& model,
                        std::vector<const output::StateRecord*>& states) {
    for (std::size_t k = 0; k < states.size(); ++k)
        if (dynamic_cast<const State*>(states[k]->state) == &state) return k;
    for (const output::StateRecord& r : scene.states()) {
        if (dynamic_cast<const State*>(r.state) == &state) {
            states.push_back(&r);
            return states.size() - 1;
        }
    }
    throw std::invalid_argument("viewer: the state of collision model '" + model.name() +
                                "' is not a state of the scene");
}

std::uint32_t index32(Index i) { return static_cast<std::uint32_t>(i); }

}  // namespace

ViewerBodies viewer_bodies(const Scene& scene) {
    ViewerBodies out;
    for (const SceneCollisionModel& entry : scene.collision_models()) {
        const CollisionModel& model = *entry.model;
        output::ViewerShape shape;
        shape.name = model.name();
        shape.type = model_type_name(model.type());
        auto every_dof = [&](std::size_t n) {
            for (std::size_t i = 0; i < n; ++i) shape.indices.push_back(std::uint32_t(i));
        };
        if (const auto* t = dynamic_cast<const TriangleModel*>(&model)) {
            shape.kind = output::ViewerShapeKind::triangles;
            shape.state = state_index(scene, t->state(), model, out.states);
            for (std::size_t i = 0; i < t->size(); ++i)
                for (const auto v : t->triangle(Index(i))) shape.indices.push_back(index32(v));
        } else if (const auto* l = dynamic_cast<const LineModel*>(&model)) {
            shape.kind = output::ViewerShapeKind::lines;
            shape.state = state_index(scene, l->state(), model, out.states);
            for (std::size_t i = 0; i < l->size(); ++i)
                for (const auto v : l->edge(Index(i))) shape.indices.push_back(index32(v));
        } else if (const auto* p = dynamic_cast<const PointModel*>(&model)) {
            shape.kind = output::ViewerShapeKind::points;
            shape.state = state_index(scene, p->state(), model, out.states);
            every_dof(p->size());
        } else if (const auto* s = dynamic_cast<const SphereModel*>(&model)) {
            shape.kind = output::ViewerShapeKind::spheres;
            shape.state = state_index(scene, s->state(), model, out.states);
            every_dof(s->size());
            for (std::size_t i = 0; i < s->size(); ++i) shape.radius.push_back(s->radius(Index(i)));
        } else if (const auto* r = dynamic_cast<const RigidSphereModel*>(&model)) {
            shape.kind = output::ViewerShapeKind::spheres;
            shape.state = state_index(scene, r->state(), model, out.states);
            every_dof(r->size());
            for (std::size_t i = 0; i < r->size(); ++i) shape.radius.push_back(r->radius(Index(i)));
        } else if (const auto* c = dynamic_cast<const CylinderModel*>(&model)) {
            shape.kind = output::ViewerShapeKind::cylinders;
            shape.state = state_index(scene, c->state(), model, out.states);
            every_dof(c->size());
            for (std::size_t i = 0; i < c->size(); ++i) {
                shape.radius.push_back(c->radius(Index(i)));
                shape.height.push_back(c->height(Index(i)));
                shape.axis.push_back(c->local_axis(Index(i)));
            }
        } else if (const auto* tet = dynamic_cast<const TetrahedronModel*>(&model)) {
            shape.kind = output::ViewerShapeKind::triangles;
            shape.state = state_index(scene, tet->state(), model, out.states);
            // Boundary faces: a face shared by two tetrahedra is inside. Faces are keyed by their
            // sorted vertices; each face keeps the orientation of its first tetrahedron, outward
            // for a positively oriented tetrahedron (faces opposite each vertex, SOFA's order).
            std::map<std::array<Index, 3>, std::pair<std::array<Index, 3>, int>> faces;
            for (std::size_t i = 0; i < tet->size(); ++i) {
                const auto& v = tet->tetrahedron(Index(i));
                const std::array<std::array<Index, 3>, 4> local{
                    {{v[1], v[2], v[3]}, {v[0], v[3], v[2]}, {v[0], v[1], v[3]}, {v[0], v[2], v[1]}}};
                for (const auto& f : local) {
                    auto key = f;
                    std::sort(key.begin(), key.end());
                    auto [it, inserted] = faces.try_emplace(key, f, 0);
                    ++it->second.second;
                }
            }
            for (const auto& [key, face] : faces)
                if (face.second == 1)
                    for (const Index v : face.first) shape.indices.push_back(index32(v));
        } else {
            continue;
        }
        out.shapes.push_back(std::move(shape));
    }
    if (out.shapes.empty()) {
        // No collision model at all: show the Vec3 states as points, so the run is not an empty view.
        for (const output::StateRecord& r : scene.states()) {
            const auto* v = dynamic_cast<const Vec3Object*>(r.state);
            if (v == nullptr) continue;
            output::ViewerShape shape;
            shape.name = r.name;
            shape.type = "state";
            shape.kind = output::ViewerShapeKind::points;
            shape.state = out.states.size();
            for (std::size_t i = 0; i < v->position.size(); ++i) shape.indices.push_back(std::uint32_t(i));
            out.states.push_back(&r);
            out.shapes.push_back(std::move(shape));
        }
    }
    return out;
}

std::unique_ptr<output::ViewerWriter> open_viewer(const Scene& scene, const std::filesystem::path& directory,
                                                  std::string title) {
    ViewerBodies bodies = viewer_bodies(scene);
    auto writer =
        std::make_unique<output::ViewerWriter>(directory, bodies.states, std::move(bodies.shapes), std::move(title));
    if (!scene.dynamic_topologies().empty()) {
        // Topological changes: the shapes of the frames after a change (same states, in the same order).
        writer->follow_topology(
            [&scene] { return scene.topology_revision(); },
            [&scene, states = std::move(bodies.states)] {
                ViewerBodies now = viewer_bodies(scene);
                if (now.states != states)
                    throw std::invalid_argument("viewer: a topological change changed the drawn states");
                return std::move(now.shapes);
            });
    }
    return writer;
}

}  // namespace penalty::scene
