// Direct linear solvers and the parts they read: SparseLDLSolver, AsyncSparseLDLSolver,
// SparseCholeskySolver, CholeskySolver, SparseLUSolver, EigenSimplicialLDLT, EigenSimplicialLLT,
// EigenSparseLU, EigenSparseQR; MatrixLinearSystem, ConstantSparsityPatternSystem,
// CompositeLinearSystem; AMDOrderingMethod, COLAMDOrderingMethod, NaturalOrderingMethod. The ODE
// solver of the node reads its linear solver (read_direct_linear_solver); these components'
// own build functions only note what penalty does not read.
#include "penalty/simulation/direct_linear_solver.hpp"
#include "scene/builder/families.hpp"
#include "scene/builder/scene_builder.hpp"

#include <algorithm>

namespace penalty::scene::builder {

namespace {

using io::SceneComponent;
using K = AttributeKind;
using F = ComponentFamily;

// ---- the direct solvers ------------------------------------------------------------------------
// MatrixLinearSolver's data (d_parallelInverseProduct, l_linearSystem), OrderingMethodAccessor's
// l_orderingMethod, SparseLDLSolverImpl's precomputeSymbolicDecomposition.
constexpr AttributeSpec kDirectSolver[] = {
    {"linearSystem", K::link, "(a linear system of the node, else a MatrixLinearSystem)", "", ValueCheck::none,
     "the system assembled (MatrixLinearSystem, ConstantSparsityPatternSystem or CompositeLinearSystem)"},
    {"orderingMethod", K::link, "(an ordering method of the node, else AMD)", "", ValueCheck::none,
     "the fill-reducing permutation (AMD, COLAMD, natural)"},
    {"precomputeSymbolicDecomposition", K::boolean, "1", "", ValueCheck::none,
     "keep the symbolic factorization while the matrix's pattern is the same"},
    {"parallelInverseProduct", K::boolean, "0", "", ValueCheck::none, "constraint solvers only (no effect here)"},
    {"enableAssembly", K::boolean, "1", "", ValueCheck::none, "AsyncSparseLDLSolver: 0 is refused"},
    {"L_nnz", K::integer, "0", "", ValueCheck::none, "output (a written value is ignored)"},
};

/// The factorization of each direct solver type. SparseLDLSolver's own LDLᵀ (SOFA's, with its
/// AMD permutation) is the same factorization as Eigen's SimplicialLDLT: the numbers agree to
/// rounding. AsyncSparseLDLSolver factorizes in a thread between steps in SOFA; here at once
/// (its result one step later in SOFA is not reproduced: see docs). SparseCholeskySolver and
/// SparseLUSolver live in SOFA's CSparseSolvers plugin (CSparse's Cholesky and LU).
struct DirectType {
    std::string_view type;
    FactorizationMethod method;
    FillOrdering default_ordering;
};
constexpr DirectType kDirectTypes[] = {
    {"SparseLDLSolver", FactorizationMethod::ldlt, FillOrdering::amd},
    {"AsyncSparseLDLSolver", FactorizationMethod::ldlt, FillOrdering::amd},
    {"EigenSimplicialLDLT", FactorizationMethod::ldlt, FillOrdering::amd},
    {"EigenSimplicialLLT", FactorizationMethod::llt, FillOrdering::amd},
    {"SparseCholeskySolver", FactorizationMethod::llt, FillOrdering::amd},
    {"CholeskySolver", FactorizationMethod::llt, FillOrdering::natural},
    {"EigenSparseLU", FactorizationMethod::lu, FillOrdering::colamd},
    {"SparseLUSolver", FactorizationMethod::lu, FillOrdering::colamd},
    {"EigenSparseQR", FactorizationMethod::qr, FillOrdering::colamd},
};

const DirectType* direct_type(std::string_view type) {
    for (const DirectType& d : kDirectTypes)
        if (d.type == type) return &d;
    return nullptr;
}

// ---- linear systems ------------------------------------------------------------------------------
constexpr AttributeSpec kMatrixLinearSystem[] = {
    {"assembleStiffness", K::boolean, "1", "", ValueCheck::none, "K in the matrix"},
    {"assembleMass", K::boolean, "1", "", ValueCheck::none, "M in the matrix"},
    {"assembleDamping", K::boolean, "1", "", ValueCheck::none, "B in the matrix"},
    {"assembleGeometricStiffness", K::boolean, "1", "", ValueCheck::none,
     "mappings' geometric stiffness (none of penalty's mappings has one: RigidMapping's is off in SOFA)"},
    {"applyProjectiveConstraints", K::boolean, "1", "", ValueCheck::none, "projective constraints on the matrix"},
    {"applyMappedComponents", K::boolean, "1", "", ValueCheck::none, "the mapped states' components through Jᵀ·J"},
    {"checkIndices", K::boolean, "0", "", ValueCheck::none, "debugging only"},
    {"parallelAssemblyIndependentMatrices", K::boolean, "0", "", ValueCheck::none, "same numbers"},
    {"factorizationInvalidation", K::boolean, "0", "", ValueCheck::none, "internal"},
};

constexpr AttributeSpec kCompositeLinearSystem[] = {
    {"linearSystems", K::links, "", "", ValueCheck::none, "the systems fed (penalty assembles the solver's only)"},
    {"solverLinearSystem", K::link, "(the first of linearSystems)", "", ValueCheck::none,
     "the system the solver solves"},
};

bool is_linear_system(std::string_view type) {
    return type == "MatrixLinearSystem" || type == "ConstantSparsityPatternSystem" || type == "CompositeLinearSystem";
}
bool is_ordering(std::string_view type) {
    return type == "AMDOrderingMethod" || type == "COLAMDOrderingMethod" || type == "NaturalOrderingMethod";
}

/// The MatrixLinearSystem a solver assembles: a CompositeLinearSystem's solverLinearSystem.
const SceneComponent& solved_system(const SceneComponent& system) {
    if (system.type != "CompositeLinearSystem") return system;
    const Attributes a(system);
    const SceneComponent* target = nullptr;
    if (a.has("solverLinearSystem")) {
        target = a.link("solverLinearSystem").component;
    } else if (a.has("linearSystems")) {
        const auto links = a.links("linearSystems");
        if (!links.empty()) target = links.front().component;
    }
    if (target == nullptr)
        io::throw_element_error(system, "needs solverLinearSystem (or linearSystems) linking to a MatrixLinearSystem");
    if (target->type != "MatrixLinearSystem" && target->type != "ConstantSparsityPatternSystem")
        a.fail(a.has("solverLinearSystem") ? "solverLinearSystem" : "linearSystems",
               "must link to a MatrixLinearSystem, found " + target->describe());
    return *target;
}

MatrixAssemblyOptions read_assembly(const SceneComponent& system) {
    const Attributes a(system);
    MatrixAssemblyOptions o;
    o.assemble_stiffness = a.boolean("assembleStiffness");
    o.assemble_mass = a.boolean("assembleMass");
    o.assemble_damping = a.boolean("assembleDamping");
    o.apply_projective_constraints = a.boolean("applyProjectiveConstraints");
    o.apply_mapped_components = a.boolean("applyMappedComponents");
    return o;
}

/// The first component of the node of `c` for which `wanted` holds (SOFA's getContext()->get:
/// the component's own node).
const SceneComponent* in_node(const SceneComponent& c, bool (*wanted)(std::string_view)) {
    if (c.node == nullptr) return nullptr;
    for (const auto& other : c.node->components)
        if (wanted(other->type)) return other.get();
    return nullptr;
}

void note_unless_solver_reads(SceneBuilder& b, const SceneComponent& c, NodeBuild&) {
    b.note_unread_attributes(c);
    if (!b.is_used(&c))
        b.role(c, [] {
            return std::string("not read by an ODE solver of penalty's (no ODE solver in this node reads it)");
        });
}

/// Linear systems and ordering methods: their reader describes them; an unused one is said so.
void note_part(SceneBuilder& b, const SceneComponent& c, NodeBuild&) {
    b.note_unread_attributes(c);
    if (!b.is_used(&c))
        b.role(c, [type = c.type] {
            return type == "MatrixLinearSystem" || type == "ConstantSparsityPatternSystem"
                       ? std::string(
                             "not solved by a solver: assembled for access from Python only (its A(), "
                             "with the solve's factors, when asked)")
                       : std::string("not read by a solver");
        });
}

constexpr ComponentSpec kDirectSolverComponents[] = {
    {.type = "SparseLDLSolver",
     .family = F::linear_solver,
     .summary = "direct LDLᵀ solver of the assembled system",
     .attributes = kDirectSolver,
     .build = note_unless_solver_reads},
    {.type = "AsyncSparseLDLSolver",
     .family = F::linear_solver,
     .summary = "direct LDLᵀ solver (penalty factorizes at each solve, synchronously)",
     .attributes = kDirectSolver,
     .build = note_unless_solver_reads},
    {.type = "EigenSimplicialLDLT",
     .family = F::linear_solver,
     .summary = "Eigen's sparse LDLᵀ of the assembled system",
     .attributes = kDirectSolver,
     .build = note_unless_solver_reads},
    {.type = "EigenSimplicialLLT",
     .family = F::linear_solver,
     .summary = "Eigen's sparse Cholesky LLᵀ of the assembled system",
     .attributes = kDirectSolver,
     .build = note_unless_solver_reads},
    {.type = "SparseCholeskySolver",
     .family = F::linear_solver,
     .summary = "sparse Cholesky LLᵀ (SOFA's CSparseSolvers plugin)",
     .attributes = kDirectSolver,
     .build = note_unless_solver_reads},
    {.type = "CholeskySolver",
     .family = F::linear_solver,
     .summary = "Cholesky LLᵀ, natural ordering",
     .attributes = kDirectSolver,
     .build = note_unless_solver_reads},
    {.type = "EigenSparseLU",
     .family = F::linear_solver,
     .summary = "Eigen's sparse LU of the assembled system",
     .attributes = kDirectSolver,
     .build = note_unless_solver_reads},
    {.type = "SparseLUSolver",
     .family = F::linear_solver,
     .summary = "sparse LU (SOFA's CSparseSolvers plugin)",
     .attributes = kDirectSolver,
     .build = note_unless_solver_reads},
    {.type = "EigenSparseQR",
     .family = F::linear_solver,
     .summary = "Eigen's sparse QR of the assembled system",
     .attributes = kDirectSolver,
     .build = note_unless_solver_reads},
    {.type = "MatrixLinearSystem",
     .family = F::solver_part,
     .summary = "the assembled global matrix M, B, K (options)",
     .attributes = kMatrixLinearSystem,
     .build = note_part},
    {.type = "ConstantSparsityPatternSystem",
     .family = F::solver_part,
     .summary = "MatrixLinearSystem keeping its pattern (same numbers)",
     .attributes = kMatrixLinearSystem,
     .build = note_part},
    {.type = "CompositeLinearSystem",
     .family = F::solver_part,
     .summary = "several linear systems, one solved",
     .attributes = kCompositeLinearSystem,
     .build = note_part},
    {.type = "AMDOrderingMethod",
     .family = F::solver_part,
     .summary = "approximate minimum degree ordering",
     .build = note_part},
    {.type = "COLAMDOrderingMethod",
     .family = F::solver_part,
     .summary = "column approximate minimum degree ordering",
     .build = note_part},
    {.type = "NaturalOrderingMethod", .family = F::solver_part, .summary = "no permutation", .build = note_part},
};

}  // namespace

bool is_direct_linear_solver(std::string_view type) { return direct_type(type) != nullptr; }

std::shared_ptr<DirectLinearSolver> read_direct_linear_solver(SceneBuilder& b, const SceneComponent& linear) {
    const DirectType* kind = direct_type(linear.type);
    if (kind == nullptr) io::throw_element_error(linear, "is not a direct linear solver");
    const Attributes a(linear);
    auto solver = std::make_shared<DirectLinearSolver>();
    solver->method = kind->method;
    solver->ordering = kind->default_ordering;
    solver->reuse_symbolic = a.boolean("precomputeSymbolicDecomposition");
    if (!a.boolean("enableAssembly")) a.fail("enableAssembly", "0 is not supported (penalty assembles the system)");
    b.mark_used(&linear);
    b.record_origin(solver.get(), linear);  // (a SingularSystemError names it)
    // the linear system: the link, else one of the solver's node, else MatrixLinearSystem's defaults
    const SceneComponent* system = nullptr;
    if (a.has("linearSystem")) {
        system = a.link("linearSystem").component;
        if (system == nullptr || !is_linear_system(system->type))
            a.fail("linearSystem",
                   "must link to a MatrixLinearSystem, ConstantSparsityPatternSystem or CompositeLinearSystem");
    } else {
        system = in_node(linear, [](std::string_view t) { return t == "CompositeLinearSystem"; });
        if (system == nullptr) system = in_node(linear, is_linear_system);
    }
    if (system != nullptr) {
        const SceneComponent& solved = solved_system(*system);
        solver->assembly = read_assembly(solved);
        b.mark_used(system);
        b.mark_used(&solved);
        b.role(*system, [] { return std::string("the system the direct linear solver assembles and solves"); });
        if (&solved != system) b.role(solved, [] { return std::string("the system the direct linear solver solves"); });
    }
    // the ordering: the link, else one of the node
    const SceneComponent* ordering = nullptr;
    if (a.has("orderingMethod")) {
        ordering = a.link("orderingMethod").component;
        if (ordering == nullptr || !is_ordering(ordering->type))
            a.fail("orderingMethod",
                   "must link to an AMDOrderingMethod, COLAMDOrderingMethod or NaturalOrderingMethod");
    } else {
        ordering = in_node(linear, is_ordering);
    }
    if (ordering != nullptr && kind->method != FactorizationMethod::llt) {
        solver->ordering = ordering->type == "AMDOrderingMethod"      ? FillOrdering::amd
                           : ordering->type == "COLAMDOrderingMethod" ? FillOrdering::colamd
                                                                      : FillOrdering::natural;
        b.mark_used(ordering);
        b.role(*ordering, [] { return std::string("the ordering of the direct linear solver"); });
    } else if (ordering != nullptr) {
        solver->ordering = ordering->type == "NaturalOrderingMethod" ? FillOrdering::natural : FillOrdering::amd;
        b.mark_used(ordering);
        b.role(*ordering, [] { return std::string("the ordering of the direct linear solver"); });
    }
    b.role(linear, [s = solver.get()] {
        std::string out = "direct solve of the assembled system: " + std::string(factorization_name(s->method)) +
                          " (Eigen), " + std::string(ordering_name(s->ordering)) + " ordering";
        const MatrixAssemblyOptions& o = s->assembly;
        if (!o.assemble_mass || !o.assemble_stiffness || !o.assemble_damping)
            out += std::string("; assembles") + (o.assemble_mass ? " M" : "") + (o.assemble_damping ? " B" : "") +
                   (o.assemble_stiffness ? " K" : "") + " only";
        if (!o.apply_projective_constraints) out += "; projective constraints not applied to the matrix";
        if (!o.apply_mapped_components) out += "; mapped components left out";
        return out;
    });
    return solver;
}

std::span<const ComponentSpec> direct_solver_components() { return kDirectSolverComponents; }

}  // namespace penalty::scene::builder
