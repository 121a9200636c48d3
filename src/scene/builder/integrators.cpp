// ODE solvers beyond implicit and explicit Euler, and the multi-step animation loop:
// StaticSolver (with its NewtonRaphsonSolver), RungeKutta2Solver, RungeKutta4Solver,
// MultiStepAnimationLoop.
#include "penalty/simulation/runge_kutta.hpp"
#include "penalty/simulation/static_solver.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using io::SceneNode;
using K = AttributeKind;
using F = ComponentFamily;

// ---- NewtonRaphsonSolver ----------------------------------------------------------------------
constexpr AttributeSpec kNewtonRaphson[] = {
    {"maxNbIterationsNewton", K::integer, "1", "", ValueCheck::none, "Newton iterations at most (0 to 10^6)"},
    {"relativeSuccessiveStoppingThreshold", K::real, "1e-5", "", ValueCheck::nonnegative, "|r_k| < t |r_k-1|"},
    {"relativeInitialStoppingThreshold", K::real, "1e-5", "", ValueCheck::nonnegative, "|r_k| < t |r_0|"},
    {"absoluteResidualStoppingThreshold", K::real, "1e-5", "N", ValueCheck::nonnegative, "|r_k| < t"},
    {"relativeEstimateDifferenceThreshold", K::real, "0", "", ValueCheck::nonnegative, "|dx| < t |x| (0: off)"},
    {"absoluteEstimateDifferenceThreshold", K::real, "0", "m", ValueCheck::nonnegative, "|dx| < t (0: off)"},
    {"maxNbIterationsLineSearch", K::integer, "1", "", ValueCheck::none, "line search steps at most (0 to 10^6)"},
    {"lineSearchCoefficient", K::real, "0.5", "", ValueCheck::positive, "step factor of the line search, (0, 1]"},
    {"updateStateWhenDiverged", K::boolean, "1", "", ValueCheck::none, "SOFA reads it nowhere; 0 is refused"},
    {"warnWhenLineSearchFails", K::boolean, "1", "", ValueCheck::none, "logging only"},
    {"warnWhenDiverge", K::boolean, "1", "", ValueCheck::none, "logging only"},
};

constexpr std::int64_t kMaxIterations = 1000000;

void read_newton(const SceneComponent& c, NewtonRaphsonParameters& p) {
    const Attributes a(c);
    const auto count = [&](std::string_view name) {
        const auto v = a.integer(name);
        if (v < 0 || v > kMaxIterations) a.fail(name, "must be between 0 and " + std::to_string(kMaxIterations));
        return int(v);
    };
    p.max_iterations = count("maxNbIterationsNewton");
    p.max_line_search_iterations = count("maxNbIterationsLineSearch");
    p.relative_successive = a.real("relativeSuccessiveStoppingThreshold");
    p.relative_initial = a.real("relativeInitialStoppingThreshold");
    p.absolute_residual = a.real("absoluteResidualStoppingThreshold");
    p.relative_estimate_difference = a.real("relativeEstimateDifferenceThreshold");
    p.absolute_estimate_difference = a.real("absoluteEstimateDifferenceThreshold");
    p.line_search_coefficient = a.real("lineSearchCoefficient");
    if (p.line_search_coefficient > 1) a.fail("lineSearchCoefficient", "must be in (0, 1]");
    if (!a.boolean("updateStateWhenDiverged"))
        a.fail("updateStateWhenDiverged", "0 is not supported (SOFA ignores it)");
}

/// SOFA's getContext()->get<T>(SearchDown): the node's components, then its children's, depth first.
const SceneComponent* search_down(const SceneNode& node, std::string_view type) {
    for (const auto& c : node.components)
        if (c->type == type) return c.get();
    for (const auto& child : node.children)
        if (const SceneComponent* found = search_down(*child, type)) return found;
    return nullptr;
}

// ---- StaticSolver -----------------------------------------------------------------------------
// The Newton data StaticSolver had before SOFA v25.06 (StaticSolver::parse): read only when no
// NewtonRaphsonSolver is found and SOFA creates one, as SOFA does (StaticSolver::init), with
// SOFA's mapping, relative_residual_tolerance_threshold included (to the estimate difference).
constexpr AttributeSpec kStatic[] = {
    {"newtonSolver", K::link, "(a NewtonRaphsonSolver of the node or below, else SOFA's defaults)", "",
     ValueCheck::none, "the Newton-Raphson parameters"},
    {"linearSolver", K::link, "(the node's linear solver)", "", ValueCheck::none, "the linear solver of -K dx = f"},
    {"newton_iterations", K::integer, "", "", ValueCheck::none, "deprecated: maxNbIterationsNewton"},
    {"absolute_correction_tolerance_threshold", K::real, "", "m", ValueCheck::nonnegative,
     "deprecated: absoluteEstimateDifferenceThreshold"},
    {"relative_correction_tolerance_threshold", K::real, "", "", ValueCheck::nonnegative,
     "deprecated: relativeEstimateDifferenceThreshold"},
    {"absolute_residual_tolerance_threshold", K::real, "", "N", ValueCheck::nonnegative,
     "deprecated: absoluteResidualStoppingThreshold"},
    {"relative_residual_tolerance_threshold", K::real, "", "", ValueCheck::nonnegative,
     "deprecated: SOFA maps it to relativeEstimateDifferenceThreshold"},
    {"should_diverge_when_residual_is_growing", K::boolean, "0", "", ValueCheck::none, "deprecated, no effect"},
};

void read_deprecated_newton(const Attributes& a, NewtonRaphsonParameters& p) {
    // StaticSolver's NewtonRaphsonDeprecatedData: no default of their own, each copied into the
    // NewtonRaphsonSolver's Data when given (SOFA maps relative_residual_tolerance_threshold onto
    // relativeEstimateDifferenceThreshold too, StaticSolver::init)
    if (a.has("newton_iterations")) {
        const auto v = a.integer_or("newton_iterations", p.max_iterations);
        if (v < 0 || v > kMaxIterations)
            a.fail("newton_iterations", "must be between 0 and " + std::to_string(kMaxIterations));
        p.max_iterations = int(v);
    }
    p.absolute_estimate_difference =
        a.real_or("absolute_correction_tolerance_threshold", p.absolute_estimate_difference);
    p.relative_estimate_difference =
        a.real_or("relative_correction_tolerance_threshold", p.relative_estimate_difference);
    p.absolute_residual = a.real_or("absolute_residual_tolerance_threshold", p.absolute_residual);
    p.relative_estimate_difference = a.real_or("relative_residual_tolerance_threshold", p.relative_estimate_difference);
}

/// The linear solver an ODE solver of `c`'s node uses: `linearSolver` link, else the node's.
const SceneComponent* linear_solver_of(const Attributes& a, const NodeBuild& info) {
    if (a.has("linearSolver")) {
        const io::LinkTarget t = a.link("linearSolver");
        if (t.component == nullptr || find_component(t.component->type)->family != F::linear_solver)
            a.fail("linearSolver", "must link to a linear solver (CGLinearSolver, SparseLDLSolver, ...)");
        return t.component;
    }
    for (const SceneComponent* l : info.physics)
        if (find_component(l->type)->family == F::linear_solver) return l;
    return nullptr;
}

void build_static_solver(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    Node& node = *info.node;
    b.guarded(c, [&] {
        auto& s = node.set_ode_solver<StaticSolver>();
        s.sofa_mapping_graph_order = b.options().sofa_head_orders;
        const SceneComponent* linear = linear_solver_of(a, info);
        if (linear == nullptr)
            io::throw_element_error(c,
                                    "needs a linear solver in its node (SOFA: 'A linear solver is required by this "
                                    "component but has not been found', and the solver does nothing)");
        if (is_direct_linear_solver(linear->type)) s.linear.direct = read_direct_linear_solver(b, *linear);
        else read_conjugate_gradient(b, *linear, s.linear.cg);
        const SceneComponent* newton = nullptr;
        if (a.has("newtonSolver")) {
            newton = a.link("newtonSolver").component;
            if (newton == nullptr || newton->type != "NewtonRaphsonSolver")
                a.fail("newtonSolver", "must link to a NewtonRaphsonSolver");
        } else {
            newton = search_down(*c.node, "NewtonRaphsonSolver");
        }
        if (newton != nullptr) {
            b.guarded(*newton, [&] { read_newton(*newton, s.newton); });
            b.mark_used(newton);
            b.role(*newton, [p = &s.newton] {
                return "Newton-Raphson of the static solver: at most " + std::to_string(p->max_iterations) +
                       " iterations, " + std::to_string(p->max_line_search_iterations) + " line-search steps";
            });
        } else {
            read_deprecated_newton(a, s.newton);
        }
        b.add_init(1, c, [p = &s, n = &node] { p->init(*n); });
        b.role(c, [p = &s, n = &node, newton, type = linear->type] {
            return "static equilibrium over this subtree (" + subtree_dofs(*n) + "): Newton-Raphson (at most " +
                   std::to_string(p->newton.max_iterations) + " iterations a step" +
                   (newton == nullptr ? ", SOFA's defaults" : "") + "), linear solver " + type;
        });
    });
    b.note_unread_attributes(c);
}

void build_newton(SceneBuilder& b, const SceneComponent& c, NodeBuild&) {
    NewtonRaphsonParameters p;
    b.guarded(c, [&] { read_newton(c, p); });  // its values are checked even when no solver reads it
    b.note_unread_attributes(c);
    if (!b.is_used(&c)) b.role(c, [] { return std::string("not read by a StaticSolver"); });
}

// ---- Runge-Kutta --------------------------------------------------------------------------------
template <class Solver>
void build_runge_kutta(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    Node& node = *info.node;
    b.guarded(c, [&] {
        auto& s = node.set_ode_solver<Solver>();
        s.sofa_mapping_graph_order = b.options().sofa_head_orders;
        b.add_init(1, c, [p = &s, n = &node] { p->init(*n); });
        b.role(c, [n = &node, order = std::is_same_v<Solver, RungeKutta4Solver> ? 4 : 2] {
            return "explicit Runge-Kutta of order " + std::to_string(order) + " over this subtree (" +
                   subtree_dofs(*n) + ")";
        });
    });
    b.note_unread_attributes(c);
}

// ---- MultiStepAnimationLoop -------------------------------------------------------------------
constexpr AttributeSpec kMultiStep[] = {
    {"collisionSteps", K::integer, "1", "", ValueCheck::none, "collision steps a step (1 to 10^6)"},
    {"integrationSteps", K::integer, "1", "", ValueCheck::none, "integrations after each collision (1 to 10^6)"},
    {"computeBoundingBox", K::boolean, "1", "", ValueCheck::none, "drawing only"},
    // beyond SOFA
    {"exactTime", K::boolean, "0", "", ValueCheck::none,
     "beyond SOFA: a step advances the time by dt (SOFA: by dt / collisionSteps)"},
};

void build_multi_step(SceneBuilder& b, const SceneComponent& c, NodeBuild& info) {
    const Attributes a(c);
    if (info.scene_node->parent != nullptr) {
        b.warn(c.file + ":" + std::to_string(c.line) + ": " + c.describe() +
               " is not in the root node: ignored (SOFA animates with the root's loop)");
        b.note_unread_attributes(c);
        return;
    }
    const auto count = [&](std::string_view name) {
        const auto v = a.integer(name);
        if (v < 1 || v > kMaxIterations) a.fail(name, "must be between 1 and " + std::to_string(kMaxIterations));
        return int(v);
    };
    const int collisions = count("collisionSteps");
    const int integrations = count("integrationSteps");
    b.guarded(c, [&] { b.simulation().set_multi_step(collisions, integrations, !a.boolean("exactTime")); });
    b.role(c, [collisions, integrations] {
        return "each step: " + counted(std::size_t(collisions), "collision", "collisions") + ", each followed by " +
               counted(std::size_t(integrations), "integration", "integrations") + " of dt / " +
               std::to_string(std::int64_t(collisions) * integrations);
    });
    b.note_unread_attributes(c);
}

constexpr ComponentSpec kIntegratorComponents[] = {
    {.type = "StaticSolver",
     .family = F::ode_solver,
     .summary = "static equilibrium by Newton-Raphson (velocities kept)",
     .attributes = kStatic,
     .build = build_static_solver},
    {.type = "NewtonRaphsonSolver",
     .family = F::solver_part,
     .summary = "Newton-Raphson parameters of a StaticSolver",
     .attributes = kNewtonRaphson,
     .build = build_newton},
    {.type = "RungeKutta2Solver",
     .family = F::ode_solver,
     .summary = "explicit midpoint Runge-Kutta ODE solver",
     .build = build_runge_kutta<RungeKutta2Solver>},
    {.type = "RungeKutta4Solver",
     .family = F::ode_solver,
     .summary = "explicit classical Runge-Kutta ODE solver",
     .build = build_runge_kutta<RungeKutta4Solver>},
    {.type = "MultiStepAnimationLoop",
     .family = F::animation_loop,
     .summary = "time loop: several collisions a step, several integrations after each",
     .attributes = kMultiStep,
     .build = build_multi_step},
};

}  // namespace

std::span<const ComponentSpec> integrator_components() { return kIntegratorComponents; }

}  // namespace penalty::scene::builder
