// The writers on a live scene, as `penalty run` uses them: SOFA's sphere-on-floor example E
// (contact pipeline, implicit Euler), records collected from the graph, contact records from the
// pipeline, state files, VTK series and statistics written every step.
#include "penalty/collision/models.hpp"
#include "penalty/mechanics/mass.hpp"
#include "penalty/output/contact_records.hpp"
#include "penalty/output/format.hpp"
#include "penalty/output/state_file.hpp"
#include "penalty/output/stats_csv.hpp"
#include "penalty/output/vtk_writer.hpp"
#include "penalty/simulation/solver.hpp"

#include "output_test_support.hpp"
#include "penalty_test/static_floor.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <tinyxml2.h>

namespace penalty::output {
namespace {

using test::read_text;
using test::TempDir;

/// SOFA's example E: a Vec3 sphere (vertex mass 1 kg, radius 0.5 m, k 10) at (0.2, 0.9, 0.3) over a
/// static two-triangle floor at y = 0; one contact spring, dist = 1 m, ks = 100 N/m.
struct SphereOnFloor {
    Simulation sim;
    penalty::test::StaticFloor floor{sim.root(), penalty::test::floor_params(10.0), "Floor"};
    Vec3Object* sphere = nullptr;
    std::unique_ptr<SphereModel> sphere_model;
    std::unique_ptr<ContactPipeline> pipeline;

    SphereOnFloor() {
        sim.root().set_gravity(Vec3(0, -9.81, 0));
        sim.root().set_dt(0.01);

        Node& body = sim.root().add_child("Sphere");
        auto& solver = body.set_ode_solver<EulerImplicitSolver>();
        solver.cg.iterations = 25;
        solver.cg.tolerance = 1e-9;
        solver.cg.threshold = 1e-9;
        sphere = &body.add_state<Vec3Types>("dofs");
        sphere->position = {Vec3(0.2, 0.9, 0.3)};
        body.set_mass<UniformMass<Vec3Types>>(*sphere).set_vertex_mass(1.0);
        CollisionModelParams sphere_params;
        sphere_params.name = "sphere";
        sphere_params.contact_stiffness = 10.0;
        sphere_model = std::make_unique<SphereModel>(*sphere, 0.5, std::vector<double>{}, sphere_params);
        pipeline = std::make_unique<ContactPipeline>(sim, IntersectionParams::new_proximity());
        pipeline->add_model(*floor.model, *floor.node);
        pipeline->add_model(*sphere_model, body);
    }
    ~SphereOnFloor() { pipeline.reset(); }
};

TEST(RunOutputs, SphereOnFloorWritesConsistentFiles) {
    TempDir dir;
    SphereOnFloor scene;
    scene.sim.init();

    std::vector<StateRecord> records = collect_state_records(scene.sim.root());
    ASSERT_EQ(records.size(), 2u);
    records[0].topology = &scene.floor.topology;
    EXPECT_EQ(state_label(records[0]), "/Floor/floor");
    EXPECT_EQ(state_label(records[1]), "/Sphere/dofs");
    const std::vector<const StateRecord*> exported = select_exported_states(records, false);
    ASSERT_EQ(exported.size(), 1u);  // the floor is outside every solver subtree
    EXPECT_EQ(exported[0]->state, scene.sphere);

    StateExporter states(dir.path() / "states", exported);
    std::vector<const StateRecord*> all;
    for (const StateRecord& r : records) all.push_back(&r);
    VtkSeriesWriter vtk(dir.path() / "vtk", all);
    StatsCsvWriter stats(dir.path() / "stats.csv");

    std::string expected_states;
    std::string expected_stats = std::string(stats_csv_header()) + "\n";
    const auto record_step = [&](std::int64_t step) {
        const double time = static_cast<double>(step) * 0.01;
        states.write(time);
        expected_states += "T= " + format_number(time) + "\n  X= " + format_positions(*scene.sphere) + "\n";
        const std::vector<ContactRecord> contacts = contact_records(*scene.pipeline);
        vtk.write_step(time, contacts);
        const ContactSummary summary = summarize_contacts(contacts);
        StepStats row;
        row.step = step;
        row.time = time;
        row.contacts = summary.contacts;
        row.active_contacts = summary.active_contacts;
        row.max_penetration = summary.max_penetration;
        row.contact_energy = summary.contact_energy;
        row.kinetic_energy = kinetic_energy(records);
        row.dissipated_energy = summary.dissipated_energy;
        stats.write(row);
        expected_stats += format_stats_row(row) + "\n";
        return summary;
    };
    const ContactSummary before = record_step(0);
    EXPECT_EQ(before.contacts, 0u);  // no detection before the first step
    for (std::int64_t step = 1; step <= 3; ++step) {
        scene.sim.step();
        const ContactSummary summary = record_step(step);
        EXPECT_EQ(summary.contacts, 1u);
        EXPECT_EQ(summary.active_contacts, 1u);
        // pen = dist − (y − 0) = 1 − y > 0 while the sphere sinks below y = 1
        EXPECT_NEAR(summary.max_penetration, 1.0 - scene.sphere->position[0].y(), 1e-12);
    }

    EXPECT_EQ(states.files()[0], dir.path() / "states" / "0_dofs_mstate.txt");
    EXPECT_EQ(read_text(states.files()[0]), expected_states);
    const auto samples = read_state_file(states.files()[0]);
    ASSERT_EQ(samples.size(), 4u);
    EXPECT_EQ(samples[3].x[1], scene.sphere->position[0].y());
    EXPECT_EQ(read_text(dir.path() / "stats.csv"), expected_stats);

    // our own run is its own reference
    const auto result = compare_with_reference(states.files(), states.files(), states.values_per_dof());
    EXPECT_TRUE(result.passed());

    // the contact piece of the last step: one line from the floor's contact point to the sphere
    const std::vector<ContactRecord> contacts = contact_records(*scene.pipeline);
    ASSERT_EQ(contacts.size(), 1u);
    EXPECT_EQ(contacts[0].name, "floor-sphere");
    EXPECT_EQ(contacts[0].state2, scene.sphere);
    tinyxml2::XMLDocument doc;
    ASSERT_EQ(doc.LoadFile(vtk.contacts_piece(3).string().c_str()), tinyxml2::XML_SUCCESS);
    const auto* piece = doc.FirstChildElement("VTKFile")->FirstChildElement("PolyData")->FirstChildElement("Piece");
    EXPECT_EQ(piece->IntAttribute("NumberOfLines"), 1);
    EXPECT_EQ(piece->IntAttribute("NumberOfPoints"), 2);
    // the floor piece has its two triangles
    tinyxml2::XMLDocument floor_doc;
    ASSERT_EQ(floor_doc.LoadFile(vtk.state_piece(0, 3).string().c_str()), tinyxml2::XML_SUCCESS);
    const auto* floor_piece =
        floor_doc.FirstChildElement("VTKFile")->FirstChildElement("UnstructuredGrid")->FirstChildElement("Piece");
    EXPECT_EQ(floor_piece->IntAttribute("NumberOfPoints"), 4);
    EXPECT_EQ(floor_piece->IntAttribute("NumberOfCells"), 2);
    EXPECT_EQ(vtk.step_count(), 4u);
}

}  // namespace
}  // namespace penalty::output
