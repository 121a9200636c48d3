// The contacts of a ContactPipeline as the writers see them (contact_records.cpp): one record per
// live pair, in the graph's order, named "<model 1>-<model 2>", pointing at the pair's penalty
// field and the contact-point states it acts on. Two spheres over SOFA's example E floor: the
// sphere of radius 0.5 and stiffness 10 at height 0.9 is one spring of rest length 1 m.
#include "penalty/collision/models.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/output/contact_records.hpp"
#include "penalty/simulation/solver.hpp"
#include "penalty_test/static_floor.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

namespace penalty::output {
namespace {

/// Two Vec3 spheres (1 kg, radius 0.5, k 10) named `left` and `right` over the static floor y = 0.
struct TwoSpheresOnFloor {
    Simulation sim;
    penalty::test::StaticFloor floor{sim.root(), penalty::test::floor_params(10.0), "Floor"};
    std::vector<Vec3Object*> spheres;
    std::vector<std::unique_ptr<SphereModel>> models;
    std::unique_ptr<ContactPipeline> pipeline;

    TwoSpheresOnFloor() {
        sim.root().set_gravity(Vec3(0, -9.81, 0));
        sim.root().set_dt(0.01);
        pipeline = std::make_unique<ContactPipeline>(sim, IntersectionParams::new_proximity());
        pipeline->add_model(*floor.model, *floor.node);
        for (const char* name : {"left", "right"}) {
            Node& body = sim.root().add_child(std::string("Sphere_") + name);
            auto& solver = body.set_ode_solver<EulerImplicitSolver>();
            solver.cg.iterations = 25;
            Vec3Object& dofs = body.add_state<Vec3Types>("dofs");
            dofs.position = {Vec3(name[0] == 'l' ? -3.0 : 4.0, 0.9, 0.1)};
            body.set_mass<UniformMass<Vec3Types>>(dofs).set_vertex_mass(1.0);
            CollisionModelParams params;
            params.name = name;
            params.contact_stiffness = 10.0;
            models.push_back(std::make_unique<SphereModel>(dofs, 0.5, std::vector<double>{}, params));
            pipeline->add_model(*models.back(), body);
            spheres.push_back(&dofs);
        }
    }
    ~TwoSpheresOnFloor() { pipeline.reset(); }
};

TEST(ContactRecords, OneRecordPerLivePairNamedByItsModelsInTheGraphsOrder) {
    TwoSpheresOnFloor scene;
    scene.sim.init();
    EXPECT_TRUE(contact_records(*scene.pipeline).empty());  // no detection before the first step
    scene.sim.step();
    const std::vector<ContactRecord> records = contact_records(*scene.pipeline);
    const auto& entries = scene.pipeline->graph_entries();
    ASSERT_EQ(records.size(), 2u);
    ASSERT_EQ(entries.size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
        SCOPED_TRACE(i);
        const ContactGraphEntry& entry = entries[i];
        const ContactRecord& record = records[i];
        EXPECT_EQ(record.name, "floor-" + entry.contact->model2().name());
        EXPECT_EQ(record.field, &entry.contact->force_field());
        EXPECT_EQ(record.state1, entry.point_states[0]);
        EXPECT_EQ(record.state2, entry.point_states[1]);
        // one spring, rest length dist = 0.5 + 0.5 (radius and the NewProximity contact
        // distance), ks = k_floor·k_sphere/dist = 100 N/m; its points: the floor's contact point
        // below the sphere's centre and the sphere's own DOF
        ASSERT_EQ(record.field->size(), 1u);
        const PenaltyContact& spring = record.field->contacts()[0];
        EXPECT_EQ(spring.dist, 1.0);
        EXPECT_EQ(spring.ks, 100.0);
        const Vec3Object* sphere = scene.spheres[record.name == "floor-left" ? 0 : 1];
        EXPECT_EQ(record.state2, sphere) << "a Vec3 sphere's contact point is its DOF";
        ASSERT_EQ(record.state1->position.size(), 1u);
        EXPECT_EQ(record.state1->position[0].y(), 0.0);
        EXPECT_EQ(record.state1->position[0].x(), sphere->position[0].x());
    }
    // one record each (in the graph's order, which the pipeline sets)
    EXPECT_NE(records[0].name, records[1].name);
    // the right sphere lifted beyond the alarm distance: its pair ends, one record is left
    scene.spheres[1]->position[0].y() = 5.0;
    scene.sim.step();
    const std::vector<ContactRecord> after = contact_records(*scene.pipeline);
    ASSERT_EQ(after.size(), 1u);
    EXPECT_EQ(after[0].name, "floor-left");
    EXPECT_EQ(after[0].state2, scene.spheres[0]);
}

// is_record_of: a record is its entry's only with the same field, point states and name; a name
// of other models, or a longer one that starts with the right one, is not.
TEST(ContactRecords, ARecordIsItsEntrysWhenFieldStatesAndNameMatch) {
    TwoSpheresOnFloor scene;
    scene.sim.init();
    scene.sim.step();
    const auto& entries = scene.pipeline->graph_entries();
    ASSERT_EQ(entries.size(), 2u);
    const ContactRecord record = contact_record(entries[0]);
    EXPECT_TRUE(is_record_of(record, entries[0]));
    EXPECT_FALSE(is_record_of(record, entries[1]));
    const std::string own = record.name, other = "floor-" + entries[1].contact->model2().name();
    for (const std::string& name :
         std::vector<std::string>{own + "s", own.substr(0, own.size() - 1), "floor_" + own.substr(6), "", other}) {
        ContactRecord renamed = record;
        renamed.name = name;
        EXPECT_FALSE(is_record_of(renamed, entries[0])) << name;
    }
    ContactRecord other_states = record;
    std::swap(other_states.state1, other_states.state2);
    EXPECT_FALSE(is_record_of(other_states, entries[0]));
}

}  // namespace
}  // namespace penalty::output
