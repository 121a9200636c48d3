// `penalty info`: what a built scene is made of, component by component, and which model pairs
// can make contacts, with where each contact goes (spec §2.1).
#include "penalty/response/collision_response.hpp"
#include "penalty/scene/components.hpp"
#include "penalty/scene/scene.hpp"
#include "scene/display.hpp"

#include <map>
#include <set>
#include <sstream>

namespace penalty::scene {

namespace {

using display::node_path;

/// The node whose solver integrates `n`: the first node from the root owning an ODE solver.
const Node* integrating_node(const Node& n) {
    const Node* found = nullptr;
    for (const Node* x = &n; x != nullptr; x = x->parent())
        if (x->ode_solver() != nullptr) found = x;
    return found;
}

std::string ignored_reason(const io::SceneComponent& c) {
    const ComponentSpec* spec = find_component(c.type);
    if (spec != nullptr && category_of(spec->family) == ComponentCategory::ignored)
        return "ignored (" + std::string(spec->summary) + ")";
    if (spec != nullptr && category_of(spec->family) == ComponentCategory::loader)
        return "ignored (loader no physics component uses)";
    return "ignored (maps onto a visual model)";
}

void describe_node(const Scene& scene, const io::SceneNode& sn, int depth,
                   const std::set<const io::SceneComponent*>& ignored, std::ostringstream& out) {
    const std::string indent(std::size_t(2 * depth), ' ');
    out << indent << "Node " << (sn.parent ? sn.path() : std::string("/ (") + sn.name + ")");
    // dt and gravity where they are set (the root always), inherited below
    const Node* n = scene.node_of(sn);
    const Node* parent = n ? n->parent() : nullptr;
    if (n && (parent == nullptr || parent->dt() != n->dt())) out << ": dt " << display::number(n->dt()) << " s";
    if (n && (parent == nullptr || parent->gravity() != n->gravity())) {
        const Vec3 g = n->gravity();
        out << (parent && parent->dt() == n->dt() ? ": " : ", ") << "gravity (" << display::number(g.x()) << ", "
            << display::number(g.y()) << ", " << display::number(g.z()) << ") m/s^2";
    }
    out << "\n";
    const auto print = [&](const std::string& label, const std::string& what) {
        const std::size_t width = 46, used = indent.size() + 2 + label.size();
        out << indent << "  " << label << std::string(used + 1 < width ? width - used : 1, ' ') << what << "\n";
    };
    for (std::size_t i = 0; i < sn.components.size(); ++i) {
        const io::SceneComponent& c = *sn.components[i];
        std::string what;
        if (ignored.count(&c)) {
            what = ignored_reason(c);
            // A run of ignored components of one type (a scene's 15 RequiredPlugins) is one line.
            std::size_t run = 1;
            while (i + run < sn.components.size() && sn.components[i + run]->type == c.type &&
                   ignored.count(sn.components[i + run].get()) && ignored_reason(*sn.components[i + run]) == what)
                ++run;
            if (run > 1) {
                print(c.type + " \u00d7" + std::to_string(run), what);
                i += run - 1;
                continue;
            }
        } else {
            what = scene.role(c);
            if (what.empty()) what = "built";
            const std::vector<std::string> unread = unread_attributes(c);
            if (!unread.empty()) {
                what += "; not read:";
                for (const auto& a : unread) what += " " + a;
            }
        }
        std::string label = c.type;
        if (!c.template_name.empty()) label += "<" + c.template_name + ">";
        if (!c.name.empty()) label += " '" + c.name + "'";
        print(label, what);
    }
    for (const auto& child : sn.children) describe_node(scene, *child, depth + 1, ignored, out);
}

std::string support_text(PairSupport s, const IntersectionParams& p, const std::string& method) {
    switch (s) {
        case PairSupport::Supported:
            return "";
        case PairSupport::Ignored:
            return "not detected: " + method + " ignores this pair (SOFA registers it so, or a use* switch is off)";
        case PairSupport::Unsupported:
            return "not detected: " + method + " has no intersector for this pair (as SOFA)";
        case PairSupport::BeyondSofa:
            return p.enable_beyond_sofa_pairs
                       ? ""
                       : "not detected: beyond-SOFA pair, off (beyondSofaPairs=\"1\" on the intersection turns it on)";
    }
    return "";
}

std::string model_label(const SceneCollisionModel& m) {
    return m.model->name() + " (" + model_type_name(m.model->type()) + ", " + node_path(*m.node) + ")";
}

/// Why SOFA's broad phase drops the pair (keep_model_pair is false).
std::string exclusion_reason(const CollisionModel& a, const CollisionModel& b) {
    if (!a.params().active || !b.params().active) return "an inactive model";
    if (!a.params().simulated && !b.params().simulated) return "both non-simulated";
    if (&a == &b || same_node(a, b)) return "same node without selfCollision";
    return "a shared collision group";
}

void describe_pipeline(const ScenePipeline& sp, std::size_t pair_lines, std::ostringstream& out) {
    const ContactPipeline& pipeline = *sp.pipeline;
    const IntersectionParams& params = pipeline.intersection();
    const std::string method = intersection_method_short_name(sp.intersection);
    out << "contact pairs of collision pipeline '" << sp.name << "' (" << method;
    if (sp.intersection != IntersectionMethod::Discrete)
        out << ", alarm " << display::number(params.alarm_distance) << " m, contact "
            << display::number(params.contact_distance) << " m";
    const std::string base = pipeline.response().base_response_name();
    out << ", response " << (base.empty() ? std::string("none") : base) << "):\n";
    std::map<std::string, int> excluded;
    // the pairs past the first pair_lines, counted by types and outcome
    std::map<std::string, std::size_t> more;
    std::size_t kept = 0, contacting = 0;
    for (std::size_t i = 0; i < sp.models.size(); ++i) {
        for (std::size_t j = i; j < sp.models.size(); ++j) {
            const SceneCollisionModel* a = sp.models[i];
            const SceneCollisionModel* b = sp.models[j];
            if (!keep_model_pair(*a->model, *b->model)) {
                ++excluded[exclusion_reason(*a->model, *b->model)];
                continue;
            }
            ++kept;
            if (!is_registered_order(a->model->type(), b->model->type())) std::swap(a, b);
            std::string what = support_text(pair_support(params, a->model->type(), b->model->type()), params, method);
            std::string kind;  // what, without the nodes
            if (what.empty()) {
                const std::string name = pipeline.response().response_name(*a->model, *b->model);
                const std::string key = name.substr(0, name.find('?'));
                if (key.empty() || key == "nullptr") {
                    what = "detected; no response (" + (key.empty() ? std::string("none set") : key) + "): no contact";
                } else if (!is_penalty_response_pair(a->model->type(), b->model->type())) {
                    what = "detected; the penalty response has no contact for this pair (as SOFA)";
                } else {
                    ++contacting;
                    const Node* host = pipeline.host_node(*a->model, *b->model);
                    const Node* solver = integrating_node(*host);
                    what = "penalty contact in " + node_path(*host) + ", " +
                           (solver ? "implicit (solver of " + node_path(*solver) + ")"
                                   : std::string("explicit (no solver above it: forces from the start of the step)"));
                    kind = solver ? "penalty contact, implicit" : "penalty contact, explicit";
                    if (name != kPenaltyResponseName) {
                        what += ", response " + name;
                        kind += ", response " + name;
                    }
                }
            }
            if (kept > pair_lines) {
                ++more[std::string(model_type_name(a->model->type())) + " - " + model_type_name(b->model->type()) +
                       ": " + (kind.empty() ? what : kind)];
                continue;
            }
            out << "  " << model_label(*a) << " - " << model_label(*b) << ": " << what << "\n";
        }
    }
    if (!more.empty()) {
        out << "  ... and " << kept - pair_lines << " more model pairs (`penalty info --all-pairs` lists each):\n";
        for (const auto& [what, n] : more) out << "    " << n << " \u00d7 " << what << "\n";
    }
    out << "  " << kept << " model pair" << (kept == 1 ? "" : "s") << " kept by the broad phase, " << contacting
        << " can make penalty contacts";
    for (const auto& [reason, n] : excluded) out << "; " << n << " excluded (" << reason << ")";
    out << "\n";
}

}  // namespace

std::string describe_scene(const Scene& scene, std::size_t pair_lines) {
    const io::SceneFile& file = scene.file();
    const SceneCheck check = validate(file);
    std::ostringstream out;
    out << "scene: " << file.path.string() << "\n";
    const std::set<const io::SceneComponent*> ignored(check.ignored.begin(), check.ignored.end());
    if (file.root) describe_node(scene, *file.root, 0, ignored, out);
    out << check.physics.size() << " physics components, " << check.loaders.size() << " loaders, "
        << check.ignored.size() << " ignored\n";
    for (const ScenePipeline& sp : scene.pipelines()) describe_pipeline(sp, pair_lines, out);
    if (scene.pipelines().empty()) out << "no collision pipeline: no contact\n";
    for (const std::string& w : scene.warnings())
        if (w != check.summary) out << "note: " << w << "\n";
    return out.str();
}

}  // namespace penalty::scene
