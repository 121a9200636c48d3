// BarycentricMapping onto a HexahedronSetTopologyContainer, as SOFA's
// BarycentricMapperHexahedronSetTopology (BarycentricMapperTopologyContainer::init): each point's
// coordinates in the parallelepiped of its hexahedron's three edges from vertex 0, trilinear weights
// of them; after a removal every point is mapped again onto the remaining hexahedra with the
// current positions (SOFA's processTopologicalChanges: clear, then init).
#include "penalty/mechanics/mapping.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty_test/scene_text.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>

namespace penalty {
namespace {

TEST(HexahedronMappingFollowers, SetHexahedraMapInTheParallelepipedOfThreeEdgesAsSofa) {
    // a hexahedron that is no parallelepiped: SOFA's coordinates b = (x1 − x0, x3 − x0, x4 − x0)⁻¹
    // (p − x0), weights trilinear in b; the mapped point is then not p (the inverse trilinear map
    // of map_on_hexahedra gives p back)
    Vec3Object in, out;
    in.position = {Vec3(0, 0, 0), Vec3(1, 0, 0),   Vec3(1.2, 1.1, 0.1), Vec3(0, 1, 0),
                   Vec3(0, 0, 1), Vec3(1, 0.1, 1), Vec3(1, 1, 1.3),     Vec3(-0.1, 1, 1)};
    in.init();
    const std::vector<Vec3> points{Vec3(0.6, 0.7, 0.8)};
    out.position = points;
    out.init();
    MeshTopology topo;
    topo.set_hexahedra({{0, 1, 2, 3, 4, 5, 6, 7}});
    BarycentricMapping sofa(in, out), inverse(in, out);
    sofa.map_on_set_hexahedra(topo, in.position, points);
    inverse.map_on_hexahedra(topo, in.position, points);

    Eigen::Matrix3d edges;
    edges.col(0) = in.position[1] - in.position[0];
    edges.col(1) = in.position[3] - in.position[0];
    edges.col(2) = in.position[4] - in.position[0];
    const Vec3 b = edges.inverse() * (points[0] - in.position[0]);
    const auto w = trilinear_weights(b);
    ASSERT_EQ(sofa.weights()[0].count, 8);
    Vec3 mapped = Vec3::Zero(), back = Vec3::Zero();
    for (std::size_t k = 0; k < 8; ++k) {
        EXPECT_EQ(sofa.weights()[0].entries[k].index, Index(k));
        EXPECT_NEAR(sofa.weights()[0].entries[k].weight, w[k], 1e-15) << k;
        mapped += sofa.weights()[0].entries[k].weight * in.position[k];
        back +=
            inverse.weights()[0].entries[k].weight * in.position[std::size_t(inverse.weights()[0].entries[k].index)];
    }
    EXPECT_GT((mapped - points[0]).norm(), 1e-3);  // SOFA's approximation
    EXPECT_LT((back - points[0]).norm(), 1e-12);
}

std::string hmf_grid_scene() {
    // 2×2×2 hexahedra of 10 cm; skin points inside hexahedra 0 and 5, and one outside
    std::string points, hexahedra;
    const auto id = [](int x, int y, int z) { return x + 3 * (y + 3 * z); };
    for (int z = 0; z <= 2; ++z)
        for (int y = 0; y <= 2; ++y)
            for (int x = 0; x <= 2; ++x)
                points += std::to_string(0.1 * x + 0.004 * ((x * 7 + y * 3 + z) % 3)) + " " + std::to_string(0.1 * y) +
                          " " + std::to_string(0.1 * z + 0.003 * ((x + y * 5) % 2)) + "  ";
    for (int z = 0; z < 2; ++z)
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x)
                for (const int v : {id(x, y, z), id(x + 1, y, z), id(x + 1, y + 1, z), id(x, y + 1, z), id(x, y, z + 1),
                                    id(x + 1, y, z + 1), id(x + 1, y + 1, z + 1), id(x, y + 1, z + 1)})
                    hexahedra += std::to_string(v) + " ";
    return R"(<Node name="root" gravity="0 -9.81 0" dt="0.01"><Node name="body">
  <EulerImplicitSolver/><CGLinearSolver iterations="50" tolerance="1e-12" threshold="1e-12"/>
  <HexahedronSetTopologyContainer name="volume" position=")" +
           points + R"(" hexahedra=")" + hexahedra + R"("/>
  <HexahedronSetTopologyModifier/>
  <MechanicalObject name="dofs"/>
  <UniformMass vertexMass="0.05"/>
  <HexahedronFEMForceField youngModulus="3000" poissonRatio="0.3" method="large"/>
  <FixedProjectiveConstraint indices="6 7 8 15 16 17 24 25"/>
  <Node name="skin"><MechanicalObject name="skinDofs" position="0.03 0.04 0.05  0.15 0.02 0.13  0.22 0.1 0.1"/>
    <BarycentricMapping name="attach"/></Node>
</Node></Node>
)";
}

TEST(HexahedronMappingFollowers, BarycentricMappingMapsItsPointsAgainOntoTheRemainingHexahedra) {
    auto s = test::build(hmf_grid_scene());
    for (int k = 0; k < 3; ++k) s->step();
    BarycentricMapping* mapping = nullptr;
    for (const auto& child : s->simulation().root().children()[0]->children())
        if (auto* m = dynamic_cast<BarycentricMapping*>(child->mapping())) mapping = m;
    ASSERT_NE(mapping, nullptr);
    const auto* in = dynamic_cast<const Vec3Object*>(mapping->from());
    auto* out = dynamic_cast<Vec3Object*>(mapping->to());
    ASSERT_TRUE(in && out);
    const std::vector<Vec3> mapped = out->position;

    s->remove_elements("volume", ElementType::hexahedron, {0, 5});
    ASSERT_EQ(s->topology_container("volume").mesh().hexahedra().size(), 6u);
    BarycentricMapping fresh(const_cast<Vec3Object&>(*in), *out);
    fresh.map_on_set_hexahedra(s->topology_container("volume").mesh(), in->position, mapped);
    ASSERT_EQ(mapping->weights().size(), fresh.weights().size());
    for (std::size_t i = 0; i < fresh.weights().size(); ++i) {
        ASSERT_EQ(mapping->weights()[i].count, 8) << i;
        for (std::size_t k = 0; k < 8; ++k) {
            EXPECT_EQ(mapping->weights()[i].entries[k].index, fresh.weights()[i].entries[k].index) << i;
            EXPECT_EQ(mapping->weights()[i].entries[k].weight, fresh.weights()[i].entries[k].weight) << i;
        }
    }
    for (int k = 0; k < 3; ++k) s->step();
    for (const Vec3& p : out->position) EXPECT_TRUE(p.allFinite());
}

}  // namespace
}  // namespace penalty
