#pragma once
/// @file
/// Two force fields that must act alike (a follower after a topological change against the same
/// component built fresh on the changed mesh): the same displaced positions and dx in both
/// states, then forces, add_dforce(k = 0.7) and the assembled stiffness compared to the bit.

#include "penalty/core/types.hpp"
#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/mechanical_object.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace penalty::test {

/// Positions displaced from each state's rest shape by the same amounts, and the same dx.
inline void displace_alike(Vec3Object& a, Vec3Object& b) {
    ASSERT_EQ(a.num_dofs(), b.num_dofs());
    for (std::size_t i = 0; i < a.num_dofs(); ++i) {
        const Vec3 d(0.01 * double(i % 3), -0.02 + 0.001 * double(i), 0.005 * double(i % 5));
        a.position[i] = a.rest_position[i] + d;
        b.position[i] = b.rest_position[i] + d;
        a.dx[i] = b.dx[i] = Vec3(1.0 + double(i), -0.5, 0.25 * double(i % 4));
    }
}

/// Forces, add_dforce and the assembled matrix of `a` (on `xa`) and `b` (on `xb`) at the same
/// displaced positions: equal to the bit, and the forces not all zero.
inline void expect_same_forces(BaseForceField& a, Vec3Object& xa, BaseForceField& b, Vec3Object& xb) {
    displace_alike(xa, xb);
    for (Vec3Object* s : {&xa, &xb}) {
        std::fill(s->force.begin(), s->force.end(), Vec3::Zero());
        std::fill(s->df.begin(), s->df.end(), Vec3::Zero());
    }
    a.accumulate_force();
    b.accumulate_force();
    a.accumulate_dforce(0.7, 0.0);
    b.accumulate_dforce(0.7, 0.0);
    EXPECT_EQ(xa.force, xb.force);
    EXPECT_EQ(xa.df, xb.df);
    double norm = 0;
    for (const Vec3& f : xa.force) norm += f.norm();
    EXPECT_GT(norm, 0.0);  // not vacuous
    TripletList ta;
    TripletList tb;
    a.add_stiffness(
        ta, [](const BaseState*) { return Index{0}; }, 1.0);
    b.add_stiffness(
        tb, [](const BaseState*) { return Index{0}; }, 1.0);
    const auto n = Index(3 * xa.num_dofs());
    SparseMatrix ka(n, n);
    SparseMatrix kb(n, n);
    ka.setFromTriplets(ta.begin(), ta.end());
    kb.setFromTriplets(tb.begin(), tb.end());
    EXPECT_EQ(Eigen::MatrixXd(ka), Eigen::MatrixXd(kb));
}

}  // namespace penalty::test
