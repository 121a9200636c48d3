// State of the contact path is owned, not global (issue 14 item 4): node identities come from
// Node::id() (unique in a graph, never reused), and ContactPipeline detects through its own
// CollisionPipeline (the one detection driver), whose result it exposes.

#include "penalty/collision/models.hpp"
#include "penalty/simulation/contact_pipeline.hpp"

#include <gtest/gtest.h>

namespace penalty {
namespace {

CollisionModelParams named(const char* name) {
    CollisionModelParams p;
    p.name = name;
    return p;
}

TEST(NodeId, UniqueInItsGraphInCreationOrderAndNeverReused) {
    Simulation sim;
    EXPECT_EQ(sim.root().id(), 0);
    Node& a = sim.root().add_child("a");
    Node& b = a.add_child("b");
    Node& c = sim.root().add_child("c");
    EXPECT_EQ(a.id(), 1);
    EXPECT_EQ(b.id(), 2);
    EXPECT_EQ(c.id(), 3);
    ASSERT_TRUE(a.remove_child(&b));
    EXPECT_EQ(a.add_child("b again").id(), 4);  // a removed node's id is not given again
    Simulation other;                           // another graph numbers its own nodes
    EXPECT_EQ(other.root().add_child("a").id(), 1);
}

TEST(ContactPipelineState, ModelsWithoutNodeIdGetTheirNodesIdentity) {
    Simulation sim;
    Node& body = sim.root().add_child("body");
    Node& other = sim.root().add_child("other");
    auto& s1 = body.add_state<Vec3Types>("s1");
    auto& s2 = other.add_state<Vec3Types>("s2");
    s1.position = {Vec3(0, 0, 0), Vec3(0.05, 0, 0)};
    s2.position = {Vec3(0, 0.05, 0)};
    PointModel pts(s1, nullptr, named("points"));
    SphereModel sph(s1, 0.01, std::vector<double>{}, named("spheres"));
    PointModel far(s2, nullptr, named("far"));
    CollisionModelParams fixed = named("numbered");
    fixed.node = 7;  // set by the caller (the scene builder numbers its nodes): kept
    PointModel numbered(s2, nullptr, fixed);
    ContactPipeline pipeline(sim);
    pipeline.add_model(pts, body);
    pipeline.add_model(sph, body);
    pipeline.add_model(far, other);
    pipeline.add_model(numbered, other);
    EXPECT_EQ(pts.params().node, kAutoNodeIdBase + body.id());
    EXPECT_EQ(sph.params().node, kAutoNodeIdBase + body.id());
    EXPECT_EQ(far.params().node, kAutoNodeIdBase + other.id());
    EXPECT_EQ(numbered.params().node, 7);
    EXPECT_TRUE(same_node(pts, sph));  // same node: no pair without self-collision
    EXPECT_FALSE(same_node(pts, far));
    // a second pipeline of the same simulation gives the same identity
    ContactPipelineOptions no_hook;
    no_hook.register_stage = false;  // run by nobody: only its models' identity is checked
    ContactPipeline second(sim, IntersectionParams::new_proximity(), CollisionResponse(), nullptr, no_hook);
    PointModel again(s1, nullptr, CollisionModelParams{});
    second.add_model(again, body);
    EXPECT_TRUE(same_node(again, pts));
}

TEST(ContactPipelineState, DetectionsAreTheDriversResult) {
    Simulation sim;
    Node& a = sim.root().add_child("a");
    Node& b = sim.root().add_child("b");
    auto& sa = a.add_state<Vec3Types>("sa");
    auto& sb = b.add_state<Vec3Types>("sb");
    sa.position = {Vec3(0, 0, 0)};
    sb.position = {Vec3(0.3, 0, 0)};  // 0.3 apart: within NewProximity's alarm distance 1
    SphereModel ma(sa, 0.1, std::vector<double>{}, named("a"));
    SphereModel mb(sb, 0.1, std::vector<double>{}, named("b"));
    ContactPipeline pipeline(sim);
    pipeline.add_model(ma, a);
    pipeline.add_model(mb, b);
    pipeline.update();
    ASSERT_EQ(pipeline.collision().models().size(), 2u);
    EXPECT_EQ(&pipeline.detections(), &pipeline.collision().detections());
    // (b, a): no self pairs without selfCollision; two models of one type are keyed (later,
    // earlier), as SOFA's BruteForceBroadPhase::addCollisionModel pairs a new model with each
    // model added before it
    ASSERT_EQ(pipeline.detections().size(), 1u);
    EXPECT_EQ(pipeline.detections()[0].model1, &mb);
    EXPECT_EQ(pipeline.detections()[0].model2, &ma);
    ASSERT_EQ(pipeline.detections()[0].outputs.size(), 1u);
    EXPECT_NEAR(pipeline.detections()[0].outputs[0].value, 0.3 - 0.2 - 0.5, 1e-15);  // dist − radii − C
    EXPECT_EQ(pipeline.graph_entries().size(), 1u);
}

}  // namespace
}  // namespace penalty
