// CGLinearSolver's stopping rules (iterations, tolerance, threshold) as SOFA's.
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/simulation/solver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

namespace penalty {
namespace {

TEST(CGLinearSolver, StoppingRulesAndFirstSolveException) {
    CGLinearSolver cg;
    cg.tolerance = 0.5;
    cg.threshold = 0.0;
    const auto identity = [](const Eigen::VectorXd& p, Eigen::VectorXd& q) { q = p; };
    Eigen::VectorXd b = Eigen::VectorXd::Constant(3, 1.0);
    Eigen::VectorXd x;
    // First solve: err = 1 > 0.5 anyway; one step solves an identity system.
    auto s1 = cg.solve(identity, b, x);
    EXPECT_EQ(s1.end_condition, CgEndCondition::tolerance);
    EXPECT_EQ(s1.iterations, 2);
    EXPECT_TRUE(x.isApprox(b));
    // |b| = 0 -> x = 0.
    auto s0 = cg.solve(identity, Eigen::VectorXd::Zero(3), x);
    EXPECT_EQ(s0.end_condition, CgEndCondition::b_zero);
    EXPECT_EQ(x, Eigen::VectorXd::Zero(3));
    // Tolerance 2: from the second solve on, stop before any update.
    CGLinearSolver cg2;
    cg2.tolerance = 2.0;
    auto f1 = cg2.solve(identity, b, x);
    EXPECT_TRUE(x.isApprox(b)) << "first solve exempt at k=1";
    EXPECT_EQ(f1.iterations, 2);
    auto f2 = cg2.solve(identity, b, x);
    EXPECT_EQ(f2.end_condition, CgEndCondition::tolerance);
    EXPECT_EQ(f2.iterations, 1);
    EXPECT_EQ(x, Eigen::VectorXd::Zero(3));
    // Iteration cap on an ill-conditioned diagonal system.
    CGLinearSolver cg3;
    cg3.iterations = 2;
    cg3.tolerance = 0;
    cg3.threshold = 0;
    Eigen::VectorXd d(4);
    d << 1, 10, 100, 1000;
    auto s3 = cg3.solve([&](const Eigen::VectorXd& p, Eigen::VectorXd& q) { q = d.cwiseProduct(p); },
                        Eigen::VectorXd::Ones(4), x);
    EXPECT_EQ(s3.end_condition, CgEndCondition::iterations);
    EXPECT_EQ(s3.iterations, 2);
    EXPECT_GT((d.cwiseProduct(x) - Eigen::VectorXd::Ones(4)).norm(), 1e-3);
    CGLinearSolver bad;
    bad.iterations = 0;
    EXPECT_THROW(bad.solve(identity, b, x), std::invalid_argument);
}

TEST(CGLinearSolver, EndConditionNamesAreSofasWords) {
    // The names printed (run reports, `penalty run --report`) are SOFA's log words.
    EXPECT_EQ(cg_end_condition_name(CgEndCondition::none), "none");
    EXPECT_EQ(cg_end_condition_name(CgEndCondition::iterations), "iterations");
    EXPECT_EQ(cg_end_condition_name(CgEndCondition::tolerance), "tolerance");
    EXPECT_EQ(cg_end_condition_name(CgEndCondition::threshold), "threshold");
    EXPECT_EQ(cg_end_condition_name(CgEndCondition::den_zero), "den=0");
    EXPECT_EQ(cg_end_condition_name(CgEndCondition::b_zero), "b=0");
    std::ostringstream out;
    out << CgEndCondition::den_zero << " " << CgEndCondition::b_zero;
    EXPECT_EQ(out.str(), "den=0 b=0");
}

}  // namespace
}  // namespace penalty
