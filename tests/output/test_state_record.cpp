// State records: SOFA's regression selection, collection from a scene graph, kinetic energy.
#include "penalty/mechanics/mass.hpp"
#include "penalty/output/state_record.hpp"
#include "penalty/output/stats_csv.hpp"
#include "penalty/simulation/node.hpp"
#include "penalty/simulation/solver.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace penalty::output {
namespace {

TEST(SelectExportedStates, KeepsSolverSubtreeAndMappedOnlyOnRequest) {
    std::vector<StateRecord> records(4);
    records[0] = {"static", "/", nullptr, nullptr, false, false, nullptr, {}};
    records[1] = {"dofs", "/A", nullptr, nullptr, false, true, nullptr, {}};
    records[2] = {"surface", "/A/S", nullptr, nullptr, true, true, nullptr, {}};
    records[3] = {"free", "/B", nullptr, nullptr, false, true, nullptr, {}};
    EXPECT_THAT(select_exported_states(records, false), ::testing::ElementsAre(&records[1], &records[3]));
    EXPECT_THAT(select_exported_states(records, true), ::testing::ElementsAre(&records[1], &records[2], &records[3]));
}

TEST(CollectStateRecords, DepthFirstPathsSolverSubtreeMappingAndMass) {
    Node root("root");
    auto& floor = root.add_state<Vec3Types>("floor");
    floor.position = {Vec3::Zero()};
    Node& a = root.add_child("A");
    a.set_ode_solver<EulerImplicitSolver>();
    auto& dofs = a.add_state<Vec3Types>("dofs");
    dofs.position = {Vec3(1, 2, 3)};
    auto& mass = a.set_mass<UniformMass<Vec3Types>>(dofs);
    Node& surface = a.add_child("S");
    auto& surface_dofs = surface.add_state<Vec3Types>("surface");
    surface.set_mapping<IdentityMapping>(dofs, surface_dofs);
    Node& b = root.add_child("B");
    auto& rigid = b.add_state<Rigid3Types>("rigid");
    Node& empty = b.add_child("Empty");  // no state: no record
    (void)empty;

    const std::vector<StateRecord> records = collect_state_records(root);
    ASSERT_EQ(records.size(), 4u);
    EXPECT_EQ(records[0].name, "floor");
    EXPECT_EQ(records[0].node_path, "/");
    EXPECT_EQ(records[0].state, &floor);
    EXPECT_FALSE(records[0].in_solver_subtree);
    EXPECT_EQ(records[1].node_path, "/A");
    EXPECT_EQ(records[1].state, &dofs);
    EXPECT_TRUE(records[1].in_solver_subtree);
    EXPECT_FALSE(records[1].mapped);
    EXPECT_EQ(records[1].mass, &mass);
    EXPECT_EQ(records[2].node_path, "/A/S");
    EXPECT_EQ(records[2].name, "surface");
    EXPECT_TRUE(records[2].mapped);
    EXPECT_TRUE(records[2].in_solver_subtree);
    EXPECT_EQ(records[2].mass, nullptr);
    EXPECT_EQ(records[3].node_path, "/B");
    EXPECT_EQ(records[3].state, &rigid);
    EXPECT_FALSE(records[3].in_solver_subtree);
    for (const StateRecord& r : records) EXPECT_EQ(r.topology, nullptr);

    EXPECT_EQ(state_label(records[0]), "/floor");
    EXPECT_EQ(state_label(records[2]), "/A/S/surface");
    EXPECT_EQ(values_per_dof(*records[1].state), 3);
    EXPECT_EQ(values_per_dof(*records[3].state), 7);
}

TEST(KineticEnergy, SumsTheMassesOfTheRecords) {
    Vec3Object a("a");
    a.position = {Vec3::Zero(), Vec3::Zero()};
    a.velocity = {Vec3(1, 0, 0), Vec3(0, 2, 0)};
    a.init();
    UniformMass<Vec3Types> mass_a(a);
    mass_a.set_vertex_mass(3.0);
    mass_a.init();
    Vec3Object b("b");  // no mass: not counted
    b.position = {Vec3::Zero()};
    b.velocity = {Vec3(100, 0, 0)};
    b.init();
    std::vector<StateRecord> records(2);
    records[0] = {"a", "/", &a, nullptr, false, true, &mass_a, {}};
    records[1] = {"b", "/B", &b, nullptr, true, true, nullptr, {}};
    // ½·3·(1 + 4) = 7.5 J
    EXPECT_DOUBLE_EQ(kinetic_energy(records), 7.5);
}

}  // namespace
}  // namespace penalty::output
