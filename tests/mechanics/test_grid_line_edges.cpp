// RegularGridTopology::mesh on a grid of one row (SOFA's GridUpdate::updateEdges): no quad, so no
// triangle, so the edges are the segments along the axis even with computeTriangleList (a beam's
// topology in SOFA's Edge2QuadTopologicalMapping example).
#include "penalty/mechanics/regular_grid_topology.hpp"

#include <gtest/gtest.h>

namespace penalty {
namespace {

TEST(RegularGridLine, EdgesAlongTheAxisWhenThereIsNoTriangle) {
    const RegularGridTopology line({5, 1, 1}, Vec3(0, 0, 0), Vec3(4, 0, 0));
    for (const bool triangles : {true, false}) {
        const MeshTopology m = line.mesh(triangles);
        EXPECT_TRUE(m.triangles().empty());
        ASSERT_EQ(m.edges().size(), 4u);
        for (std::size_t i = 0; i < 4; ++i) {
            EXPECT_EQ(m.edges()[i][0], PointId(i));
            EXPECT_EQ(m.edges()[i][1], PointId(i + 1));
        }
    }
    // a 2 x 2 grid keeps the edges of its two triangles: the quad's four sides and a diagonal
    const RegularGridTopology square({2, 2, 1}, Vec3(0, 0, 0), Vec3(1, 1, 0));
    EXPECT_EQ(square.mesh(true).edges().size(), 5u);
    EXPECT_EQ(square.mesh(false).edges().size(), 4u);
}

}  // namespace
}  // namespace penalty
