// SubtreeSystem::assemble (system_assembly.cpp): the assembled m·M + k·K of a subtree, the
// stiffness of mapped states through Jᵀ·K·J. K against central differences of the subtree's
// force (springs between independent and barycentric-mapped points, stretched and compressed so
// that their geometric stiffness counts), M against the masses, and the sum's linearity.
#include "penalty/mechanics/mapping.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/simulation/solver.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

namespace penalty {
namespace {

/// A body of three points (2 kg each) with a barycentric-mapped contact point, and a
/// free ball (0.5 kg) sprung to the contact point; a spring inside the body.
struct SystemAssemblyScene {
    Simulation sim;
    Vec3Object* body = nullptr;
    Vec3Object* contact = nullptr;
    Vec3Object* ball = nullptr;

    SystemAssemblyScene() {
        Node& root = sim.root();
        root.set_ode_solver<EulerImplicitSolver>();
        Node& body_node = root.add_child("body");
        body = &body_node.add_state<Vec3Types>("body");
        body->position = {Vec3(0, 0, 0), Vec3(1.1, 0.1, 0), Vec3(0.2, 0.9, 0.3)};
        body_node.set_mass<UniformMass<Vec3Types>>(*body).set_vertex_mass(2.0);
        body_node.add_force_field<SpringForceField>(*body, *body).add_spring({0, 2, 150.0, 0.0, 0.8});
        Node& contact_node = body_node.add_child("contact");
        contact = &contact_node.add_state<Vec3Types>("contact");
        contact_node.set_mapping<BarycentricMapping>(*body, *contact).set_weights({{{0, 0.2}, {1, 0.3}, {2, 0.5}}});
        Node& ball_node = root.add_child("ball");
        ball = &ball_node.add_state<Vec3Types>("ball");
        ball->position = {Vec3(0.6, 1.2, 0.9)};
        ball_node.set_mass<UniformMass<Vec3Types>>(*ball).set_vertex_mass(0.5);
        // rest length 0.4 for a distance of about 0.9: stretched
        root.add_force_field<SpringForceField>(*contact, *ball).add_spring({0, 0, 300.0, 0.0, 0.4});
        sim.init();
    }
};

TEST(SystemAssembly, TheStiffnessIsTheForcesDerivativeThroughTheMapping) {
    SystemAssemblyScene s;
    SubtreeSystem sys(s.sim.root());
    ASSERT_EQ(sys.size(), 3 * 3 + 3);
    // the springs keep the derivative of their last force (SOFA's addForce computes dfdx)
    sys.propagate_positions_and_velocities();
    Eigen::VectorXd f0;
    sys.compute_force(f0);
    const Eigen::MatrixXd k = Eigen::MatrixXd(sys.assemble(0.0, 1.0));
    ASSERT_GT(k.norm(), 100.0);
    // central differences of f over every independent coordinate
    const auto force = [&] {
        sys.propagate_positions_and_velocities();
        Eigen::VectorXd f;
        sys.compute_force(f);
        return f;
    };
    const double h = 1e-6;
    Eigen::MatrixXd fd(sys.size(), sys.size());
    for (Vec3Object* state : {s.body, s.ball}) {
        const Index offset = sys.offset(state);
        for (std::size_t i = 0; i < state->position.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                const double x = state->position[i][c];
                state->position[i][c] = x + h;
                const Eigen::VectorXd up = force();
                state->position[i][c] = x - h;
                const Eigen::VectorXd down = force();
                state->position[i][c] = x;
                fd.col(Eigen::Index(offset) + Eigen::Index(3 * i) + c) = (up - down) / (2 * h);
            }
    }
    EXPECT_LT((k - fd).cwiseAbs().maxCoeff(), 1e-6 * k.cwiseAbs().maxCoeff()) << "K\n" << k << "\nFD\n" << fd;
    // the contact spring couples the ball with every body point through the weights
    const Index ball = sys.offset(s.ball);
    const Index body = sys.offset(s.body);
    for (int i = 0; i < 3; ++i) EXPECT_NE(k(Eigen::Index(ball), Eigen::Index(body) + 3 * i), 0.0) << i;
    EXPECT_TRUE(k.isApprox(k.transpose(), 1e-12));
}

TEST(SystemAssembly, TheMassIsTheDiagonalOfTheIndependentStatesAndTheSumIsLinear) {
    SystemAssemblyScene s;
    SubtreeSystem sys(s.sim.root());
    sys.propagate_positions_and_velocities();
    Eigen::VectorXd f0;
    sys.compute_force(f0);
    const Eigen::MatrixXd m = Eigen::MatrixXd(sys.assemble(2.5, 0.0));
    Eigen::VectorXd expected(sys.size());
    const Index body = sys.offset(s.body);
    const Index ball = sys.offset(s.ball);
    expected.segment<9>(Eigen::Index(body)).setConstant(2.5 * 2.0);
    expected.segment<3>(Eigen::Index(ball)).setConstant(2.5 * 0.5);
    EXPECT_EQ(Eigen::VectorXd(m.diagonal()), expected);
    EXPECT_EQ(Eigen::MatrixXd(m - Eigen::MatrixXd(m.diagonal().asDiagonal())).cwiseAbs().maxCoeff(), 0.0);
    const Eigen::MatrixXd k = Eigen::MatrixXd(sys.assemble(0.0, 1.0));
    ASSERT_GT(k.norm(), 100.0);
    const Eigen::MatrixXd both = Eigen::MatrixXd(sys.assemble(2.5, -0.3));
    EXPECT_LT((both - (m - 0.3 * k)).cwiseAbs().maxCoeff(), 1e-12 * k.cwiseAbs().maxCoeff());
}

}  // namespace
}  // namespace penalty
