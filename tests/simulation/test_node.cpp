// Node (simulation/node.cpp): moving force fields to the end of a node's list, as SOFA re-adds
// contact force fields each step.
#include "penalty/mechanics/spring_force_field.hpp"
#include "penalty/simulation/solver.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace penalty {
namespace {

TEST(Node, MoveForceFieldsToEndReordersOnlyWhenNeededAndNamesMisuse) {
    // SOFA re-adds the contact force fields of a node at each step in contact-map order:
    // the listed fields go to the end in the given order, the others keep theirs, and a list
    // already in place changes nothing (no new structure version, so no system rebuild).
    Simulation sim;
    Node& n = sim.root().add_child("n");
    auto& x = n.add_state<Vec3Types>();
    x.position = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
    auto& a = n.add_force_field<SpringForceField>(x, x);
    auto& b = n.add_force_field<SpringForceField>(x, x);
    auto& c = n.add_force_field<SpringForceField>(x, x);
    const auto order = [&] {
        std::vector<const BaseForceField*> o;
        for (const auto& f : n.force_fields()) o.push_back(f.get());
        return o;
    };
    const std::uint64_t v0 = n.structure_version();
    std::vector<BaseForceField*> moved = {&c, &a};
    n.move_force_fields_to_end(moved);
    EXPECT_EQ(order(), (std::vector<const BaseForceField*>{&b, &c, &a}));
    const std::uint64_t v1 = n.structure_version();
    EXPECT_GT(v1, v0);
    n.move_force_fields_to_end(moved);  // already at the end in that order
    EXPECT_EQ(order(), (std::vector<const BaseForceField*>{&b, &c, &a}));
    EXPECT_EQ(n.structure_version(), v1);
    // a field of another node, or one listed twice: an error naming the node, nothing moved
    Node& other = sim.root().add_child("other");
    auto& y = other.add_state<Vec3Types>();
    y.position = {Vec3(0, 0, 0)};
    auto& foreign = other.add_force_field<SpringForceField>(y, y);
    std::vector<BaseForceField*> bad = {&b, &foreign};
    try {
        n.move_force_fields_to_end(bad);
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("Node 'n'"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("not a force field of this node"), std::string::npos) << e.what();
    }
    std::vector<BaseForceField*> twice = {&a, &a};
    EXPECT_THROW(n.move_force_fields_to_end(twice), std::invalid_argument);
    EXPECT_EQ(order(), (std::vector<const BaseForceField*>{&b, &c, &a}));
}

}  // namespace
}  // namespace penalty
