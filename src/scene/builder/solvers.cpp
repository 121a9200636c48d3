// Solvers and the animation loop: EulerImplicitSolver (with the node's CGLinearSolver),
// EulerExplicitSolver, CGLinearSolver, DefaultAnimationLoop.
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

#include "penalty/simulation/direct_linear_solver.hpp"

namespace penalty::scene::builder {

using io::SceneComponent;

std::string subtree_dofs(const Node& n) {
    std::size_t dofs = 0, states = 0;
    std::function<void(const Node&)> visit = [&](const Node& x) {
        if (x.state() != nullptr && x.mapping() == nullptr) {
            dofs += x.state()->num_dofs();
            ++states;
        }
        for (const auto& child : x.children()) visit(*child);
    };
    visit(n);
    return counted(dofs, "DOF", "DOFs") + " in " + counted(states, "state", "states");
}

namespace {

using K = AttributeKind;
using F = ComponentFamily;

// ---- EulerExplicitSolver ----------------------------------------------------------------------
constexpr AttributeSpec kExplicit[] = {
    {"symplectic", K::boolean, "1", "", ValueCheck::none, "only the symplectic scheme (v then x)"},
};

void build_explicit_solver(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Node& node = *info.node;
    b.guarded(c, [&] {
        if (!a.boolean("symplectic")) a.fail("symplectic", "only the symplectic scheme is supported");
        auto& solver = node.set_ode_solver<EulerExplicitSolver>();
        solver.sofa_mapping_graph_order = b.options().sofa_head_orders;
        b.add_init(1, c, [p = &solver, n = &node] { p->init(*n); });
        b.role(c, [n = &node] { return "symplectic explicit Euler over this subtree (" + subtree_dofs(*n) + ")"; });
    });
    b.note_unread_attributes(c);
}

// ---- CGLinearSolver ---------------------------------------------------------------------------
constexpr AttributeSpec kConjugateGradient[] = {
    {"iterations", K::integer, "25", "", ValueCheck::none, "at most (1 to BuildOptions::max_cg_iterations)"},
    {"tolerance", K::real, "1e-5", "", ValueCheck::nonnegative, "stop when |r| / |b| <= tolerance"},
    {"threshold", K::real, "1e-5", "", ValueCheck::nonnegative, "stop when |pᵀAp| <= threshold"},
};

}  // namespace

/// The CG limits from the node's CGLinearSolver (read by the ODE solver of its node).
void read_conjugate_gradient(SceneBuilder& b, const SceneComponent& linear, CGLinearSolver& cg) {
    const Attributes a(linear);
    const std::uint64_t max_iterations = b.options().max_cg_iterations;
    const auto it = a.integer("iterations");
    if (it < 1 || std::uint64_t(it) > max_iterations)
        a.fail("iterations", "must be between 1 and " + std::to_string(max_iterations));
    cg.iterations = int(it);
    cg.tolerance = a.real("tolerance");
    cg.threshold = a.real("threshold");
    b.role(linear, [p = &cg] {
        return "conjugate gradient of the node's ODE solver: at most " + std::to_string(p->iterations) +
               " iterations, tolerance " + num(p->tolerance) + ", threshold " + num(p->threshold);
    });
}

namespace {

// ---- EulerImplicitSolver ----------------------------------------------------------------------
constexpr AttributeSpec kImplicit[] = {
    {"rayleighStiffness", K::real, "0", "s", ValueCheck::none, "damping proportional to K"},
    {"rayleighMass", K::real, "0", "1/s", ValueCheck::none, "damping proportional to M"},
    {"vdamping", K::real, "0", "1/s", ValueCheck::nonnegative, "velocity damping"},
    {"firstOrder", K::boolean, "0", "", ValueCheck::none, "first-order system (no inertia term)"},
    {"trapezoidalScheme", K::boolean, "0", "", ValueCheck::none, "trapezoidal rule"},
    // beyond SOFA
    {"newton", K::boolean, "0", "", ValueCheck::none, "beyond SOFA: Newton iterations, contact re-detected"},
    {"newtonIterations", K::integer, "10", "", ValueCheck::none, "beyond SOFA: at most (1 to 1000)"},
    {"newtonTolerance", K::real, "1e-10", "N s", ValueCheck::nonnegative, "beyond SOFA: residual norm"},
};

void build_implicit_solver(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Node& node = *info.node;
    b.guarded(c, [&] {
        auto& s = node.set_ode_solver<EulerImplicitSolver>();
        s.sofa_mapping_graph_order = b.options().sofa_head_orders;
        s.blocked_reductions = b.options().blocked_reductions;
        b.add_init(1, c, [p = &s, n = &node] { p->init(*n); });
        b.record_implicit_solver(s, node);
        s.rayleigh_stiffness = a.real("rayleighStiffness");
        s.rayleigh_mass = a.real("rayleighMass");
        s.vdamping = a.real("vdamping");
        s.first_order = a.boolean("firstOrder");
        s.trapezoidal_scheme = a.boolean("trapezoidalScheme");
        s.newton.enabled = a.boolean("newton");
        if (s.newton.enabled) b.add_newton_solver(s, node);
        const auto newton_iterations = a.integer("newtonIterations");
        if (newton_iterations < 1 || newton_iterations > 1000) a.fail("newtonIterations", "must be between 1 and 1000");
        s.newton.max_iterations = int(newton_iterations);
        s.newton.tolerance = a.real("newtonTolerance");
        const SceneComponent* linear = nullptr;
        for (const SceneComponent* l : info.physics) {
            if (find_component(l->type)->family != F::linear_solver) continue;
            if (is_direct_linear_solver(l->type)) s.direct_solver = read_direct_linear_solver(b, *l);
            else read_conjugate_gradient(b, *l, s.cg);
            linear = l;
            break;
        }
        b.role(c, [p = &s, n = &node, linear] {
            std::string out = "implicit Euler over this subtree (" + subtree_dofs(*n) + ")";
            if (p->rayleigh_stiffness != 0 || p->rayleigh_mass != 0)
                out += ", Rayleigh stiffness " + num(p->rayleigh_stiffness) + " mass " + num(p->rayleigh_mass);
            if (p->vdamping != 0) out += ", vdamping " + num(p->vdamping);
            if (p->first_order) out += ", first order";
            if (p->trapezoidal_scheme) out += ", trapezoidal";
            if (p->newton.enabled)
                out += ", Newton (at most " + std::to_string(p->newton.max_iterations) +
                       " iterations, contact geometry re-detected)";
            if (linear == nullptr) out += "; no linear solver in its node: CG with SOFA's defaults";
            else if (p->direct_solver) out += "; direct linear solver " + linear->type;
            return out;
        });
    });
    b.note_unread_attributes(c);
}

/// Components another one reads (the CG by its ODE solver): their build only notes the
/// attributes penalty does not read.

constexpr ComponentSpec kSolverComponents[] = {
    {.type = "DefaultAnimationLoop",
     .family = F::animation_loop,
     .summary = "time loop: collision, then one solver step per solver node",
     .build = note_unread_attributes_only},
    {.type = "EulerImplicitSolver",
     .family = F::ode_solver,
     .summary = "implicit Euler ODE solver",
     .attributes = kImplicit,
     .build = build_implicit_solver},
    {.type = "EulerExplicitSolver",
     .family = F::ode_solver,
     .summary = "explicit Euler ODE solver",
     .attributes = kExplicit,
     .build = build_explicit_solver},
    {.type = "CGLinearSolver",
     .family = F::linear_solver,
     .summary = "conjugate gradient linear solver",
     .attributes = kConjugateGradient,
     .build = note_unread_attributes_only},
};

}  // namespace

std::span<const ComponentSpec> solver_components() { return kSolverComponents; }

}  // namespace penalty::scene::builder
