// The direct linear solvers of a scene file (src/scene/builder/direct_solvers.cpp): each type's
// factorization and default ordering, the ordering and linear system read from a link or the node
// (a Cholesky solver keeps AMD or natural), a MatrixLinearSystem's assembly options, the system a
// CompositeLinearSystem solves, the role printed, and the refusals' exact messages naming
// test.scn:line, the component and the attribute.
#include "penalty/scene/scene.hpp"
#include "penalty/simulation/direct_linear_solver.hpp"
#include "penalty_test/scene_text.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>
#include <string>

namespace {

using namespace penalty;
using penalty::test::build;
using penalty::test::error_of;
using ::testing::HasSubstr;

/// A node "S" with an implicit Euler solver, `parts` (the linear solver and what it reads), and a
/// particle on a fixed one by a spring.
std::string direct_solver_scene(const std::string& parts) {
    return R"(<Node name="root" dt="0.01" gravity="0 -10 0">
  <Node name="S">
    <EulerImplicitSolver rayleighStiffness="0" rayleighMass="0"/>
)" + parts +
           R"(
    <MechanicalObject name="dofs" position="0 0 0  1 0 0"/>
    <UniformMass totalMass="2"/>
    <FixedProjectiveConstraint indices="0"/>
    <SpringForceField spring="0 1 100 0 1"/>
  </Node>
</Node>)";
}

/// The direct solver of node "S" of `xml`, built.
std::shared_ptr<DirectLinearSolver> direct_solver_of(const std::string& xml) {
    auto s = build(xml);
    std::shared_ptr<DirectLinearSolver> found;
    std::function<void(Node&)> visit = [&](Node& n) {
        if (auto* e = dynamic_cast<EulerImplicitSolver*>(n.ode_solver()); e != nullptr && n.name() == "S")
            found = e->direct_solver;
        for (const auto& c : n.children()) visit(*c);
    };
    visit(s->simulation().root());
    return found;
}

TEST(DirectSolvers, EachTypesFactorizationAndDefaultOrdering) {
    struct Row {
        const char* type;
        FactorizationMethod method;
        FillOrdering ordering;
    };
    const Row rows[] = {
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
    for (const Row& r : rows) {
        const auto solver = direct_solver_of(direct_solver_scene(std::string("    <") + r.type + "/>"));
        ASSERT_TRUE(solver) << r.type;
        EXPECT_EQ(solver->method, r.method) << r.type;
        EXPECT_EQ(solver->ordering, r.ordering) << r.type;
        EXPECT_TRUE(solver->reuse_symbolic) << r.type;  // precomputeSymbolicDecomposition="1"
        EXPECT_TRUE(solver->assembly.assemble_mass && solver->assembly.assemble_stiffness &&
                    solver->assembly.assemble_damping && solver->assembly.apply_projective_constraints &&
                    solver->assembly.apply_mapped_components)
            << r.type;  // MatrixLinearSystem's defaults without a system
    }
}

TEST(DirectSolvers, TheOrderingFromTheLinkOrTheNodeAndCholeskysTwo) {
    EXPECT_EQ(direct_solver_of(direct_solver_scene("    <NaturalOrderingMethod/><SparseLDLSolver/>"))->ordering,
              FillOrdering::natural);
    EXPECT_EQ(direct_solver_of(direct_solver_scene("    <COLAMDOrderingMethod/><SparseLDLSolver/>"))->ordering,
              FillOrdering::colamd);
    // the link wins over the node's first
    EXPECT_EQ(direct_solver_of(direct_solver_scene("    <NaturalOrderingMethod/><AMDOrderingMethod name=\"amd\"/>"
                                                   "<EigenSparseLU orderingMethod=\"@amd\"/>"))
                  ->ordering,
              FillOrdering::amd);
    // a Cholesky solver: natural kept, any other ordering is AMD
    EXPECT_EQ(direct_solver_of(direct_solver_scene("    <COLAMDOrderingMethod/><EigenSimplicialLLT/>"))->ordering,
              FillOrdering::amd);
    EXPECT_EQ(direct_solver_of(direct_solver_scene("    <NaturalOrderingMethod/><SparseCholeskySolver/>"))->ordering,
              FillOrdering::natural);
}

TEST(DirectSolvers, TheLinearSystemsAssemblyOptionsAndTheCompositesSolvedSystem) {
    const auto solver = direct_solver_of(direct_solver_scene(
        R"(    <MatrixLinearSystem assembleMass="0" applyProjectiveConstraints="0"/><SparseLDLSolver precomputeSymbolicDecomposition="0"/>)"));
    EXPECT_FALSE(solver->assembly.assemble_mass);
    EXPECT_TRUE(solver->assembly.assemble_stiffness);
    EXPECT_FALSE(solver->assembly.apply_projective_constraints);
    EXPECT_FALSE(solver->reuse_symbolic);
    // a CompositeLinearSystem of the node is preferred; it solves its solverLinearSystem
    const auto composite = direct_solver_of(direct_solver_scene(
        R"(    <MatrixLinearSystem name="full"/><MatrixLinearSystem name="stiff" assembleMass="0" assembleDamping="0"/>
    <CompositeLinearSystem linearSystems="@full @stiff" solverLinearSystem="@stiff"/><SparseLDLSolver/>)"));
    EXPECT_FALSE(composite->assembly.assemble_mass);
    EXPECT_FALSE(composite->assembly.assemble_damping);
    // without solverLinearSystem: the first of linearSystems
    const auto first = direct_solver_of(direct_solver_scene(
        R"(    <MatrixLinearSystem name="full"/><MatrixLinearSystem name="stiff" assembleMass="0"/>
    <CompositeLinearSystem linearSystems="@stiff @full"/><SparseLDLSolver/>)"));
    EXPECT_FALSE(first->assembly.assemble_mass);
}

TEST(DirectSolvers, TheRoleNamesTheFactorizationOrderingAndWhatIsAssembled) {
    auto s = build(direct_solver_scene(
        R"(    <MatrixLinearSystem assembleMass="0" applyMappedComponents="0"/><NaturalOrderingMethod/><EigenSparseLU/>)"));
    const std::string info = scene::describe_scene(*s);
    EXPECT_THAT(info, HasSubstr("direct solve of the assembled system: LU (Eigen), natural ordering; assembles B K "
                                "only; mapped components left out"));
    EXPECT_THAT(info, HasSubstr("the system the direct linear solver assembles and solves"));
    EXPECT_THAT(info, HasSubstr("the ordering of the direct linear solver"));
}

// One implicit Euler step of the particle (m = 1) at the spring's rest length, along x: no
// transverse stiffness, so v = dt·g and x = dt²·g in y, whatever the factorization.
TEST(DirectSolvers, EveryFactorizationSolvesTheSameStep) {
    for (const char* type :
         {"SparseLDLSolver", "EigenSimplicialLLT", "CholeskySolver", "EigenSparseLU", "EigenSparseQR"}) {
        auto s = build(direct_solver_scene(std::string("    <MatrixLinearSystem/><") + type + "/>"));
        s->step();
        const auto* dofs = dynamic_cast<const Vec3Object*>(s->states().front().state);
        ASSERT_NE(dofs, nullptr);
        EXPECT_NEAR(dofs->velocity[1].y(), -0.1, 1e-15) << type;
        EXPECT_NEAR(dofs->position[1].y(), -0.001, 1e-17) << type;
        EXPECT_NEAR(dofs->position[1].x(), 1.0, 1e-15) << type;
        EXPECT_EQ(dofs->position[0], Vec3(0, 0, 0)) << type;
    }
}

TEST(DirectSolvers, RefusalsNameTheLineTheComponentAndTheAttribute) {
    EXPECT_EQ(error_of(direct_solver_scene(R"(    <AsyncSparseLDLSolver enableAssembly="0"/>)")),
              "test.scn:4: AsyncSparseLDLSolver: attribute 'enableAssembly': 0 is not supported (penalty assembles "
              "the system)");
    EXPECT_EQ(
        error_of(direct_solver_scene(R"(    <AMDOrderingMethod name="amd"/><SparseLDLSolver linearSystem="@amd"/>)")),
        "test.scn:4: SparseLDLSolver: attribute 'linearSystem': must link to a MatrixLinearSystem, "
        "ConstantSparsityPatternSystem or CompositeLinearSystem");
    EXPECT_EQ(
        error_of(direct_solver_scene(R"(    <MatrixLinearSystem name="m"/><SparseLDLSolver orderingMethod="@m"/>)")),
        "test.scn:4: SparseLDLSolver: attribute 'orderingMethod': must link to an AMDOrderingMethod, "
        "COLAMDOrderingMethod or NaturalOrderingMethod");
    EXPECT_EQ(error_of(direct_solver_scene(R"(    <CompositeLinearSystem/><SparseLDLSolver/>)")),
              "test.scn:4: CompositeLinearSystem: needs solverLinearSystem (or linearSystems) linking to a "
              "MatrixLinearSystem");
    EXPECT_EQ(
        error_of(direct_solver_scene(
            R"(    <NaturalOrderingMethod name="n"/><CompositeLinearSystem solverLinearSystem="@n"/><SparseLDLSolver/>)")),
        "test.scn:4: CompositeLinearSystem: attribute 'solverLinearSystem': must link to a MatrixLinearSystem, "
        "found NaturalOrderingMethod 'n'");
}

}  // namespace
