// Tetra2TriangleTopologicalMapping while its input changes (tetra_to_triangle_mapping.cpp, SOFA's
// Tetra2TriangleTopologicalMapping::updateTopologicalMappingTopDown): the output keeps the input's
// border triangles, each output triangle naming its input triangle (Loc2GlobVec), under
// tetrahedra removed (a face shared with a kept tetrahedron joins the output, oriented as a face of
// that tetrahedron, smallest vertex first, flipped with flipNormals) and added (new border faces
// join, faces now inside leave), noNewTriangles, and the points forwarded.
#include "penalty/mechanics/topological_mapping.hpp"
#include "penalty/mechanics/topological_mapping_changes.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <vector>

namespace penalty {
namespace {

/// The tetrahedra (0,1,2,3) and (1,2,3,4), sharing (1,2,3), as an input container and its border
/// as the output, the mapping listening to the input.
struct MappedTetrahedra {
    MeshTopology volume;
    MeshTopology surface;
    std::unique_ptr<TopologyContainer> input;
    std::unique_ptr<TopologyContainer> output;
    std::unique_ptr<Tetra2TriangleMappingFollower> mapping;
    MappedTetrahedra(std::vector<Tetrahedron> tetrahedra, bool flip_normals, bool no_new_triangles) {
        volume.set_tetrahedra(std::move(tetrahedra));
        surface.set_triangles(border_triangles(volume, flip_normals));
        input = std::make_unique<TopologyContainer>(volume, ElementType::tetrahedron, "volume");
        output = std::make_unique<TopologyContainer>(surface, ElementType::triangle, "surface");
        auto scope = std::make_shared<TopologyChangeScope>();
        input->set_scope(scope);
        output->set_scope(scope);
        mapping =
            std::make_unique<Tetra2TriangleMappingFollower>(*input, *output, flip_normals, no_new_triangles, false);
        input->add_listener(*mapping);
    }
    /// Each output triangle has the vertices of the input triangle it names.
    void expect_maps_consistent() const {
        const auto& out = output->mesh().triangles();
        const auto& in = input->mesh().triangles();
        ASSERT_EQ(mapping->output_to_input().size(), out.size());
        for (std::size_t k = 0; k < out.size(); ++k) {
            const ElementId g = mapping->output_to_input()[k];
            ASSERT_GE(g, 0);
            ASSERT_LT(std::size_t(g), in.size());
            Triangle a = out[k];
            Triangle b = in[std::size_t(g)];
            std::sort(a.begin(), a.end());
            std::sort(b.begin(), b.end());
            EXPECT_EQ(a, b) << "output triangle " << k;
        }
    }
};

TEST(TetraToTriangleMapping, TheInitialMapsNameTheInputsBorderTriangles) {
    MappedTetrahedra m({{0, 1, 2, 3}, {1, 2, 3, 4}}, false, false);
    // input triangles (1,2,3) (0,3,2) (0,1,3) (0,2,1) (2,3,4) (1,4,3) (1,2,4): all but the shared first
    EXPECT_EQ(m.mapping->output_to_input(), (std::vector<ElementId>{1, 2, 3, 4, 5, 6}));
    m.expect_maps_consistent();
    EXPECT_EQ(m.mapping->input_cell_of(0), 0);
    EXPECT_EQ(m.mapping->input_cell_of(3), 1);
    EXPECT_EQ(m.mapping->input_cell_of(6), -1);
}

TEST(TetraToTriangleMapping, ARemovedTetrahedronsSharedFaceJoinsTheOutput) {
    for (const bool flip : {false, true}) {
        MappedTetrahedra m({{0, 1, 2, 3}, {1, 2, 3, 4}}, flip, false);
        m.input->remove_tetrahedra({1});
        const auto& out = m.output->mesh().triangles();
        ASSERT_EQ(out.size(), 4U) << flip;
        m.expect_maps_consistent();
        // appended at 6, then moved down to 3 by the output's swap-and-pops of 5, 4, 3 (the removed faces)
        EXPECT_EQ(m.mapping->output_to_input(), (std::vector<ElementId>{1, 2, 3, 0})) << flip;
        EXPECT_EQ(out[3], (flip ? Triangle{1, 3, 2} : Triangle{1, 2, 3})) << flip;
        // the shared face, as face (1,2,3) of (0,1,2,3), smallest vertex first; flipped: (1,3,2)
        EXPECT_NE(std::find(out.begin(), out.end(), flip ? Triangle{1, 3, 2} : Triangle{1, 2, 3}), out.end()) << flip;
        // the other three are tetrahedron 0's faces as init stored them
        for (const Triangle& t : border_triangles(m.volume, flip))
            EXPECT_NE(std::find(out.begin(), out.end(), t), out.end()) << flip;
        for (ElementId k = 0; k < 4; ++k) EXPECT_EQ(m.mapping->input_cell_of(k), 0) << flip;
        // outward: positive for (0,1,2,3) at the unit corner, each face's normal away from the 4th vertex
        const std::vector<Vec3> x{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        const Vec3 centre = (x[0] + x[1] + x[2] + x[3]) / 4.0;
        for (const Triangle& f : out) {
            const Vec3 n =
                (x[std::size_t(f[1])] - x[std::size_t(f[0])]).cross(x[std::size_t(f[2])] - x[std::size_t(f[0])]);
            EXPECT_EQ(n.dot(x[std::size_t(f[0])] - centre) > 0.0, !flip) << flip;
        }
    }
}

// Removing the first tetrahedron removes input triangles 1, 2, 3 (not the last ones): the input's
// swap-and-pops renumber the faces of the second, and the maps follow them.
TEST(TetraToTriangleMapping, TheMapsFollowTheInputsRenumberedTriangles) {
    MappedTetrahedra m({{0, 1, 2, 3}, {1, 2, 3, 4}}, false, false);
    m.input->remove_tetrahedra({0});
    const auto& out = m.output->mesh().triangles();
    ASSERT_EQ(out.size(), 4U);
    m.expect_maps_consistent();
    // the shared face oriented as a face of (1,2,3,4): (1,3,2), not as the input stores it
    EXPECT_NE(std::find(out.begin(), out.end(), Triangle{1, 3, 2}), out.end());
    // point 0, isolated, removed: 4 took its index (POINTSREMOVED forwarded to the output)
    EXPECT_EQ(m.input->num_points(), 4U);
    EXPECT_EQ(m.output->num_points(), 4U);
    // (1,2,3,4) is positive with 4 (now 0) at (1,1,1): every output face points away from its centre
    const std::vector<Vec3> x{{1, 1, 1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const Vec3 centre = (x[0] + x[1] + x[2] + x[3]) / 4.0;
    for (const Triangle& f : out) {
        const Vec3 n = (x[std::size_t(f[1])] - x[std::size_t(f[0])]).cross(x[std::size_t(f[2])] - x[std::size_t(f[0])]);
        EXPECT_GT(n.dot(x[std::size_t(f[0])] - centre), 0.0);
    }
    for (ElementId k = 0; k < 4; ++k) EXPECT_EQ(m.mapping->input_cell_of(k), 0);
}

TEST(TetraToTriangleMapping, NoNewTrianglesOnlyRemoves) {
    MappedTetrahedra m({{0, 1, 2, 3}, {1, 2, 3, 4}}, false, true);
    m.input->remove_tetrahedra({1});
    // tetrahedron 1's three faces gone, the shared face not added
    EXPECT_EQ(m.output->mesh().triangles(), (std::vector<Triangle>{{0, 3, 2}, {0, 1, 3}, {0, 2, 1}}));
    m.expect_maps_consistent();
}

TEST(TetraToTriangleMapping, AnAddedTetrahedronsFacesJoinAndTheCoveredFaceLeaves) {
    MappedTetrahedra m({{0, 1, 2, 3}}, false, false);
    ASSERT_EQ(m.output->mesh().triangles().size(), 4U);
    m.input->add_points(1);
    m.input->add_tetrahedra({{1, 2, 3, 4}});
    const auto& out = m.output->mesh().triangles();
    EXPECT_EQ(out.size(), 6U);
    m.expect_maps_consistent();
    // the three new faces appended (input triangles 4, 5, 6); (1,2,3), output 0, removed by swap-and-pop
    EXPECT_EQ(m.mapping->output_to_input(), (std::vector<ElementId>{6, 1, 2, 3, 4, 5}));
    for (std::size_t k = 0; k < out.size(); ++k)
        EXPECT_EQ(out[k], m.volume.triangles()[std::size_t(m.mapping->output_to_input()[k])]) << k;
    // (1,2,3) is inside now
    for (const Triangle& t : out) {
        Triangle s = t;
        std::sort(s.begin(), s.end());
        EXPECT_NE(s, (Triangle{1, 2, 3}));
    }
    EXPECT_EQ(m.output->num_points(), 5U);  // POINTSADDED forwarded
}

}  // namespace
}  // namespace penalty
