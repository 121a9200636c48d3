// The component registry (penalty/scene/components.hpp): each type declared once, defaults that
// parse and agree with the library's own, every attribute the builder reads declared, the
// unread-attribute notes, and `penalty info --components`.
#include "penalty/collision/intersection.hpp"
#include "penalty/io/error.hpp"
#include "penalty/scene/components.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty/simulation/solver.hpp"
#include "penalty_test/component_defaults.hpp"
#include "penalty_test/paths.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace {

using namespace penalty;
using namespace penalty::scene;
using penalty::test::default_number;
using ::testing::HasSubstr;

bool is_scene_dependent(std::string_view default_value) {
    return !default_value.empty() && default_value.front() == '(';
}

TEST(ComponentRegistry, EachTypeOnceEachAttributeOncePhysicsIsBuilt) {
    std::set<std::string_view> types;
    std::size_t physics = 0;
    for (const ComponentSpec& s : component_registry()) {
        EXPECT_TRUE(types.insert(s.type).second) << "declared twice: " << s.type;
        EXPECT_FALSE(s.summary.empty()) << s.type;
        std::set<std::string_view> names;
        for (std::span<const AttributeSpec> list : {s.attributes, s.shared_attributes})
            for (const AttributeSpec& a : list) EXPECT_TRUE(names.insert(a.name).second) << s.type << "." << a.name;
        if (category_of(s.family) == ComponentCategory::physics) {
            ++physics;
            EXPECT_NE(s.build, nullptr) << s.type;
        } else {
            EXPECT_EQ(s.build, nullptr) << s.type;
        }
    }
    EXPECT_EQ(physics, 159u);  // the physics types of docs/sofa-compatibility.md and docs/components/
    EXPECT_EQ(component_category("TriangleCollisionModel"), ComponentCategory::physics);
    EXPECT_EQ(component_category("SphereLoader"), ComponentCategory::loader);
    EXPECT_EQ(component_category("OglModel"), ComponentCategory::ignored);
    EXPECT_EQ(component_category("FancyForceField"), std::nullopt);
}

TEST(ComponentRegistry, WrittenDefaultsParseAsTheirKind) {
    std::size_t checked = 0;
    for (const ComponentSpec& s : component_registry()) {
        for (std::span<const AttributeSpec> list : {s.attributes, s.shared_attributes}) {
            for (const AttributeSpec& a : list) {
                if (a.default_value.empty() || is_scene_dependent(a.default_value)) continue;
                std::istringstream in{std::string(a.default_value)};
                double x = 0, y = 0, z = 0;
                switch (a.kind) {
                    case AttributeKind::real:
                    case AttributeKind::integer:
                    case AttributeKind::boolean:
                        EXPECT_TRUE(in >> x && (in >> std::ws).eof())
                            << s.type << "." << a.name << " = " << a.default_value;
                        if (a.kind == AttributeKind::boolean) {
                            EXPECT_TRUE(x == 0 || x == 1) << s.type << "." << a.name;
                        }
                        if (a.check == ValueCheck::positive) {
                            EXPECT_GT(x, 0) << s.type << "." << a.name;
                        }
                        if (a.check == ValueCheck::nonnegative) {
                            EXPECT_GE(x, 0) << s.type << "." << a.name;
                        }
                        ++checked;
                        break;
                    case AttributeKind::vector3:
                        EXPECT_TRUE(in >> x >> y >> z && (in >> std::ws).eof()) << s.type << "." << a.name;
                        ++checked;
                        break;
                    default:
                        break;
                }
            }
        }
    }
    EXPECT_GT(checked, 60u);
}

// The registry's defaults are what a scene gets; the library has its own for direct users. They
// must agree (SOFA's defaults, spec §6).
TEST(ComponentRegistry, DefaultsAgreeWithTheLibrary) {
    const CollisionModelParams model;
    for (const char* t : {"PointCollisionModel", "LineCollisionModel", "TriangleCollisionModel", "SphereCollisionModel",
                          "CylinderCollisionModel", "TetrahedronCollisionModel"}) {
        SCOPED_TRACE(t);
        EXPECT_EQ(default_number(t, "contactStiffness"), model.contact_stiffness);
        EXPECT_EQ(default_number(t, "proximity"), model.contact_distance);
        EXPECT_EQ(default_number(t, "active"), double(model.active));
        EXPECT_EQ(default_number(t, "moving"), double(model.moving));
        EXPECT_EQ(default_number(t, "simulated"), double(model.simulated));
        EXPECT_EQ(default_number(t, "selfCollision"), double(model.self_collision));
        EXPECT_EQ(default_number(t, "bothSide"), double(model.both_side));
    }
    const IntersectionParams np = IntersectionParams::new_proximity();
    const IntersectionParams mp = IntersectionParams::min_proximity();
    const IntersectionParams lmd = IntersectionParams::local_min_distance();
    for (const auto& [type, p] : {std::pair{"NewProximityIntersection", np}, std::pair{"MinProximityIntersection", mp},
                                  std::pair{"LocalMinDistance", lmd}}) {
        SCOPED_TRACE(type);
        EXPECT_EQ(default_number(type, "alarmDistance"), p.alarm_distance);
        EXPECT_EQ(default_number(type, "contactDistance"), p.contact_distance);
    }
    EXPECT_EQ(default_number("NewProximityIntersection", "useLineLine"), double(np.use_line_line));
    EXPECT_EQ(default_number("MinProximityIntersection", "useLineLine"), double(mp.use_line_line));
    EXPECT_EQ(default_number("MinProximityIntersection", "useSphereTriangle"), double(mp.use_sphere_triangle));
    EXPECT_EQ(default_number("MinProximityIntersection", "usePointPoint"), double(mp.use_point_point));
    EXPECT_EQ(default_number("MinProximityIntersection", "useLinePoint"), double(mp.use_line_point));
    EXPECT_EQ(default_number("MinProximityIntersection", "useSurfaceNormals"), double(mp.use_surface_normals));
    EXPECT_EQ(default_number("LocalMinDistance", "filterIntersection"), double(lmd.filter_intersection));
    EXPECT_EQ(default_number("LocalMinDistance", "angleCone"), lmd.angle_cone);
    EXPECT_EQ(default_number("LocalMinDistance", "coneFactor"), lmd.cone_factor);
    EXPECT_EQ(default_number("LocalMinDistance", "useLMDFilters"), double(lmd.use_lmd_filters));
    const CGLinearSolver cg;
    EXPECT_EQ(default_number("CGLinearSolver", "iterations"), double(cg.iterations));
    EXPECT_EQ(default_number("CGLinearSolver", "tolerance"), cg.tolerance);
    EXPECT_EQ(default_number("CGLinearSolver", "threshold"), cg.threshold);
    const EulerImplicitSolver implicit;
    EXPECT_EQ(default_number("EulerImplicitSolver", "newtonIterations"), double(implicit.newton.max_iterations));
    EXPECT_EQ(default_number("EulerImplicitSolver", "newtonTolerance"), implicit.newton.tolerance);
}

// A scene that sets every declared attribute of a component to a bad value gets an error naming
// that attribute, never a logic_error: the builder reads only declared attributes, and each of
// them is reachable from a scene.
TEST(ComponentRegistry, UnreadAttributesAreReportedPerElement) {
    const auto s =
        build_scene(io::parse_scene_string("<Node name='root' dt='0.01' color='1' frobnicate='2'>\n"
                                           "  <MeshOBJLoader name='loader' filename='none.obj' whatever='1'/>\n"
                                           "  <Node name='A'>\n"
                                           "    <MechanicalObject position='0 0 0' velocty='1 0 0'/>\n"
                                           "    <UniformMass vertexMass='1' showAxisSizeFactor='2'/>\n"
                                           "  </Node>\n</Node>\n",
                                           "unread.scn"));
    const std::vector<std::string> w = s->warnings();
    const auto count = [&](const std::string& needle) {
        return std::count_if(w.begin(), w.end(),
                             [&](const std::string& x) { return x.find(needle) != std::string::npos; });
    };
    EXPECT_EQ(count("unread.scn:1: Node 'root': attribute 'frobnicate' is not read by penalty (ignored)"), 1);
    EXPECT_EQ(count("unread.scn:4: MechanicalObject: attribute 'velocty' is not read by penalty (ignored)"), 1);
    EXPECT_EQ(count("'color'"), 0);               // display only: accepted silently
    EXPECT_EQ(count("'showAxisSizeFactor'"), 0);  // display only
    EXPECT_EQ(count("'whatever'"), 0);            // a loader nobody uses is ignored as a whole
    EXPECT_EQ(unread_attributes(*s->file().root->components[0]), std::vector<std::string>{"whatever"});
}

TEST(ComponentRegistry, ReadAttributesListsOwnThenShared) {
    const std::vector<std::string> mass = read_attributes("UniformMass");
    EXPECT_EQ(mass, (std::vector<std::string>{"vertexMass", "totalMass", "inertiaMatrix", "filename"}));
    const std::vector<std::string> node = read_attributes("Node");
    EXPECT_EQ(node, (std::vector<std::string>{"dt", "gravity"}));
    const std::vector<std::string> triangle = read_attributes("TriangleCollisionModel");
    EXPECT_EQ(triangle.size(), 14u);
    EXPECT_EQ(triangle[0], "topology");
    EXPECT_EQ(triangle[1], "computeNormals");
    EXPECT_EQ(triangle[8], "contactStiffness");
    EXPECT_TRUE(read_attributes("OglModel").empty());
    EXPECT_TRUE(read_attributes("NoSuchType").empty());
}

TEST(ComponentRegistry, InfoListsAttributesWithKindUnitCheckAndDefault) {
    const std::string mass = describe_components("UniformMass");
    EXPECT_THAT(mass, HasSubstr("masses:\n  UniformMass: uniform mass\n"));
    EXPECT_THAT(mass,
                HasSubstr("    vertexMass (text, kg): mass of each DOF (or totalMass), > 0; Rigid3d: `m` or SOFA's "
                          "Rigid3Mass `m volume [3x3 inertia per unit mass]`\n"));
    const std::string fem = describe_components("TetrahedronFEMForceField");
    EXPECT_THAT(fem, HasSubstr("    youngModulus (number, Pa, > 0) default 5000\n"));
    EXPECT_THAT(fem, HasSubstr("    poissonRatio (number) default 0.45: in (-1, 0.5)\n"));
    const std::string all = describe_components();
    EXPECT_THAT(all, HasSubstr(std::to_string(component_registry().size()) + " component types"));
    for (const ComponentSpec& s : component_registry()) EXPECT_THAT(all, HasSubstr("  " + std::string(s.type) + ": "));
    EXPECT_THROW((void)describe_components("FancyForceField"), io::SceneError);
}

// Every declared default is what the builder uses: a component written with no attribute
// behaves as one written with every default spelled out (same roles in `penalty info`).
TEST(ComponentRegistry, SpelledOutDefaultsChangeNothing) {
    const std::string body_defaults =
        "<MechanicalObject position='0 0 0  1 0 0  0 1 0'/><MeshTopology triangles='0 1 2'/>"
        "<UniformMass vertexMass='1'/><MeshSpringForceField/>"
        "<TriangleCollisionModel/><PointCollisionModel/>";
    const std::string body_spelled =
        "<MechanicalObject position='0 0 0  1 0 0  0 1 0' translation='0 0 0' rotation='0 0 0' scale3d='1 1 1' "
        "scale='1'/>"
        "<MeshTopology triangles='0 1 2'/><UniformMass vertexMass='1'/>"
        "<MeshSpringForceField stiffness='0' damping='0'/>"
        "<TriangleCollisionModel active='1' moving='1' simulated='1' selfCollision='0' proximity='0' "
        "contactStiffness='10' "
        "contactFriction='0' contactRestitution='0' bothSide='0' computeNormals='1'/>"
        "<PointCollisionModel contactStiffness='10'/>";
    const auto roles = [](const std::string& body, const std::string& pipeline) {
        const std::string xml = "<Node name='root'>" + pipeline +
                                "<BruteForceBroadPhase/><BVHNarrowPhase/><CollisionResponse/>"
                                "<Node name='A'><EulerImplicitSolver/><CGLinearSolver/>" +
                                body + "</Node></Node>";
        const auto s = build_scene(io::parse_scene_string(xml, "d.scn"));
        std::string out;
        io::for_each_component(*s->file().root, [&](const io::SceneComponent& c) { out += s->role(c) + "\n"; });
        return out;
    };
    const std::string a = roles(body_defaults, "<CollisionPipeline/><NewProximityIntersection/>");
    const std::string b = roles(body_spelled,
                                "<CollisionPipeline/><NewProximityIntersection alarmDistance='1' contactDistance='0.5' "
                                "useLineLine='0' beyondSofaPairs='0'/>");
    EXPECT_EQ(a, b);
    EXPECT_THAT(a, HasSubstr("alarm distance 1 m, contact distance 0.5 m"));
    EXPECT_THAT(a, HasSubstr("contactStiffness 10"));
}

}  // namespace

namespace {

// The fuzz dictionary (fuzz/scene.dict) lists the registry's tags and attributes, so that the
// scene fuzzers reach every build function: it must not fall behind the registry.
TEST(ComponentRegistry, FuzzDictionaryCoversTheRegistry) {
    std::ifstream in(penalty::test::source_dir() / "fuzz/scene.dict");
    ASSERT_TRUE(in) << "fuzz/scene.dict (scripts/update-fuzz-dictionary.py adds what it lacks)";
    std::ostringstream text;
    text << in.rdbuf();
    const std::string dict = text.str();
    std::size_t entries = 0;
    for (const ComponentSpec& s : component_registry()) {
        EXPECT_NE(dict.find("\"<" + std::string(s.type) + " \""), std::string::npos) << "tag " << s.type;
        ++entries;
        if (category_of(s.family) == ComponentCategory::ignored) continue;
        for (std::span<const AttributeSpec> list : {s.attributes, s.shared_attributes}) {
            for (const AttributeSpec& a : list) {
                EXPECT_NE(dict.find("\" " + std::string(a.name) + "=\\\"\""), std::string::npos)
                    << s.type << "." << a.name;
                ++entries;
            }
        }
    }
    EXPECT_GT(entries, 200u);
}

}  // namespace
