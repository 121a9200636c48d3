// Bad input never crashes, hangs or gives a silent NaN: every attribute of valid scenes is
// replaced in turn by hostile values; building and running a few steps must either work (with
// finite states) or throw an error that names the file and line.
#include "penalty/io/error.hpp"
#include "penalty/output/format.hpp"
#include "penalty/scene/runner.hpp"
#include "penalty/scene/scene.hpp"

#include <gtest/gtest.h>

#include <regex>
#include <string>
#include <vector>

namespace {

using namespace penalty;

const char* const kHostileValues[] = {"",         "-1", "nan", "inf",         "1e400",   "abc",
                                      "@nowhere", "0",  "1 2", "99999999999", "-0.5 0 0"};

const std::string kRigidAndGrid = R"(<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <CollisionPipeline/><BruteForceBroadPhase/><BVHNarrowPhase/>
  <NewProximityIntersection alarmDistance="0.3" contactDistance="0.1"/>
  <CollisionResponse response="PenalityContactForceField" responseParams="damping=1"/>
  <Node name="Grid">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="25" tolerance="1e-9" threshold="1e-9"/>
    <RegularGridTopology nx="3" ny="3" nz="3" xmin="-0.5" xmax="0.5" ymin="0" ymax="1" zmin="-0.5" zmax="0.5"/>
    <MechanicalObject name="grid" dy="0.2"/>
    <UniformMass totalMass="1"/>
    <TetrahedronFEMForceField youngModulus="500" poissonRatio="0.3" method="large"/>
    <FixedProjectiveConstraint indices="0"/>
    <SphereCollisionModel name="grid_spheres" radius="0.1" contactStiffness="5"/>
    <Node name="Surface">
      <MechanicalObject name="surface" position="0 0.5 0  0.2 0.5 0.1"/>
      <BarycentricMapping/>
    </Node>
  </Node>
  <Node name="Ball">
    <EulerImplicitSolver/><CGLinearSolver/>
    <MechanicalObject name="ball" template="Rigid3d" position="0 1.5 0  0 0 0 1"/>
    <UniformMass totalMass="0.5"/>
    <Node name="Collision">
      <MechanicalObject name="points"/>
      <SphereCollisionModel name="ball_sphere" radius="0.2"/>
      <IdentityMapping input="@../ball" output="@points"/>
    </Node>
  </Node>
  <Node name="Floor">
    <MeshTopology position="-2 0 -2  2 0 -2  2 0 2  -2 0 2" triangles="0 2 1  0 3 2"/>
    <MechanicalObject name="floor"/>
    <TriangleCollisionModel name="floor_triangles" simulated="0" moving="0"/>
    <LineCollisionModel name="floor_lines" simulated="0" moving="0"/>
    <PointCollisionModel name="floor_points" simulated="0" moving="0"/>
  </Node>
</Node>)";

/// Positions of the attribute values in the XML text: (offset of the value, length).
std::vector<std::pair<std::size_t, std::size_t>> attribute_values(const std::string& xml) {
    std::vector<std::pair<std::size_t, std::size_t>> out;
    const std::regex attr(R"(\s([A-Za-z_]+)="([^"]*)\")");
    for (auto it = std::sregex_iterator(xml.begin(), xml.end(), attr); it != std::sregex_iterator(); ++it) {
        if ((*it)[1] == "name") continue;  // names are free text
        out.emplace_back(std::size_t(it->position(2)), std::size_t(it->length(2)));
    }
    return out;
}

TEST(SceneRobustness, HostileAttributeValuesGiveErrorsNamingFileAndLine) {
    const auto values = attribute_values(kRigidAndGrid);
    ASSERT_EQ(values.size(), 43u);  // every attribute but the names
    std::size_t built = 0, rejected = 0, diverged = 0;
    const std::regex located(R"(^robust\.scn:\d+: .+)");
    for (const auto& [offset, length] : values) {
        for (const char* hostile : kHostileValues) {
            std::string xml = kRigidAndGrid;
            xml.replace(offset, length, hostile);
            SCOPED_TRACE(xml.substr(offset > 60 ? offset - 60 : 0, 100));
            try {
                auto scene = scene::build_scene(io::parse_scene_string(xml, "robust.scn"));
                scene::RunOptions run;
                run.steps = 3;
                (void)scene::run_scene(*scene, run);  // checks every state is finite after each step
                ++built;
            } catch (const io::SceneError& e) {
                EXPECT_TRUE(std::regex_search(std::string(e.what()), located)) << e.what();
                ++rejected;
            } catch (const output::NonFiniteValueError& e) {
                ++diverged;  // e.g. dt = 1e400 is rejected as a number, dt = 99999999999 may blow up
                EXPECT_NE(std::string(e.what()).find("simulation diverged"), std::string::npos) << e.what();
            } catch (const std::exception& e) {
                ADD_FAILURE() << "unexpected " << typeid(e).name() << ": " << e.what();
            }
        }
    }
    // Both outcomes must really happen, or the test proves nothing.
    EXPECT_GT(rejected, values.size() * 3);
    EXPECT_GT(built, values.size());
    RecordProperty("built", int(built));
    RecordProperty("rejected", int(rejected));
    RecordProperty("diverged", int(diverged));
}

TEST(SceneRobustness, HugeSizesAreRefusedBeforeAllocating) {
    auto error_of = [](const std::string& xml) -> std::string {
        try {
            (void)scene::build_scene(io::parse_scene_string(xml, "huge.scn"));
        } catch (const io::SceneError& e) {
            return e.what();
        }
        return "no error";
    };
    EXPECT_EQ(error_of(R"(<Node name="root">
  <RegularGridTopology nx="100000" ny="100000" nz="100000"/>
  <MechanicalObject/>
</Node>)"),
              "huge.scn:2: RegularGridTopology: 1000000000000000 grid points (more than 10000000)");
    EXPECT_EQ(error_of(R"(<Node name="root">
  <MechanicalObject size="5000000000000"/>
</Node>)"),
              "huge.scn:2: MechanicalObject: attribute 'size': must be between 0 and 10000000");
    EXPECT_EQ(error_of(R"(<Node name="root">
  <EulerImplicitSolver/>
  <CGLinearSolver iterations="99999999999" tolerance="0" threshold="0"/>
</Node>)"),
              "huge.scn:3: CGLinearSolver: attribute 'iterations': must be between 1 and 1000000");
}

TEST(SceneRobustness, SpringIndicesBeyondAPointIndexAreRefusedAsTheAttribute) {
    // SpringForceField's `spring` list is read as numbers: an index past PointId's range (which
    // no integer type of the springs could hold, 2⁶³ here) is the attribute's error, like
    // indices1/indices2's, not a conversion out of range
    const auto error_of = [](const std::string& spring) -> std::string {
        try {
            (void)scene::build_scene(io::parse_scene_string(R"(<Node name="root">
  <EulerImplicitSolver/><CGLinearSolver/>
  <MechanicalObject position="0 0 0  1 0 0"/>
  <UniformMass totalMass="1"/>
  <SpringForceField spring=")" + spring + R"("/>
</Node>)",
                                                            "springs.scn"));
        } catch (const io::SceneError& e) {
            return e.what();
        }
        return "no error";
    };
    const std::string refused =
        "springs.scn:5: SpringForceField: attribute 'spring': indices must be integers from 0 to 2147483647";
    EXPECT_EQ(error_of("0 9223372036854775808 100 1 1"), refused);
    EXPECT_EQ(error_of("2147483648 1 100 1 1"), refused);
    EXPECT_EQ(error_of("0 -1 100 1 1"), refused);
    EXPECT_EQ(error_of("0 1.5 100 1 1"), refused);
    EXPECT_EQ(error_of("0 1 100 1 1"), "no error");
    // in PointId's range but past the state: the force field's own check at init
    EXPECT_NE(error_of("0 2147483647 100 1 1").find("out of range for states of 2 and 2 DOFs"), std::string::npos);
}

}  // namespace
