// `penalty info --contact-advice` (contact_advice.hpp, docs/no-tunnelling.md "Advice").
#include "penalty/scene/contact_advice.hpp"

#include "penalty/collision/models.hpp"
#include "penalty/mechanics/mechanical_object.hpp"
#include "penalty/response/barycentric_penalty_contact.hpp"
#include "penalty/simulation/ode_solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace penalty::scene {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

bool has_vertices(ModelType t) { return t == ModelType::Point || t == ModelType::Line || t == ModelType::Triangle; }
bool has_spheres(ModelType t) { return t == ModelType::Sphere || t == ModelType::RigidSphere; }

/// Whether the guard tests any feature of the pair (ccd_detection.hpp's rules).
bool can_tunnel(ModelType a, ModelType b) {
    const auto one_way = [](ModelType x, ModelType y) {
        return ((has_vertices(x) || has_spheres(x)) && (y == ModelType::Triangle || has_spheres(y))) ||
               ((x == ModelType::Line || x == ModelType::Triangle) &&
                (y == ModelType::Line || y == ModelType::Triangle));
    };
    return one_way(a, b) || one_way(b, a);
}

/// The smallest sphere radius of a model (0 for a model without spheres).
double smallest_radius(const CollisionModel& m) {
    double r = kInf;
    if (m.type() == ModelType::Sphere) {
        const auto& s = static_cast<const SphereModel&>(m);
        for (std::size_t i = 0; i < s.size(); ++i) r = std::min(r, s.radius(Index(i)));
    } else if (m.type() == ModelType::RigidSphere) {
        const auto& s = static_cast<const RigidSphereModel&>(m);
        for (std::size_t i = 0; i < s.size(); ++i) r = std::min(r, s.radius(Index(i)));
    }
    return std::isfinite(r) ? r : 0.0;
}

struct Side {
    double mass = kInf;            ///< per contact point (kg); +inf: does not move
    const Node* solver = nullptr;  ///< the node of its ODE solver
    const EulerImplicitSolver* implicit = nullptr;
};

/// The mass a contact point of model `m` carries: its body's mass (the nearest node at or above
/// the model's node with a mass) over the DOFs of the model's state; +inf for a state no solver moves.
Side side_of(const Scene& scene, const CollisionModel& m) {
    Side s;
    const SceneCollisionModel* entry = nullptr;
    for (const SceneCollisionModel& c : scene.collision_models())
        if (c.model.get() == &m) entry = &c;
    if (entry == nullptr || entry->node == nullptr) return s;
    const output::StateRecord* record = nullptr;
    for (const output::StateRecord& r : scene.states())
        if (r.state == entry->node->state()) record = &r;
    if (record == nullptr || !(record->in_solver_subtree || record->mapped) || !m.params().simulated) return s;
    for (const Node* n = entry->node; n != nullptr; n = n->parent()) {
        if (n->ode_solver() != nullptr && s.solver == nullptr) {
            s.solver = n;
            s.implicit = dynamic_cast<const EulerImplicitSolver*>(n->ode_solver());
        }
        if (n->mass() != nullptr && !std::isfinite(s.mass)) {
            const std::size_t points =
                std::max<std::size_t>(1, entry->node->state() ? entry->node->state()->num_dofs() : 1);
            s.mass = n->mass()->total_mass() / double(points);
        }
    }
    return s;
}

std::string three_digits(double x) {
    char buf[32];
    if (std::isinf(x)) return "inf";
    std::snprintf(buf, sizeof buf, "%.3g", x);
    return buf;
}

}  // namespace

bool PairAdvice::safe() const {
    return dt <= max_dt_detection && ks >= min_ks_energy && ks >= min_ks_implicit &&
           (!explicit_contact || dt <= max_dt_explicit) && (cg_limit == 0 || cg_iterations <= cg_limit);
}

double estimated_impact_speed(const Scene& scene) {
    const Vec3 g = const_cast<Scene&>(scene).simulation().root().gravity();
    const double gn = g.norm();
    const Vec3 down = gn > 0 ? Vec3(g / gn) : Vec3::Zero();
    double lo = kInf, hi = -kInf, v0 = 0.0;
    for (const output::StateRecord& r : scene.states()) {
        if (const auto* v = dynamic_cast<const Vec3Object*>(r.state)) {
            for (const Vec3& x : v->position) {
                lo = std::min(lo, x.dot(down));
                hi = std::max(hi, x.dot(down));
            }
            if (r.in_solver_subtree)
                for (const Vec3& u : v->velocity) v0 = std::max(v0, u.norm());
        } else if (const auto* q = dynamic_cast<const Rigid3Object*>(r.state)) {
            for (const RigidFrame& x : q->position) {
                lo = std::min(lo, x.center.dot(down));
                hi = std::max(hi, x.center.dot(down));
            }
            if (r.in_solver_subtree)
                for (const RigidDeriv& u : q->velocity) v0 = std::max(v0, u.linear.norm());
        }
    }
    const double height = hi > lo ? hi - lo : 0.0;
    return v0 + std::sqrt(2.0 * gn * height);
}

std::vector<PairAdvice> contact_advice_pairs(const Scene& scene, std::optional<double> impact_speed) {
    std::vector<PairAdvice> out;
    const double v = impact_speed ? *impact_speed : estimated_impact_speed(scene);
    const double dt = scene.dt();
    for (const ScenePipeline& p : scene.pipelines()) {
        const IntersectionParams& params = p.pipeline->intersection();
        std::vector<ModelPair> pairs;
        broad_phase(params, p.pipeline->collision().models(), pairs);
        for (const ModelPair& mp : pairs) {
            const CollisionModel& m1 = *mp.model1;
            const CollisionModel& m2 = *mp.model2;
            if (!can_tunnel(m1.type(), m2.type())) continue;
            const Side s1 = side_of(scene, m1), s2 = side_of(scene, m2);
            if (!std::isfinite(s1.mass) && !std::isfinite(s2.mass)) continue;  // nothing moves
            PairAdvice a;
            a.model1 = m1.name();
            a.model2 = m2.name();
            a.impact_speed = v;
            a.dt = dt;
            a.mass = !std::isfinite(s1.mass)   ? s2.mass
                     : !std::isfinite(s2.mass) ? s1.mass
                                               : s1.mass * s2.mass / (s1.mass + s2.mass);
            const double skins = m1.params().contact_distance + m2.params().contact_distance;
            const double r1 = smallest_radius(m1), r2 = smallest_radius(m2);
            // the far side: a centre through a triangle (reach + r), into the other sphere (+ min r)
            const double radii = has_spheres(m1.type()) && has_spheres(m2.type()) ? std::min(r1, r2) : r1 + r2;
            a.reach = params.contact_distance + skins + radii;
            a.alarm = params.alarm_distance + skins + radii;
            const double spring_dist = params.contact_distance + skins + r1 + r2;
            a.ks =
                combined_contact_stiffness(p.pipeline->response().base_parameters().stiffness_law,
                                           m1.params().contact_stiffness, m2.params().contact_stiffness, spring_dist);
            a.max_dt_detection = v > 0 ? a.alarm / v : kInf;
            a.min_ks_energy = a.reach > 0 ? a.mass * v * v / (a.reach * a.reach) : kInf;
            a.min_ks_implicit =
                v * dt > a.reach ? (a.reach > 0 ? a.mass * (v * dt - a.reach) / (dt * dt * a.reach) : kInf) : 0.0;
            // §2.1: the field goes to the moving side's node, or to the pipeline's when both move
            const Node* host = p.pipeline->host_node(m1, m2);
            const EulerImplicitSolver* implicit = nullptr;
            bool solved = false;
            for (const Node* n = host; n != nullptr && !solved; n = n->parent())
                if (n->ode_solver() != nullptr) {
                    solved = true;
                    implicit = dynamic_cast<const EulerImplicitSolver*>(n->ode_solver());
                }
            a.explicit_contact = !solved || implicit == nullptr;
            a.max_dt_explicit = a.ks > 0 && std::isfinite(a.mass) ? 2.0 * std::sqrt(a.mass / a.ks) : kInf;
            if (!a.explicit_contact) {
                const double tol = std::max(implicit->cg.tolerance, 1e-300);
                a.cg_iterations = std::sqrt(1.0 + dt * dt * a.ks / a.mass) * std::log(2.0 / tol);
                a.cg_limit = implicit->cg.iterations;
            }
            out.push_back(a);
        }
    }
    return out;
}

namespace {

double largest_dt(const PairAdvice& a) {
    return a.explicit_contact ? std::min(a.max_dt_detection, a.max_dt_explicit) : a.max_dt_detection;
}
double smallest_ks(const PairAdvice& a) { return std::max(a.min_ks_energy, a.min_ks_implicit); }

void describe_pair(std::ostringstream& o, const PairAdvice& a) {
    o << "pair " << a.model1 << " - " << a.model2 << ": mass per contact point m = " << three_digits(a.mass)
      << " kg, reach D = " << three_digits(a.reach) << " m, first seen at A = " << three_digits(a.alarm)
      << " m, spring ks = " << three_digits(a.ks) << " N/m\n";
    o << "  detection: dt <= A/v = " << three_digits(a.max_dt_detection) << " s"
      << (a.dt <= a.max_dt_detection ? "" : "  (EXCEEDED)") << "\n";
    o << "  energy: ks >= m v^2/D^2 = " << three_digits(a.min_ks_energy) << " N/m"
      << (a.ks >= a.min_ks_energy ? "" : "  (NOT MET)") << "\n";
    if (a.min_ks_implicit > 0)
        o << "  implicit step: ks >= m (v dt - D)/(dt^2 D) = " << three_digits(a.min_ks_implicit) << " N/m"
          << (a.ks >= a.min_ks_implicit ? "" : "  (NOT MET)") << "\n";
    if (a.explicit_contact) {
        o << "  solve: explicit contact (stored above the sides' solvers, spec 2.1): stable for dt <= 2 sqrt(m/ks) = "
          << three_digits(a.max_dt_explicit) << " s" << (a.dt <= a.max_dt_explicit ? "" : "  (EXCEEDED)") << "\n";
    } else {
        o << "  solve: implicit Euler (A-stable for any ks); CG needs about sqrt(1 + dt^2 ks/m) ln(2/tol) = "
          << three_digits(a.cg_iterations) << " iterations of its limit " << a.cg_limit
          << (a.cg_iterations <= a.cg_limit ? "" : "  (the solve will stop on its limit: raise iterations)") << "\n";
    }
    o << "  => largest dt " << three_digits(largest_dt(a)) << " s, smallest ks " << three_digits(smallest_ks(a))
      << " N/m\n";
}

}  // namespace

std::string contact_advice(const Scene& scene, std::optional<double> impact_speed) {
    constexpr std::size_t kMostPairsShown = 12;
    std::ostringstream o;
    const std::vector<PairAdvice> pairs = contact_advice_pairs(scene, impact_speed);
    const double v = impact_speed ? *impact_speed : estimated_impact_speed(scene);
    o << "contact advice (docs/no-tunnelling.md, \"Advice\"): dt = " << three_digits(scene.dt())
      << " s, impact speed v = " << three_digits(v) << " m/s"
      << (impact_speed ? " (--impact-speed)"
                       : " (initial speed + sqrt(2 g H), H the scene's height; --impact-speed V to set it)")
      << "\n";
    if (pairs.empty()) {
        o << "no model pair can tunnel (no moving model paired with a triangle, edge or sphere model)\n";
        return o.str();
    }
    // the scene's limits: the smallest largest-dt and the largest smallest-ks over its pairs
    const auto by_dt = std::min_element(pairs.begin(), pairs.end(),
                                        [](const auto& x, const auto& y) { return largest_dt(x) < largest_dt(y); });
    const auto by_ks = std::max_element(pairs.begin(), pairs.end(),
                                        [](const auto& x, const auto& y) { return smallest_ks(x) < smallest_ks(y); });
    const std::size_t unsafe =
        std::size_t(std::count_if(pairs.begin(), pairs.end(), [](const PairAdvice& a) { return !a.safe(); }));
    o << "scene: largest dt " << three_digits(largest_dt(*by_dt)) << " s (pair " << by_dt->model1 << " - "
      << by_dt->model2 << "), smallest contact stiffness ks " << three_digits(smallest_ks(*by_ks)) << " N/m (pair "
      << by_ks->model1 << " - " << by_ks->model2 << "); " << unsafe << " of " << pairs.size()
      << " model pairs may tunnel at the scene's dt and ks\n";
    // the pairs, the unsafe ones first, the most demanding first
    std::vector<const PairAdvice*> order;
    order.reserve(pairs.size());
    for (const PairAdvice& a : pairs) order.push_back(&a);
    std::stable_sort(order.begin(), order.end(), [](const PairAdvice* x, const PairAdvice* y) {
        if (x->safe() != y->safe()) return !x->safe();
        return smallest_ks(*x) / std::max(x->ks, 1e-300) > smallest_ks(*y) / std::max(y->ks, 1e-300);
    });
    for (std::size_t i = 0; i < order.size() && i < kMostPairsShown; ++i) describe_pair(o, *order[i]);
    if (order.size() > kMostPairsShown) o << "... and " << order.size() - kMostPairsShown << " more pairs\n";
    return o.str();
}

}  // namespace penalty::scene
