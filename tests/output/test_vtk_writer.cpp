// VTK series: file names, pieces parsed with tinyxml2 (counts, connectivity, offsets, types,
// arrays), the collections, contacts, Rigid3 frames, and errors.
#include "penalty/output/format.hpp"
#include "penalty/output/vtk_writer.hpp"

#include "output_test_support.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <cmath>
#include <limits>
#include <sstream>

namespace penalty::output {
namespace {

using test::TempDir;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

/// A parsed VTK XML file.
class VtkFile {
public:
    explicit VtkFile(const std::filesystem::path& file) {
        const auto status = doc_.LoadFile(file.string().c_str());
        EXPECT_EQ(status, tinyxml2::XML_SUCCESS) << file << ": " << doc_.ErrorStr();
        root_ = doc_.FirstChildElement("VTKFile");
        EXPECT_NE(root_, nullptr) << file;
    }
    [[nodiscard]] const tinyxml2::XMLElement* root() const { return root_; }
    [[nodiscard]] const tinyxml2::XMLElement* piece(const char* type) const {
        const auto* grid = root_->FirstChildElement(type);
        EXPECT_NE(grid, nullptr) << type;
        return grid == nullptr ? nullptr : grid->FirstChildElement("Piece");
    }

private:
    tinyxml2::XMLDocument doc_;
    const tinyxml2::XMLElement* root_ = nullptr;
};

/// The values of the DataArray named `name` under `parent` (searched one level down).
std::vector<double> array_values(const tinyxml2::XMLElement* parent, const char* section, const char* name,
                                 int* components = nullptr) {
    const auto* block = parent->FirstChildElement(section);
    if (block == nullptr) {
        ADD_FAILURE() << "no section " << section;
        return {};
    }
    for (const auto* array = block->FirstChildElement("DataArray"); array != nullptr;
         array = array->NextSiblingElement("DataArray")) {
        const char* array_name = array->Attribute("Name");
        if (array_name == nullptr || std::string(array_name) != name) continue;
        if (components != nullptr) *components = array->IntAttribute("NumberOfComponents", 1);
        std::vector<double> values;
        std::istringstream in(array->GetText() == nullptr ? "" : array->GetText());
        std::string word;
        while (in >> word) values.push_back(std::stod(word));
        return values;
    }
    ADD_FAILURE() << "no DataArray " << name << " in " << section;
    return {};
}

struct CollectionEntry {
    double time;
    std::string file;
};

std::vector<CollectionEntry> collection(const std::filesystem::path& file) {
    VtkFile pvd(file);
    EXPECT_STREQ(pvd.root()->Attribute("type"), "Collection");
    std::vector<CollectionEntry> entries;
    const auto* list = pvd.root()->FirstChildElement("Collection");
    if (list == nullptr) return entries;
    for (const auto* e = list->FirstChildElement("DataSet"); e != nullptr; e = e->NextSiblingElement("DataSet")) {
        EXPECT_STREQ(e->Attribute("group"), "");
        EXPECT_STREQ(e->Attribute("part"), "0");
        entries.push_back({std::stod(e->Attribute("timestep")), e->Attribute("file")});
    }
    return entries;
}

/// Scene: a tetra+hexa block ("block dofs", name with a space), a triangle surface named like
/// it, a point cloud without topology and a Rigid3 frame.
struct Scene {
    Vec3Object block{"block dofs"};
    Vec3Object surface{"block dofs"};
    Vec3Object cloud{"cloud"};
    Rigid3Object frame{"rigid"};
    MeshTopology volume;
    MeshTopology triangles;
    std::vector<StateRecord> records;

    Scene() {
        // unit cube 0..7 (SOFA/VTK hexahedron order) plus apex 8 above it
        block.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),    Vec3(0, 0, 1),
                          Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 1), Vec3(0.5, 0.5, 2)};
        block.velocity = std::vector<Vec3>(9, Vec3::Zero());
        block.velocity[8] = Vec3(0.1, -5, 0);
        block.init();
        volume.set_tetrahedra({{4, 5, 6, 8}});
        volume.set_hexahedra({{0, 1, 2, 3, 4, 5, 6, 7}});
        surface.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)};
        surface.init();
        triangles.set_triangles({{0, 1, 2}, {1, 3, 2}});
        cloud.position = {Vec3(1, 2, 3), Vec3(4, 5, 6)};
        cloud.init();
        frame.position.resize(1);
        frame.position[0].center = Vec3(1, 2, 3);
        frame.position[0].orientation = Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()));
        frame.velocity = {RigidDeriv{Vec3(1, 0, 0), Vec3(0, 0, 2)}};
        frame.init();
        records.push_back({"block dofs", "/Block", &block, &volume, false, true, nullptr, {}});
        records.push_back({"block dofs", "/Block/Surface", &surface, &triangles, true, true, nullptr, {}});
        records.push_back({"cloud", "/Cloud", &cloud, nullptr, false, true, nullptr, {}});
        records.push_back({"rigid", "/Rigid", &frame, nullptr, false, true, nullptr, {}});
    }
    std::vector<const StateRecord*> pointers() const {
        std::vector<const StateRecord*> out;
        for (const StateRecord& r : records) out.push_back(&r);
        return out;
    }
};

TEST(VtkCells, HighestDimensionElementsOrVertices) {
    MeshTopology volume;
    volume.set_tetrahedra({{0, 1, 2, 3}});
    const VtkCells tetra = vtk_cells(&volume, 4);  // derived triangles/edges are not written
    EXPECT_THAT(tetra.connectivity, ElementsAre(0, 1, 2, 3));
    EXPECT_THAT(tetra.offsets, ElementsAre(4));
    EXPECT_THAT(tetra.types, ElementsAre(VtkCellType::tetra));

    MeshTopology surface;
    surface.set_triangles({{0, 1, 2}});
    surface.set_quads({{0, 1, 3, 2}});
    const VtkCells mixed = vtk_cells(&surface, 4);
    EXPECT_THAT(mixed.connectivity, ElementsAre(0, 1, 2, 0, 1, 3, 2));
    EXPECT_THAT(mixed.offsets, ElementsAre(3, 7));
    EXPECT_THAT(mixed.types, ElementsAre(VtkCellType::triangle, VtkCellType::quad));

    MeshTopology wire;
    wire.set_edges({{0, 1}, {1, 2}});
    const VtkCells lines = vtk_cells(&wire, 3);
    EXPECT_THAT(lines.connectivity, ElementsAre(0, 1, 1, 2));
    EXPECT_THAT(lines.types, ElementsAre(VtkCellType::line, VtkCellType::line));

    const MeshTopology nothing;
    const VtkCells vertices = vtk_cells(&nothing, 2);
    EXPECT_THAT(vertices.connectivity, ElementsAre(0, 1));
    EXPECT_THAT(vertices.offsets, ElementsAre(1, 2));
    EXPECT_THAT(vertices.types, ElementsAre(VtkCellType::vertex, VtkCellType::vertex));
    EXPECT_TRUE(vtk_cells(nullptr, 0).types.empty());

    try {
        (void)vtk_cells(&volume, 3);
        FAIL();
    } catch (const std::invalid_argument& error) {
        EXPECT_THAT(error.what(), HasSubstr("tetrahedron 0 uses point 3 but the state has 3 points"));
    }
}

TEST(VtkCells, HexahedronOrderIsVtkOrder) {
    // VTK_HEXAHEDRON: face 0 1 2 3 seen from 4 5 6 7 is counter-clockwise (its normal
    // (p1 − p0) × (p3 − p0) points toward the top face). SOFA's grid numbering satisfies it.
    const Vec3 p[8] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
                       Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 1)};
    MeshTopology cube;
    cube.set_hexahedra({{0, 1, 2, 3, 4, 5, 6, 7}});
    const VtkCells cells = vtk_cells(&cube, 8);
    ASSERT_EQ(cells.connectivity.size(), 8u);
    const auto at = [&](int j) { return p[cells.connectivity[static_cast<std::size_t>(j)]]; };
    EXPECT_GT((at(1) - at(0)).cross(at(3) - at(0)).dot(at(4) - at(0)), 0.0);
    for (int j = 0; j < 4; ++j) EXPECT_EQ(at(j + 4) - at(j), Vec3(0, 0, 1)) << j;
    // SOFA's kHexaFaces[0] (−z face, outward) is 0 3 2 1: the reverse of VTK's bottom loop
    EXPECT_THAT(MeshTopology::kHexaFaces[0], ElementsAre(0, 3, 2, 1));
}

TEST(VtkSeriesWriter, FileNamesAreUniqueAndStable) {
    TempDir dir;
    Scene scene;
    VtkSeriesWriter writer(dir.path() / "vtk", scene.pointers());
    EXPECT_THAT(writer.state_collections(),
                ElementsAre(dir.path() / "vtk" / "0_block_dofs.pvd", dir.path() / "vtk" / "1_block_dofs.pvd",
                            dir.path() / "vtk" / "2_cloud.pvd", dir.path() / "vtk" / "3_rigid.pvd"));
    EXPECT_EQ(writer.contacts_collection(), dir.path() / "vtk" / "contacts.pvd");
    // collections exist (empty, valid) before the first step
    EXPECT_TRUE(collection(writer.contacts_collection()).empty());
    writer.write_step(0.0, {});
    writer.write_step(0.01, {});
    EXPECT_EQ(writer.step_count(), 2u);
    for (const char* name : {"0_block_dofs_000000.vtu", "0_block_dofs_000001.vtu", "1_block_dofs_000001.vtu",
                             "2_cloud_000000.vtu", "3_rigid_000001.vtu", "contacts_000000.vtp", "contacts_000001.vtp"})
        EXPECT_TRUE(std::filesystem::exists(dir.path() / "vtk" / name)) << name;
    EXPECT_EQ(writer.state_piece(2, 7), dir.path() / "vtk" / "2_cloud_000007.vtu");
    EXPECT_EQ(writer.contacts_piece(123456), dir.path() / "vtk" / "contacts_123456.vtp");
}

TEST(VtkSeriesWriter, Vec3PieceHasPointsVelocityAndCells) {
    TempDir dir;
    Scene scene;
    VtkSeriesWriter writer(dir.path(), scene.pointers());
    writer.write_step(0.1, {});

    VtkFile block(writer.state_piece(0, 0));
    EXPECT_STREQ(block.root()->Attribute("type"), "UnstructuredGrid");
    const auto* piece = block.piece("UnstructuredGrid");
    ASSERT_NE(piece, nullptr);
    EXPECT_EQ(piece->IntAttribute("NumberOfPoints"), 9);
    EXPECT_EQ(piece->IntAttribute("NumberOfCells"), 2);
    EXPECT_THAT(array_values(piece, "Cells", "connectivity"), ElementsAre(4, 5, 6, 8, 0, 1, 2, 3, 4, 5, 6, 7));
    EXPECT_THAT(array_values(piece, "Cells", "offsets"), ElementsAre(4, 12));
    EXPECT_THAT(array_values(piece, "Cells", "types"), ElementsAre(10, 12));
    int components = 0;
    const auto points = array_values(piece, "Points", "position", &components);
    EXPECT_EQ(components, 3);
    ASSERT_EQ(points.size(), 27u);
    EXPECT_THAT(std::vector<double>(points.end() - 3, points.end()), ElementsAre(0.5, 0.5, 2));
    const auto velocity = array_values(piece, "PointData", "velocity", &components);
    EXPECT_EQ(components, 3);
    ASSERT_EQ(velocity.size(), 27u);
    EXPECT_THAT(std::vector<double>(velocity.end() - 3, velocity.end()), ElementsAre(0.1, -5, 0));
    const auto* time = block.root()->FirstChildElement("UnstructuredGrid")->FirstChildElement("FieldData");
    ASSERT_NE(time, nullptr);
    EXPECT_EQ(std::stod(time->FirstChildElement("DataArray")->GetText()), 0.1);

    VtkFile surface(writer.state_piece(1, 0));
    const auto* surface_piece = surface.piece("UnstructuredGrid");
    EXPECT_EQ(surface_piece->IntAttribute("NumberOfPoints"), 4);
    EXPECT_EQ(surface_piece->IntAttribute("NumberOfCells"), 2);
    EXPECT_THAT(array_values(surface_piece, "Cells", "connectivity"), ElementsAre(0, 1, 2, 1, 3, 2));
    EXPECT_THAT(array_values(surface_piece, "Cells", "offsets"), ElementsAre(3, 6));
    EXPECT_THAT(array_values(surface_piece, "Cells", "types"), ElementsAre(5, 5));

    VtkFile cloud(writer.state_piece(2, 0));
    const auto* cloud_piece = cloud.piece("UnstructuredGrid");
    EXPECT_EQ(cloud_piece->IntAttribute("NumberOfPoints"), 2);
    EXPECT_EQ(cloud_piece->IntAttribute("NumberOfCells"), 2);
    EXPECT_THAT(array_values(cloud_piece, "Points", "position"), ElementsAre(1, 2, 3, 4, 5, 6));
    EXPECT_THAT(array_values(cloud_piece, "Cells", "types"), ElementsAre(1, 1));
}

TEST(VtkSeriesWriter, NumbersRoundTripExactly) {
    TempDir dir;
    Vec3Object state("p");
    state.position = {Vec3(1.0 / 3.0, -5, 1e-300)};
    state.init();
    const StateRecord record{"p", "/", &state, nullptr, false, true, nullptr, {}};
    VtkSeriesWriter writer(dir.path(), {&record});
    writer.write_step(0.1, {});
    VtkFile file(writer.state_piece(0, 0));
    EXPECT_THAT(array_values(file.piece("UnstructuredGrid"), "Points", "position"), ElementsAre(1.0 / 3.0, -5, 1e-300));
    EXPECT_THAT(test::read_text(writer.state_piece(0, 0)), HasSubstr("0.3333333333333333 -5 1e-300"));
}

TEST(VtkSeriesWriter, RigidPieceHasFramesOrientationAndAxes) {
    TempDir dir;
    Scene scene;
    VtkSeriesWriter writer(dir.path(), scene.pointers());
    writer.write_step(0.0, {});
    VtkFile rigid(writer.state_piece(3, 0));
    const auto* piece = rigid.piece("UnstructuredGrid");
    EXPECT_EQ(piece->IntAttribute("NumberOfPoints"), 1);
    EXPECT_EQ(piece->IntAttribute("NumberOfCells"), 1);
    EXPECT_THAT(array_values(piece, "Points", "position"), ElementsAre(1, 2, 3));
    EXPECT_THAT(array_values(piece, "Cells", "types"), ElementsAre(1));
    int components = 0;
    const auto q = array_values(piece, "PointData", "orientation", &components);
    EXPECT_EQ(components, 4);
    const double s = std::sqrt(0.5);
    ASSERT_EQ(q.size(), 4u);
    EXPECT_NEAR(q[0], 0, 1e-15);
    EXPECT_NEAR(q[1], 0, 1e-15);
    EXPECT_NEAR(q[2], s, 1e-15);
    EXPECT_NEAR(q[3], s, 1e-15);
    // 90° about z: body x -> world y, body y -> world −x, body z -> world z
    const auto near = [](const std::vector<double>& v, Vec3 expected) {
        ASSERT_EQ(v.size(), 3u);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(v[static_cast<std::size_t>(c)], expected[c], 1e-15) << c;
    };
    near(array_values(piece, "PointData", "axis_x"), Vec3(0, 1, 0));
    near(array_values(piece, "PointData", "axis_y"), Vec3(-1, 0, 0));
    near(array_values(piece, "PointData", "axis_z"), Vec3(0, 0, 1));
    EXPECT_THAT(array_values(piece, "PointData", "velocity"), ElementsAre(1, 0, 0));
    EXPECT_THAT(array_values(piece, "PointData", "angular_velocity"), ElementsAre(0, 0, 2));
}

TEST(VtkSeriesWriter, SphereRadiiArePointScalars) {
    TempDir dir;
    Scene scene;
    scene.records[2].radius = {0.25, 0.5};  // the cloud carries Vec3 spheres
    scene.records[3].radius = {0.75};       // the frame a rigid sphere
    VtkSeriesWriter writer(dir.path(), scene.pointers());
    writer.write_step(0.0, {});
    VtkFile cloud(writer.state_piece(2, 0));
    const auto* piece = cloud.piece("UnstructuredGrid");
    EXPECT_STREQ(piece->FirstChildElement("PointData")->Attribute("Scalars"), "radius");
    int components = 0;
    EXPECT_THAT(array_values(piece, "PointData", "radius", &components), ElementsAre(0.25, 0.5));
    EXPECT_EQ(components, 1);
    VtkFile rigid(writer.state_piece(3, 0));
    EXPECT_THAT(array_values(rigid.piece("UnstructuredGrid"), "PointData", "radius"), ElementsAre(0.75));
    // without radii: no scalars attribute
    VtkFile block(writer.state_piece(0, 0));
    EXPECT_EQ(block.piece("UnstructuredGrid")->FirstChildElement("PointData")->Attribute("Scalars"), nullptr);
    // a radius list that does not match the DOFs names the state
    scene.records[2].radius = {0.25};
    VtkSeriesWriter bad(dir.path() / "bad", scene.pointers());
    try {
        bad.write_step(0.0, {});
        ADD_FAILURE() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_THAT(e.what(), HasSubstr("/Cloud/cloud: 1 radii for 2 DOFs"));
    }
}

TEST(VtkSeriesWriter, ContactsPieceHasOneLinePerContact) {
    TempDir dir;
    Vec3Object a("a");
    a.position = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
    a.init();
    Vec3Object b("b");
    b.position = {Vec3(0, -0.1, 0), Vec3(1, 0.5, 0)};
    b.init();
    PenaltyForceField field1;
    field1.add_contact(DofIndex(0), DofIndex(0), ElementIndex(7), ElementIndex(8), Vec3::UnitY(), 0.0,
                       100.0);  // pen 0.1, force on b: +10 y
    field1.add_contact(DofIndex(1), DofIndex(1), ElementIndex(9), ElementIndex(10), Vec3::UnitY(), 0.0,
                       100.0);  // pen −0.5, inactive
    Vec3List f1(2, Vec3::Zero()), f2(2, Vec3::Zero());
    const Vec3List v(2, Vec3::Zero());
    field1.add_force(f1, f2, a.position, b.position, v, v);
    PenaltyForceField field2;  // same states swapped, one contact; renewed once: age 1
    field2.add_contact(DofIndex(1), DofIndex(0), ElementIndex(3), ElementIndex(4), -Vec3::UnitX(), 0.0, 2.0);
    field2.renew_contacts();
    const std::vector<ContactRecord> contacts{{"ab", &field1, &a, &b}, {"ba", &field2, &b, &a}};

    const StateRecord record{"a", "/", &a, nullptr, false, true, nullptr, {}};
    VtkSeriesWriter writer(dir.path(), {&record});
    writer.write_step(0.0, {});  // no contact: a valid, empty file
    writer.write_step(0.5, contacts);

    VtkFile empty(writer.contacts_piece(0));
    EXPECT_STREQ(empty.root()->Attribute("type"), "PolyData");
    const auto* empty_piece = empty.piece("PolyData");
    EXPECT_EQ(empty_piece->IntAttribute("NumberOfPoints"), 0);
    EXPECT_EQ(empty_piece->IntAttribute("NumberOfLines"), 0);
    EXPECT_TRUE(array_values(empty_piece, "Lines", "connectivity").empty());
    EXPECT_TRUE(array_values(empty_piece, "CellData", "force").empty());

    VtkFile file(writer.contacts_piece(1));
    const auto* piece = file.piece("PolyData");
    EXPECT_EQ(piece->IntAttribute("NumberOfPoints"), 6);
    EXPECT_EQ(piece->IntAttribute("NumberOfLines"), 3);
    EXPECT_EQ(piece->IntAttribute("NumberOfVerts"), 0);
    EXPECT_THAT(array_values(piece, "Lines", "connectivity"), ElementsAre(0, 1, 2, 3, 4, 5));
    EXPECT_THAT(array_values(piece, "Lines", "offsets"), ElementsAre(2, 4, 6));
    EXPECT_THAT(array_values(piece, "Points", "position"),
                ElementsAre(0, 0, 0, 0, -0.1, 0, 1, 0, 0, 1, 0.5, 0, 1, 0.5, 0, 0, 0, 0));
    const auto pen = array_values(piece, "CellData", "penetration");
    ASSERT_EQ(pen.size(), 3u);
    EXPECT_DOUBLE_EQ(pen[0], 0.1);
    EXPECT_DOUBLE_EQ(pen[1], -0.5);
    EXPECT_DOUBLE_EQ(pen[2], -1.0);  // u = a[0] − b[1] = (−1, −0.5, 0), u·n = 1: pen = 0 − 1
    const auto force = array_values(piece, "CellData", "force");
    ASSERT_EQ(force.size(), 9u);
    EXPECT_DOUBLE_EQ(force[1], 10.0);
    EXPECT_THAT(array_values(piece, "CellData", "normal"), ElementsAre(0, 1, 0, 0, 1, 0, -1, 0, 0));
    EXPECT_THAT(array_values(piece, "CellData", "age"), ElementsAre(0, 0, 1));
    EXPECT_THAT(array_values(piece, "CellData", "pair"), ElementsAre(0, 0, 1));
    EXPECT_THAT(array_values(piece, "CellData", "element1"), ElementsAre(7, 9, 3));
    EXPECT_THAT(array_values(piece, "CellData", "element2"), ElementsAre(8, 10, 4));

    const auto entries = collection(writer.contacts_collection());
    ASSERT_EQ(entries.size(), 2u);
    EXPECT_EQ(entries[0].time, 0.0);
    EXPECT_EQ(entries[0].file, "contacts_000000.vtp");
    EXPECT_EQ(entries[1].time, 0.5);
    EXPECT_EQ(entries[1].file, "contacts_000001.vtp");
}

TEST(VtkSeriesWriter, CollectionsListEveryStepAfterEveryStep) {
    TempDir dir;
    Scene scene;
    VtkSeriesWriter writer(dir.path(), scene.pointers());
    const double times[] = {0.0, 0.01, 0.02, 1.0 / 3.0};
    for (std::size_t s = 0; s < std::size(times); ++s) {
        writer.write_step(times[s], {});
        for (std::size_t k = 0; k < scene.records.size(); ++k) {
            const auto entries = collection(writer.state_collections()[k]);
            ASSERT_EQ(entries.size(), s + 1);
            for (std::size_t j = 0; j <= s; ++j) {
                EXPECT_EQ(entries[j].time, times[j]);
                EXPECT_EQ(entries[j].file, writer.state_piece(k, j).filename().string());
            }
        }
        EXPECT_EQ(collection(writer.contacts_collection()).size(), s + 1);
    }
}

TEST(VtkSeriesWriter, NonFiniteThrowsBeforeWritingTheStep) {
    TempDir dir;
    Scene scene;
    VtkSeriesWriter writer(dir.path(), scene.pointers());
    writer.write_step(0.0, {});
    scene.cloud.velocity[1].y() = std::numeric_limits<double>::infinity();
    try {
        writer.write_step(0.01, {});
        FAIL();
    } catch (const NonFiniteValueError& error) {
        EXPECT_THAT(error.what(), HasSubstr("/Cloud/cloud velocity"));
        EXPECT_THAT(error.what(), HasSubstr("DOF 1"));
        EXPECT_THAT(error.what(), HasSubstr("0.01"));
    }
    EXPECT_EQ(writer.step_count(), 1u);
    EXPECT_FALSE(std::filesystem::exists(writer.state_piece(0, 1)));
    EXPECT_EQ(collection(writer.state_collections()[0]).size(), 1u);
}

TEST(VtkSeriesWriter, ErrorsNameTheirSubject) {
    TempDir dir;
    test::write_text(dir.path() / "blocker", "x");
    Scene scene;
    try {
        VtkSeriesWriter writer(dir.path() / "blocker" / "vtk", scene.pointers());
        FAIL();
    } catch (const std::runtime_error& error) {
        EXPECT_THAT(error.what(), HasSubstr("blocker"));
    }
    const StateRecord null_state{"x", "/", nullptr, nullptr, false, true, nullptr, {}};
    EXPECT_THROW(VtkSeriesWriter(dir.path(), {&null_state}), std::invalid_argument);

    // a topology larger than its state
    Vec3Object small("small");
    small.position = {Vec3::Zero()};
    small.init();
    MeshTopology topology;
    topology.set_triangles({{0, 1, 2}});
    const StateRecord mismatched{"small", "/S", &small, &topology, false, true, nullptr, {}};
    VtkSeriesWriter writer(dir.path() / "ok", {&mismatched});
    try {
        writer.write_step(0.0, {});
        FAIL();
    } catch (const std::invalid_argument& error) {
        EXPECT_THAT(error.what(), HasSubstr("/S/small"));
        EXPECT_THAT(error.what(), HasSubstr("triangle 0 uses point 1"));
    }
}

}  // namespace
}  // namespace penalty::output
