// Hexa2Quad, Quad2Triangle and Triangle2Edge topological mappings while their input changes
// (surface_mappings.cpp, SOFA's ...TopologicalMapping::updateTopologicalMappingTopDown): each output
// element keeps naming its input element (Loc2GlobVec) through the input's and the output's
// swap-and-pops; a removed cell's shared face joins the output as a face of the kept cell (flipped
// with flipNormals), Triangle2Edge's smallest vertex first; added quads give (p0,p1,p2), (p0,p2,p3);
// added triangles' border edges join and the edges now inside leave.
#include "penalty/mechanics/topological_mapping.hpp"
#include "penalty/mechanics/topological_mapping_changes.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <vector>

namespace penalty {
namespace {

/// An input container, its output and the mapping listening to the input, on one change scope.
template <class Mapping>
struct SurfaceMapped {
    MeshTopology in_mesh;
    MeshTopology out_mesh;
    std::unique_ptr<TopologyContainer> input;
    std::unique_ptr<TopologyContainer> output;
    std::unique_ptr<Mapping> mapping;
    template <class... Args>
    void wire(ElementType in_level, ElementType out_level, Args&&... args) {
        input = std::make_unique<TopologyContainer>(in_mesh, in_level, "input");
        output = std::make_unique<TopologyContainer>(out_mesh, out_level, "output");
        auto scope = std::make_shared<TopologyChangeScope>();
        input->set_scope(scope);
        output->set_scope(scope);
        mapping = std::make_unique<Mapping>(*input, *output, std::forward<Args>(args)...);
        input->add_listener(*mapping);
    }
};

template <std::size_t N, std::size_t M>
bool surface_vertices_within(std::array<PointId, N> part, std::array<PointId, M> whole) {
    return std::all_of(part.begin(), part.end(),
                       [&](PointId p) { return std::find(whole.begin(), whole.end(), p) != whole.end(); });
}

/// Every output element's vertices are those of (within, for Quad2Triangle) its input element.
template <class Out, class In>
void expect_surface_maps(const std::vector<ElementId>& loc2glob, const std::vector<Out>& out,
                         const std::vector<In>& in) {
    ASSERT_EQ(loc2glob.size(), out.size());
    for (std::size_t k = 0; k < out.size(); ++k) {
        ASSERT_GE(loc2glob[k], 0) << k;
        ASSERT_LT(std::size_t(loc2glob[k]), in.size()) << k;
        EXPECT_TRUE(surface_vertices_within(out[k], in[std::size_t(loc2glob[k])])) << "output element " << k;
    }
}

/// Two unit cubes along x sharing the face x = 1 (SOFA's hexahedron numbering).
const std::vector<Vec3> kTwoCubes{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1},
                                  {1, 1, 1}, {0, 1, 1}, {2, 0, 0}, {2, 1, 0}, {2, 0, 1}, {2, 1, 1}};

TEST(SurfaceMappings, Hexa2QuadARemovedHexahedronsSharedFaceJoinsAsAFaceOfTheKeptOne) {
    for (const bool flip : {false, true}) {
        SurfaceMapped<Hexa2QuadMappingFollower> m;
        m.in_mesh.set_hexahedra({{0, 1, 2, 3, 4, 5, 6, 7}, {1, 8, 9, 2, 5, 10, 11, 6}});
        m.out_mesh.set_quads(border_quads(m.in_mesh, flip));
        m.wire(ElementType::hexahedron, ElementType::quad, flip);
        ASSERT_EQ(m.out_mesh.quads().size(), 10U);
        expect_surface_maps(m.mapping->output_to_input(), m.out_mesh.quads(), m.in_mesh.quads());
        m.input->remove_hexahedra({1});
        const auto& out = m.out_mesh.quads();
        ASSERT_EQ(out.size(), 6U) << flip;
        expect_surface_maps(m.mapping->output_to_input(), out, m.in_mesh.quads());
        // the +x face (1,2,6,5) of the first cube (kHexaFaces[3]); flipped: (5,6,2,1)
        EXPECT_NE(std::find(out.begin(), out.end(), flip ? Quad{5, 6, 2, 1} : Quad{1, 2, 6, 5}), out.end()) << flip;
        // every face outward (inward when flipped) of the cube's centre
        const Vec3 centre(0.5, 0.5, 0.5);
        for (const Quad& q : out) {
            const auto x = [&](int j) { return kTwoCubes[std::size_t(q[std::size_t(j)])]; };
            const Vec3 n = (x(2) - x(0)).cross(x(3) - x(1));
            EXPECT_EQ(n.dot(x(0) - centre) > 0.0, !flip) << flip;
        }
        for (ElementId k = 0; k < 6; ++k) EXPECT_EQ(m.mapping->input_cell_of(k), 0) << flip;
        EXPECT_EQ(m.mapping->input_cell_of(6), -1);
    }
}

/// The strip of quads (0,1,2,3), (1,4,5,2) in the plane z = 0.
void surface_quad_strip(SurfaceMapped<Quad2TriangleMappingFollower>& m) {
    m.in_mesh.set_quads({{0, 1, 2, 3}, {1, 4, 5, 2}});
    m.out_mesh.set_triangles(triangles_of_quads(m.in_mesh.quads(), false, 2, 1));
    m.wire(ElementType::quad, ElementType::triangle);
}

TEST(SurfaceMappings, Quad2TriangleARemovedQuadsTwoTrianglesLeave) {
    SurfaceMapped<Quad2TriangleMappingFollower> m;
    surface_quad_strip(m);
    EXPECT_EQ(m.mapping->output_to_input(), (std::vector<ElementId>{0, 0, 1, 1}));
    m.input->remove_quads({0});
    // quad 1 is quad 0 now, its two triangles (init's split: (q1,q2,q0), (q3,q0,q2)) kept
    EXPECT_EQ(m.mapping->output_to_input(), (std::vector<ElementId>{0, 0}));
    const auto& out = m.out_mesh.triangles();
    ASSERT_EQ(out.size(), 2U);
    expect_surface_maps(m.mapping->output_to_input(), out, m.in_mesh.quads());
}

TEST(SurfaceMappings, Quad2TriangleAddedQuadsSplitAtTheirFirstVertex) {
    SurfaceMapped<Quad2TriangleMappingFollower> m;
    surface_quad_strip(m);
    m.input->add_points(2);
    m.input->add_quads({{4, 6, 7, 5}});
    EXPECT_EQ(m.mapping->output_to_input(), (std::vector<ElementId>{0, 0, 1, 1, 2, 2}));
    const auto& out = m.out_mesh.triangles();
    ASSERT_EQ(out.size(), 6U);
    EXPECT_EQ(out[4], (Triangle{4, 6, 7}));
    EXPECT_EQ(out[5], (Triangle{4, 7, 5}));
    EXPECT_EQ(m.output->num_points(), 8U);
    // removing the first quad now moves the last one's triangles down by SOFA's swaps
    m.input->remove_quads({0});
    ASSERT_EQ(out.size(), 4U);
    expect_surface_maps(m.mapping->output_to_input(), out, m.in_mesh.quads());
}

/// The unit square as triangles (0,1,2), (0,2,3): border edges the four sides.
void surface_square(SurfaceMapped<Triangle2EdgeMappingFollower>& m) {
    m.in_mesh.set_triangles({{0, 1, 2}, {0, 2, 3}});
    m.out_mesh.set_edges(border_edges(m.in_mesh));
    m.wire(ElementType::triangle, ElementType::edge);
}

bool surface_has_edge(const std::vector<Edge>& edges, PointId a, PointId b) {
    return std::any_of(edges.begin(), edges.end(),
                       [&](const Edge& e) { return (e[0] == a && e[1] == b) || (e[0] == b && e[1] == a); });
}

TEST(SurfaceMappings, Triangle2EdgeARemovedTrianglesSharedEdgeJoinsSmallestVertexFirst) {
    SurfaceMapped<Triangle2EdgeMappingFollower> m;
    surface_square(m);
    ASSERT_EQ(m.out_mesh.edges().size(), 4U);
    m.input->remove_triangles({1});
    const auto& out = m.out_mesh.edges();
    ASSERT_EQ(out.size(), 3U);
    expect_surface_maps(m.mapping->output_to_input(), out, m.in_mesh.edges());
    EXPECT_NE(std::find(out.begin(), out.end(), Edge{0, 2}), out.end());  // the diagonal, smallest first
    EXPECT_TRUE(surface_has_edge(out, 0, 1));
    EXPECT_TRUE(surface_has_edge(out, 1, 2));
    EXPECT_EQ(m.output->num_points(), 3U);  // point 3, isolated, removed (POINTSREMOVED forwarded)
}

TEST(SurfaceMappings, Triangle2EdgeAnAddedTrianglesEdgesJoinAndTheCoveredEdgeLeaves) {
    SurfaceMapped<Triangle2EdgeMappingFollower> m;
    m.in_mesh.set_triangles({{0, 1, 2}});
    m.out_mesh.set_edges(border_edges(m.in_mesh));
    m.wire(ElementType::triangle, ElementType::edge);
    m.input->add_points(1);
    m.input->add_triangles({{0, 2, 3}});
    const auto& out = m.out_mesh.edges();
    ASSERT_EQ(out.size(), 4U);
    expect_surface_maps(m.mapping->output_to_input(), out, m.in_mesh.edges());
    EXPECT_FALSE(surface_has_edge(out, 0, 2));  // inside now
    EXPECT_TRUE(surface_has_edge(out, 2, 3));
    EXPECT_TRUE(surface_has_edge(out, 0, 3));
    EXPECT_EQ(m.output->num_points(), 4U);
}

}  // namespace
}  // namespace penalty
