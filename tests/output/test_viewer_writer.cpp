// Browser viewer data: positions and contact segments read back from the binary files, the
// manifest's per-frame statistics, the page files, and errors.
#include "penalty/output/format.hpp"
#include "penalty/output/viewer_writer.hpp"

#include "output_test_support.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

namespace penalty::output {
namespace {

using test::TempDir;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

template <class T>
std::vector<T> read_binary(const std::filesystem::path& file) {
    const std::string bytes = test::read_text(file);
    EXPECT_EQ(bytes.size() % sizeof(T), 0u) << file;
    std::vector<T> out(bytes.size() / sizeof(T));
    std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
    return out;
}

/// A Vec3 surface of two triangles (4 points), a Rigid3 ball, and a penalty field between them.
struct TwoBodies {
    Vec3Object surface{"surface"};
    Rigid3Object ball{"ball"};
    Vec3Object ball_point{"ball_point"};  ///< the contact-point state of the ball side
    StateRecord surface_record;
    StateRecord ball_record;
    PenaltyForceField field;

    TwoBodies() {
        surface.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 1), Vec3(0, 0, 1)};
        surface.init();
        ball.position = {RigidFrame{Vec3(0.5, 0.25, 0.5), Quat(Eigen::AngleAxisd(0.5, Vec3::UnitZ()))}};
        ball.init();
        ball_point.position = {Vec3(0.5, -0.1, 0.5)};
        ball_point.init();
        surface_record = {"surface", "/Floor", &surface, nullptr, false, false, nullptr, {}};
        ball_record = {"ball", "/Ball", &ball, nullptr, false, true, nullptr, {0.25}};
        // pen = dist − (x2 − x1)·n = 0 − (−0.1 − 0)·1 = 0.1 m; ks = 100 N/m: force on side 2 = +10 N along y
        field.add_contact(DofIndex(1), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3::UnitY(), 0.0, 100.0);
        Vec3List f1(4, Vec3::Zero()), f2(1, Vec3::Zero());
        field.add_force(f1, f2, surface.position, ball_point.position, Vec3List(4, Vec3::Zero()),
                        Vec3List(1, Vec3::Zero()));
    }
    [[nodiscard]] std::vector<ViewerShape> shapes() const {
        ViewerShape floor{"floor_triangles", "Triangle", ViewerShapeKind::triangles, 0, {0, 2, 1, 0, 3, 2}, {}, {}, {}};
        ViewerShape sphere{"ball_sphere", "RigidSphere", ViewerShapeKind::spheres, 1, {0}, {0.25}, {}, {}};
        return {floor, sphere};
    }
};

TEST(ViewerWriter, PositionsAndContactSegmentsRoundTrip) {
    TempDir dir;
    TwoBodies bodies;
    const std::vector<ContactRecord> contacts{{"floor-ball", &bodies.field, &bodies.surface, &bodies.ball_point}};
    ViewerWriter writer(dir.path() / "view", {&bodies.surface_record, &bodies.ball_record}, bodies.shapes(),
                        "two bodies");
    EXPECT_EQ(writer.frame_floats(), 4u * 3 + 7);
    writer.write_frame(0.0, {}, 0.0);
    bodies.surface.position[2] = Vec3(1.5, -0.125, 1);  // move a point between frames
    bodies.ball.position[0].center = Vec3(0.5, 0.2, 0.5);
    writer.write_frame(0.01, contacts, 0.0625);
    writer.finish();
    EXPECT_EQ(writer.frame_count(), 2u);

    const std::vector<float> positions = read_binary<float>(dir.path() / "view" / "positions.f32");
    ASSERT_EQ(positions.size(), 2 * writer.frame_floats());
    const Quat q = bodies.ball.position[0].orientation;
    // frame 0: the four surface points, then the ball frame (x y z qx qy qz qw)
    EXPECT_THAT(std::vector<float>(positions.begin(), positions.begin() + 19),
                ElementsAre(0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1, 0.5f, 0.25f, 0.5f, float(q.x()), float(q.y()),
                            float(q.z()), float(q.w())));
    // frame 1: the moved point and ball centre
    EXPECT_THAT(std::vector<float>(positions.begin() + 19 + 6, positions.begin() + 19 + 9),
                ElementsAre(1.5f, -0.125f, 1.0f));
    EXPECT_THAT(std::vector<float>(positions.begin() + 19 + 12, positions.begin() + 19 + 15),
                ElementsAre(0.5f, 0.2f, 0.5f));
    EXPECT_FLOAT_EQ(q.z(), float(std::sin(0.25)));

    // one contact, in frame 1 only: point1 = surface[1], point2 = ball_point[0], normal +y, f·n = 10 N
    const std::vector<float> segments = read_binary<float>(dir.path() / "view" / "contacts.f32");
    EXPECT_THAT(segments, ElementsAre(1, 0, 0, 0.5f, -0.1f, 0.5f, 0, 1, 0, 10.0f));

    const std::vector<std::uint32_t> topology = read_binary<std::uint32_t>(dir.path() / "view" / "topology.u32");
    EXPECT_THAT(topology, ElementsAre(0, 2, 1, 0, 3, 2, 0));

    const std::string manifest = test::read_text(dir.path() / "view" / "run.json");
    EXPECT_THAT(manifest, HasSubstr("\"title\":\"two bodies\""));
    EXPECT_THAT(manifest, HasSubstr("\"frame_floats\":19,\"contact_floats\":10,\"max_normal_force\":10"));
    EXPECT_THAT(
        manifest,
        HasSubstr("{\"name\":\"surface\",\"node_path\":\"/Floor\",\"type\":\"Vec3d\",\"dofs\":4,\"offset\":0,"));
    EXPECT_THAT(manifest,
                HasSubstr("{\"name\":\"ball\",\"node_path\":\"/Ball\",\"type\":\"Rigid3d\",\"dofs\":1,\"offset\":12,"));
    EXPECT_THAT(manifest, HasSubstr("\"kind\":\"triangles\",\"state\":0,\"index_offset\":0,\"index_count\":6}"));
    EXPECT_THAT(manifest,
                HasSubstr("\"kind\":\"spheres\",\"state\":1,\"index_offset\":6,\"index_count\":1,\"radius\":[0.25]}"));
    // per-frame statistics: contact energy ½·100·0.1² = 0.5 J
    EXPECT_THAT(manifest,
                HasSubstr("\"frames\":{\"count\":2,\"time\":[0,0.01],\"contacts\":[0,1],\"active_contacts\":[0,1],"
                          "\"max_penetration\":[0,0.1],\"contact_energy\":[0," +
                          format_number(0.5 * 100 * 0.1 * 0.1) +
                          "],\"kinetic_energy\":[0,0.0625],\"dissipated_energy\":[0,0]}"));

    // the page files are there, the page loads the vendored three.js, not another host
    const std::string page = test::read_text(dir.path() / "view" / "index.html");
    EXPECT_THAT(page, HasSubstr("viewer.js"));
    EXPECT_THAT(page, ::testing::Not(HasSubstr("http")));
    EXPECT_GT(std::filesystem::file_size(dir.path() / "view" / "three.module.min.js"), 100000u);
    EXPECT_THAT(test::read_text(dir.path() / "view" / "OrbitControls.js"), HasSubstr("from './three.module.min.js'"));
}

TEST(ViewerWriter, DestructorWritesTheManifestOfTheFramesSoFar) {
    TempDir dir;
    TwoBodies bodies;
    {
        ViewerWriter writer(dir.path(), {&bodies.surface_record}, {bodies.shapes()[0]}, "t\"itle\\");
        writer.write_frame(0.5, {}, 1.0);
    }
    const std::string manifest = test::read_text(dir.path() / "run.json");
    EXPECT_THAT(manifest, HasSubstr("\"title\":\"t\\\"itle\\\\\""));
    EXPECT_THAT(manifest, HasSubstr("\"count\":1,\"time\":[0.5]"));
}

TEST(ViewerWriter, NonFinitePositionThrowsAndWritesNothingOfTheFrame) {
    TempDir dir;
    TwoBodies bodies;
    ViewerWriter writer(dir.path(), {&bodies.surface_record, &bodies.ball_record}, bodies.shapes(), "diverging");
    writer.write_frame(0.0, {}, 0.0);
    bodies.surface.position[3].y() = std::numeric_limits<double>::quiet_NaN();
    try {
        writer.write_frame(0.02, {}, 0.0);
        ADD_FAILURE() << "no error";
    } catch (const NonFiniteValueError& e) {
        EXPECT_THAT(e.what(), HasSubstr("state '/Floor/surface' DOF 3 is not finite at t = 0.02 s"));
    }
    EXPECT_EQ(writer.frame_count(), 1u);
    EXPECT_EQ(std::filesystem::file_size(dir.path() / "positions.f32"), writer.frame_floats() * sizeof(float));
    // finite positions with an overflowed kinetic energy: the frame is written, the energy is null
    bodies.surface.position[3].y() = 0.0;
    writer.write_frame(0.03, {}, std::numeric_limits<double>::infinity());
    writer.finish();
    EXPECT_THAT(test::read_text(dir.path() / "run.json"), HasSubstr("\"kinetic_energy\":[0,null]"));
}

TEST(ViewerWriter, BadShapesAreRejectedNamingTheShape) {
    TempDir dir;
    TwoBodies bodies;
    auto expect_error = [&](ViewerShape shape, const std::string& message) {
        try {
            ViewerWriter writer(dir.path(), {&bodies.surface_record, &bodies.ball_record}, {shape}, "bad");
            ADD_FAILURE() << "no error for " << message;
        } catch (const std::invalid_argument& e) {
            EXPECT_THAT(e.what(), HasSubstr(message));
        }
    };
    expect_error({"tri", "Triangle", ViewerShapeKind::triangles, 0, {0, 1, 4}, {}, {}, {}},
                 "shape 'tri': DOF index 4 out of range (state '/Floor/surface' has 4 DOFs)");
    expect_error({"tri", "Triangle", ViewerShapeKind::triangles, 0, {0, 1}, {}, {}, {}},
                 "2 indices, not a multiple of 3");
    expect_error({"s", "Sphere", ViewerShapeKind::spheres, 2, {0}, {1.0}, {}, {}},
                 "state index 2 out of range (2 states)");
    expect_error({"s", "Sphere", ViewerShapeKind::spheres, 0, {0, 1}, {1.0}, {}, {}}, "1 radii for 2 elements");
    expect_error({"c", "Cylinder", ViewerShapeKind::cylinders, 0, {0}, {1.0}, {2.0}, {Vec3::UnitY()}},
                 "cylinders need a Rigid3 state");
}

TEST(ViewerWriter, TopologicalChangesStartNewLayouts) {
    // A triangle and its point removed between frames 1 and 2 (swap-and-pop: point 3 becomes 2):
    // frame 2 starts layout 1 with 3 DOFs and one triangle; run.json goes to version 2.
    TempDir dir;
    TwoBodies bodies;
    std::uint64_t revision = 7;
    std::vector<ViewerShape> now = bodies.shapes();
    ViewerWriter writer(dir.path(), {&bodies.surface_record, &bodies.ball_record}, bodies.shapes(), "cut");
    writer.follow_topology([&] { return revision; }, [&] { return now; });
    writer.write_frame(0.0, {}, 0.0);
    writer.write_frame(0.01, {}, 0.0);  // same revision and sizes: same layout
    bodies.surface.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1)};
    now[0].indices = {0, 2, 1};
    ++revision;
    writer.write_frame(0.02, {}, 0.0);
    ++revision;  // elements changed, sizes not: a new layout too
    now[0].indices = {0, 1, 2};
    writer.write_frame(0.03, {}, 0.0);
    writer.finish();
    EXPECT_EQ(writer.layout_count(), 3u);
    EXPECT_EQ(writer.frame_floats(), 19u);  // of the first layout
    EXPECT_EQ(read_binary<float>(dir.path() / "positions.f32").size(), 2 * 19u + 2 * 16u);
    EXPECT_THAT(read_binary<std::uint32_t>(dir.path() / "topology.u32"),
                ElementsAre(0, 2, 1, 0, 3, 2, 0, 0, 2, 1, 0, 0, 1, 2, 0));
    const std::string manifest = test::read_text(dir.path() / "run.json");
    EXPECT_THAT(manifest, HasSubstr("\"version\":2,"));
    EXPECT_THAT(manifest, HasSubstr("\"layouts\":[{\"frame_floats\":19,"));
    EXPECT_THAT(
        manifest,
        HasSubstr("{\"frame_floats\":16,\"states\":[{\"name\":\"surface\",\"node_path\":\"/Floor\",\"type\":\"Vec3d\","
                  "\"dofs\":3,\"offset\":0,\"mapped\":false},{\"name\":\"ball\",\"node_path\":\"/Ball\","
                  "\"type\":\"Rigid3d\",\"dofs\":1,\"offset\":9,"));
    EXPECT_THAT(manifest, HasSubstr("\"kind\":\"triangles\",\"state\":0,\"index_offset\":7,\"index_count\":3}"));
    EXPECT_THAT(manifest, HasSubstr("\"layout\":[0,0,1,2],\"position_offset\":[0,19,38,54]}"));

    // without follow_topology a state that changes size is an error
    TempDir other;
    TwoBodies fixed;
    ViewerWriter plain(other.path(), {&fixed.surface_record}, {fixed.shapes()[0]}, "plain");
    plain.write_frame(0.0, {}, 0.0);
    fixed.surface.position.pop_back();
    EXPECT_THROW(plain.write_frame(0.01, {}, 0.0), std::invalid_argument);
}

TEST(ViewerWriter, UnwritableDirectoryThrowsNamingIt) {
    TempDir dir;
    test::write_text(dir.path() / "blocker", "x");
    TwoBodies bodies;
    try {
        ViewerWriter writer(dir.path() / "blocker" / "view", {&bodies.surface_record}, {}, "x");
        FAIL();
    } catch (const std::runtime_error& e) {
        EXPECT_THAT(e.what(), HasSubstr("blocker"));
    }
}

// Issue 49: a link in DIR named like one of the writer's files (a page file, a data file, the
// manifest or the old fixed name of its temporary) is replaced by the writer's own file; the
// file the link pointed to, outside DIR, keeps its content. No temporary file is left behind.
TEST(ViewerWriter, LinksInTheDirectoryAreReplacedNeverWrittenThrough) {
    TempDir dir;
    const std::filesystem::path view = dir.path() / "view";
    std::filesystem::create_directories(view);
    const std::vector<std::string> names{"index.html",   "viewer.js", "topology.u32", "positions.f32",
                                         "contacts.f32", "run.json",  "run.json.tmp"};
    for (const std::string& name : names) {
        test::write_text(dir.path() / ("victim-" + name), "precious");
        std::filesystem::create_symlink(std::filesystem::path("..") / ("victim-" + name), view / name);
    }
    TwoBodies bodies;
    {
        ViewerWriter writer(view, {&bodies.surface_record, &bodies.ball_record}, bodies.shapes(), "links");
        writer.write_frame(0.0, {}, 0.0);
        writer.finish();
    }
    write_viewer_page(view);  // `penalty view DIR` rewrites the page files
    for (const std::string& name : names)
        EXPECT_TRUE(test::read_text(dir.path() / ("victim-" + name)) == "precious")
            << "the file the link DIR/" << name << " points to was written through";
    for (const char* name : {"index.html", "viewer.js", "topology.u32", "positions.f32", "contacts.f32", "run.json"}) {
        EXPECT_FALSE(std::filesystem::is_symlink(view / name)) << name;
        EXPECT_TRUE(std::filesystem::is_regular_file(view / name)) << name;
    }
    EXPECT_EQ(std::filesystem::file_size(view / "positions.f32"), (4u * 3 + 7) * sizeof(float));
    EXPECT_THAT(test::read_text(view / "run.json"), HasSubstr("\"title\":\"links\""));
    for (const auto& entry : std::filesystem::directory_iterator(view))
        EXPECT_NE(entry.path().filename().string().front(), '.') << "temporary file left: " << entry.path();
}

}  // namespace
}  // namespace penalty::output
