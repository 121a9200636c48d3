// The collision pipelines of a scene, once every node is built: a CollisionPipeline gathers the
// models below its node and the first intersection method, response, broad and narrow phase
// below it (SOFA's context search); a CompositeCollisionPipeline runs its SubCollisionPipelines,
// each with the models and parts it links. One ContactPipeline per SOFA pipeline.
#include "penalty/collision/ray_trace_narrow_phase.hpp"
#include "penalty/response/collision_response.hpp"
#include "scene/builder/scene_builder.hpp"

#include <algorithm>

namespace penalty::scene {

namespace {

bool scene_has_type(const io::SceneNode& n, std::string_view type) {
    for (const auto& c : n.components)
        if (c->type == type) return true;
    for (const auto& child : n.children)
        if (scene_has_type(*child, type)) return true;
    return false;
}

using io::SceneComponent;
using io::SceneNode;
using F = ComponentFamily;

bool is_below(const SceneNode* n, const SceneNode* ancestor) {
    for (; n != nullptr; n = n->parent)
        if (n == ancestor) return true;
    return false;
}

ComponentFamily family_of(const SceneComponent& c) { return find_component(c.type)->family; }

/// "none", or the names of the fixes that are on, and the zero-distance policy when not the default.
std::string quirk_summary(const SofaQuirkFixes& q) {
    std::string out;
    for (const std::string& name : enabled_sofa_quirk_fixes(q)) out += (out.empty() ? "" : " ") + name;
    if (q.zero_distance_normal != ZeroDistanceNormal::FallbackX)
        out += (out.empty() ? "" : " ") + std::string("zeroDistanceNormal=") +
               zero_distance_normal_name(q.zero_distance_normal);
    return out.empty() ? "none" : out;
}

class PipelineAssembly {
public:
    explicit PipelineAssembly(SceneBuilder& b) : b_(b) {}

    void build() {
        for (const SceneComponent* p : b_.pipeline_components()) {
            if (family_of(*p) == F::composite_pipeline) build_composite(*p);
            else build_single(*p);
        }
        describe_pieces();
        attach_newton();
    }

private:
    /// First physics component of a family in the subtree of `n` (its own components first).
    const SceneComponent* first_below(const SceneNode& n, ComponentFamily family) const {
        for (const auto& c : n.components)
            if (family_of(*c) == family && !b_.is_ignored(c.get())) return c.get();
        for (const auto& child : n.children)
            if (const SceneComponent* c = first_below(*child, family)) return c;
        return nullptr;
    }

    void build_single(const SceneComponent& p) {
        const SceneComponent* inter = first_below(*p.node, F::intersection);
        const SceneComponent* resp = first_below(*p.node, F::contact_manager);
        const SceneComponent* broad = first_below(*p.node, F::broad_phase);
        const SceneComponent* narrow = first_below(*p.node, F::narrow_phase);
        if (!inter || !resp || !broad || !narrow) {
            b_.role(p, [] { return "incomplete: no contact will be detected (see the notes)"; });
            b_.warn(p.file + ":" + std::to_string(p.line) + ": " + p.describe() +
                    ": no contact will be detected: SOFA needs an intersection method, a CollisionResponse, "
                    "a BruteForceBroadPhase and a BVHNarrowPhase below the pipeline's node");
            return;
        }
        std::vector<const SceneCollisionModel*> models;
        for (const auto& m : b_.collision_models())
            if (is_below(m.component->node, p.node)) models.push_back(&m);
        b_.mark_used(broad);
        b_.mark_used(narrow);
        add(p, p.name.empty() ? p.type : p.name, *inter, *resp, *narrow, models, b_.node_of(*p.node));
    }

    void build_composite(const SceneComponent& p) {
        const Attributes pa(p);
        std::string subs;
        for (const io::LinkTarget& t : pa.links("subCollisionPipelines")) {
            if (t.component == nullptr || family_of(*t.component) != F::sub_pipeline)
                pa.fail("subCollisionPipelines", "must link to SubCollisionPipeline components");
            const SceneComponent& sub = *t.component;
            const Attributes sa(sub);
            auto linked = [&](const char* attr, ComponentFamily family) {
                const io::LinkTarget l = sa.link(attr);
                if (l.component == nullptr || family_of(*l.component) != family)
                    sa.fail(attr, "links to the wrong kind of component");
                return l.component;
            };
            const SceneComponent* inter = linked("intersectionMethod", F::intersection);
            const SceneComponent* resp = linked("contactManager", F::contact_manager);
            b_.mark_used(linked("broadPhaseDetection", F::broad_phase));
            const SceneComponent* narrow = linked("narrowPhaseDetection", F::narrow_phase);
            b_.mark_used(narrow);
            std::vector<const SceneCollisionModel*> models;
            for (const io::LinkTarget& m : sa.links("collisionModels")) {
                const auto& all = b_.collision_models();
                const auto it = std::find_if(all.begin(), all.end(),
                                             [&](const SceneCollisionModel& x) { return x.component == m.component; });
                if (it == all.end()) sa.fail("collisionModels", "links to something that is not a collision model");
                models.push_back(&*it);
            }
            add(sub, sub.name.empty() ? sub.type : sub.name, *inter, *resp, *narrow, models, b_.node_of(*sub.node));
            subs += (subs.empty() ? "" : ", ") + (sub.name.empty() ? sub.type : sub.name);
        }
        b_.role(p, [subs] { return "composite: runs the sub-pipelines " + subs + " each step"; });
    }

    /// The response; the friction spring's time step defaults to the scene's dt (responseParams
    /// `timeStep` overrides it).
    CollisionResponse response_of(const SceneComponent& c, double dt) {
        const Attributes a(c);
        return b_.guarded(c, [&] {
            ContactResponseParameters base;
            base.penalty.time_step = dt;
            return CollisionResponse(a.text("response"), a.text("responseParams"), base);
        });
    }

    /// SOFA's RayTraceNarrowPhase: the TriangleOctreeCollisionModels among `models` are its surfaces.
    static std::shared_ptr<RayTraceNarrowPhase> ray_trace_of(const std::vector<const SceneCollisionModel*>& models) {
        auto narrow = std::make_shared<RayTraceNarrowPhase>();
        for (const SceneCollisionModel* m : models)
            if (m->component->type == "TriangleOctreeCollisionModel")
                narrow->add_surface(dynamic_cast<TriangleModel&>(*m->model));
        return narrow;
    }

    void add(const SceneComponent& pipeline_component, const std::string& name, const SceneComponent& intersection,
             const SceneComponent& response, const SceneComponent& narrow,
             const std::vector<const SceneCollisionModel*>& models, Node& host) {
        Simulation& sim = b_.simulation();
        ScenePipeline sp;
        sp.name = name;
        const IntersectionParams& params = b_.intersection_params(intersection);
        sp.intersection = params.method;
        ContactPipelineOptions options;
        options.detection = b_.options().exhaustive_detection ? ContactDetection::exhaustive : ContactDetection::bvh;
        options.threads = b_.options().threads;
        // run by the scene's contact stage (Scene::ContactPhase), in the order they are made
        // here, scene order (SOFA's composite pipeline), between SOFA's collision events
        options.register_stage = false;
        // a CarvingManager reads every detection output (SOFA's narrow-phase map)
        options.all_detection_outputs = scene_has_type(*b_.scene().file().root, "CarvingManager");
        options.sofa_stable_id_order = b_.options().sofa_head_orders;
        // SOFA's bounding-tree depth (CollisionPipeline / SubCollisionPipeline `depth`): the
        // order of the contacts; CollisionPipeline::init resets a negative depth to 6
        const std::int64_t depth =
            b_.guarded(pipeline_component, [&] { return Attributes(pipeline_component).integer("depth"); });
        options.bvh.depth = depth < 0 || depth > 64 ? 6 : int(depth);
        if (narrow.type == "RayTraceNarrowPhase") {
            options.bvh.narrow_phase_override = ray_trace_of(models);
        } else {
            for (const SceneCollisionModel* m : models)
                if (m->component->type == "TriangleOctreeCollisionModel")
                    b_.warn(m->component->file + ":" + std::to_string(m->component->line) + ": " +
                            m->component->describe() + ": under " + narrow.type +
                            " penalty detects all its triangles, as a TriangleCollisionModel; "
                            "SOFA's single-cube tree for it reaches triangle 0 only (use RayTraceNarrowPhase)");
        }
        const double dt = b_.options().dt ? *b_.options().dt : sim.root().dt();
        sp.pipeline = std::make_unique<ContactPipeline>(sim, params, response_of(response, dt), &host, options);
        // the rank in scene order stands for the model's address in SOFA's contact map
        const auto& all = b_.collision_models();
        for (const SceneCollisionModel* m : models)
            sp.pipeline->add_model(*m->model, *m->node, std::size_t(m - all.data()));
        sp.models = models;
        std::string summary = intersection_method_short_name(sp.intersection);
        if (sp.intersection != IntersectionMethod::Discrete)
            summary += " (alarm " + num(params.alarm_distance) + " m, contact " + num(params.contact_distance) + " m)";
        summary +=
            ", " + counted(models.size(), "collision model", "collision models") + ", response " +
            (sp.pipeline->response().base_response_name().empty() ? std::string("none")
                                                                  : sp.pipeline->response().base_response_name());
        b_.role(pipeline_component, [summary] { return "collision pipeline: " + summary; });
        b_.mark_used(&intersection);
        b_.mark_used(&response);
        b_.pipelines().push_back(std::move(sp));
    }

    /// Beyond SOFA: a solver with newton="1" re-runs the contact geometry of every pipeline at
    /// each iterate. The scene owns the solver's hook (Scene::~Scene clears it before the
    /// pipelines go); each pipeline only keeps its pre-step state.
    void attach_newton() {
        if (b_.newton_solvers().empty()) return;
        std::vector<ContactPipeline*> all;
        for (ScenePipeline& p : b_.pipelines()) {
            p.pipeline->keep_step_start();
            all.push_back(p.pipeline.get());
        }
        for (auto [solver, solver_node] : b_.newton_solvers()) {
            const Node* subtree = solver_node;
            solver->newton.update_geometry = [all, subtree] {
                for (ContactPipeline* p : all) p->update_geometry(*subtree);
            };
        }
    }

    /// Roles of the animation loop, intersection methods, responses, broad and narrow phases.
    void describe_pieces() {
        for (const SceneComponent* c : b_.check().physics) {
            const ComponentFamily family = family_of(*c);
            const bool piece = family == F::intersection || family == F::contact_manager || family == F::broad_phase ||
                               family == F::narrow_phase;
            std::string d;
            if (family == F::animation_loop) {
                d = "each step: collision with the positions of the previous step's end, then the solvers";
            } else if (piece && !b_.is_used(c)) {
                d = "not used by any collision pipeline";
            } else if (family == F::intersection) {
                const IntersectionParams& p = b_.intersection_params(*c);
                d = c->type == "DiscreteIntersection" ? "contact only where elements overlap"
                                                      : "alarm distance " + num(p.alarm_distance) +
                                                            " m, contact distance " + num(p.contact_distance) + " m";
                if (p.enable_beyond_sofa_pairs) d += ", beyond-SOFA pairs on";
                d += ", SOFA quirk fixes: " + quirk_summary(p.quirks);
            } else if (family == F::contact_manager) {
                const Attributes a(*c);
                const std::string r = a.text("response");
                const std::string params = a.text("responseParams");
                d = "response " + (r.empty() ? std::string("none: no contact is created") : r) +
                    (params.empty() ? "" : ", parameters " + params);
            } else if (family == F::broad_phase) {
                d = "model pairs kept by SOFA's rules (active, not both non-simulated, self-collision, groups)";
            } else if (c->type == "RayTraceNarrowPhase") {
                d = "rays from each TriangleOctreeCollisionModel vertex along minus its normal, against the other "
                    "surface's octree (SOFA's RayTraceNarrowPhase); other models get no contact";
            } else if (family == F::narrow_phase) {
                d = b_.options().exhaustive_detection
                        ? "element pairs by SOFA's exhaustive loop (--exhaustive)"
                        : "element pairs from one BVH per model (the same outputs as SOFA's loop)";
            } else {
                continue;
            }
            b_.role(*c, [d] { return d; });
        }
    }

    SceneBuilder& b_;
};

}  // namespace

void build_collision_pipelines(SceneBuilder& builder) { PipelineAssembly(builder).build(); }

}  // namespace penalty::scene
