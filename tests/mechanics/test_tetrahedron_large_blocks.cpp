// The tetrahedra's lane blocks and their loops (src/mechanics/tetrahedron_large_blocks.hpp): an
// element's lane holds J's cofactors (6V times the shape-function gradients), D/(36V) and R; the
// data survive a change of width and a swap-and-pop copy, the lanes past the last element are 0;
// the products of methods large and small are −k·Rᵀ·J·D/(36V)·Jᵀ·R·dx and −k·J·D/(36V)·Jᵀ·dx
// (closed form, dense), every kernel path the scalar one's bits; polar's force leaves its frame in
// the lane.
#include "mechanics/tetrahedron_large_blocks.hpp"

#include "penalty_test/same_bits.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <random>
#include <string>
#include <vector>

namespace penalty {
namespace {

std::vector<KernelPath> supported_paths() {
    std::vector<KernelPath> paths{KernelPath::scalar};
    for (const KernelPath path : {KernelPath::avx, KernelPath::avx512})
        if (kernel_path_supported(path)) paths.push_back(path);
    return paths;
}

/// Random tetrahedra on a cloud of points, each with a clear volume; rest local coordinates,
/// frames and materials stored as TetrahedronFEMForceField's init stores them.
struct RandomMesh {
    std::vector<Vec3> x0;
    std::vector<Tetrahedron> elements;
    std::vector<std::array<Vec3, 4>> rest_local;
    std::vector<Mat3> frame;
    std::vector<detail::TetrahedronMaterial> material;

    RandomMesh(std::size_t count, FemMethod method, std::mt19937& rng) {
        std::uniform_real_distribution<double> u(-1, 1);
        for (int i = 0; i < 14; ++i) x0.emplace_back(u(rng), u(rng), u(rng));
        while (elements.size() < count) {
            Tetrahedron t{};
            for (auto& v : t) v = static_cast<PointId>(rng() % x0.size());
            const std::array<Vec3, 4> p = points(t, x0);
            if (std::abs((p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0])) < 0.05) continue;
            elements.push_back(t);
            Mat3 r;
            rest_local.push_back(detail::rest_coordinates(method, p, r));
            frame.push_back(r);
            material.push_back(detail::material_over_volume(1e4, 0.3, p));
        }
    }
    static std::array<Vec3, 4> points(const Tetrahedron& t, const std::vector<Vec3>& x) {
        return {x[std::size_t(t[0])], x[std::size_t(t[1])], x[std::size_t(t[2])], x[std::size_t(t[3])]};
    }
    void store(detail::TetrahedronLargeBlocks& blocks, KernelPath path) const {
        detail::resize_large_blocks(blocks, elements.size(), path);
        for (std::size_t e = 0; e < elements.size(); ++e)
            detail::store_large_element(blocks, e, material[e], rest_local[e], frame[e]);
    }
};

/// J (12×6, rows 3k + component, Voigt columns xx, yy, zz, xy, yz, zx) of cofactor vectors c_k.
Eigen::Matrix<double, 12, 6> strain_displacement(const std::array<Vec3, 4>& c) {
    Eigen::Matrix<double, 12, 6> j = Eigen::Matrix<double, 12, 6>::Zero();
    for (int k = 0; k < 4; ++k) {
        const Vec3& g = c[std::size_t(k)];
        j(3 * k, 0) = j(3 * k + 1, 3) = j(3 * k + 2, 5) = g.x();
        j(3 * k + 1, 1) = j(3 * k, 3) = j(3 * k + 2, 4) = g.y();
        j(3 * k + 2, 2) = j(3 * k + 1, 4) = j(3 * k, 5) = g.z();
    }
    return j;
}

/// The cofactor vectors c_k = 6V·∇N_k of local coordinates q: c1 = e2×e3, c2 = e3×e1, c3 = e1×e2,
/// c0 = −(c1 + c2 + c3), e_i = q_i − q_0.
std::array<Vec3, 4> cofactors(const std::array<Vec3, 4>& q) {
    const Vec3 e1 = q[1] - q[0], e2 = q[2] - q[0], e3 = q[3] - q[0];
    const Vec3 c1 = e2.cross(e3), c2 = e3.cross(e1), c3 = e1.cross(e2);
    return {-(c1 + c2 + c3), c1, c2, c3};
}

TEST(TetrahedronLargeBlocks, AnElementsLaneHoldsItsCofactorsMaterialAndFrameAcrossWidthsAndCopies) {
    std::mt19937 rng(5);
    const RandomMesh mesh(11, FemMethod::Large, rng);
    for (const KernelPath path : supported_paths()) {
        detail::TetrahedronLargeBlocks blocks;
        mesh.store(blocks, path);
        EXPECT_TRUE(detail::large_blocks_fit(blocks, 11, path));
        EXPECT_FALSE(detail::large_blocks_fit(blocks, 17, path));
        // to the other width and back: every element keeps its lane
        const KernelPath other = path == KernelPath::avx512 ? KernelPath::avx : KernelPath::avx512;
        if (kernel_path_supported(other)) {
            detail::resize_large_blocks(blocks, 11, other);
            EXPECT_TRUE(detail::large_blocks_fit(blocks, 11, other));
            detail::resize_large_blocks(blocks, 11, path);
        }
        for (std::size_t e = 0; e < 11; ++e) {
            EXPECT_TRUE(detail::large_block_rotation(blocks, e) == mesh.frame[e]) << e;
            // J through the lane accessors against the cross products of the rest shape
            const Eigen::Matrix<double, 12, 6> expected = strain_displacement(cofactors(mesh.rest_local[e]));
            std::visit(
                [&](const auto& b) {
                    using Block = typename std::remove_cvref_t<decltype(b)>::value_type;
                    const detail::LaneStrainDisplacement<detail::OneLane, Block> j{b[e / Block::kLanes],
                                                                                   e % Block::kLanes};
                    const detail::LaneMaterial<detail::OneLane, Block> m{b[e / Block::kLanes], e % Block::kLanes};
                    const double scale = expected.cwiseAbs().maxCoeff();
                    for (int r = 0; r < 12; ++r)
                        for (int c = 0; c < 6; ++c) {
                            if (expected(r, c) != 0.0) {
                                EXPECT_NEAR(j(r, c), expected(r, c), 1e-14 * scale);
                            }
                        }
                    for (int i = 0; i < 3; ++i)
                        for (int k = 0; k < 3; ++k) EXPECT_EQ(m(i, k), mesh.material[e](i, k));
                    for (int i = 3; i < 6; ++i) EXPECT_EQ(m(i, i), mesh.material[e](i, i));
                },
                blocks);
        }
        // the lanes past the last element are 0 (11 elements: lanes 3 … W − 1 of the last block)
        std::visit(
            [](const auto& b) {
                const auto& last = b.back();
                for (std::size_t lane = 11 % last.kLanes; lane < last.kLanes; ++lane) {
                    EXPECT_EQ(last.shear[0][lane], 0.0);
                    EXPECT_EQ(last.cofactor[3][2][lane], 0.0);
                    EXPECT_EQ(last.rotation[4][lane], 0.0);
                }
            },
            blocks);
        // a swap-and-pop: element 10's data into element 3's lane
        detail::copy_large_element(blocks, 10, 3);
        EXPECT_TRUE(detail::large_block_rotation(blocks, 3) == mesh.frame[10]);
    }
}

TEST(TetrahedronLargeBlocks, ProductsAreTheDenseRotatedStiffnessOnEveryPathWithTheScalarBits) {
    std::mt19937 rng(8);
    for (const FemMethod method : {FemMethod::Large, FemMethod::Small}) {
        const RandomMesh mesh(21, method, rng);
        std::uniform_real_distribution<double> u(-1, 1);
        std::vector<Vec3> dx(mesh.x0.size());
        for (auto& v : dx) v = Vec3(u(rng), u(rng), u(rng));
        const double k = -0.7;
        // −k·Rᵀ·J·D/(36V)·Jᵀ·R·dx per element (small: R = I)
        std::vector<Vec3> expected(dx.size(), Vec3::Zero());
        for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
            const Eigen::Matrix<double, 12, 6> j = strain_displacement(cofactors(mesh.rest_local[e]));
            const Mat3 r = method == FemMethod::Small ? Mat3::Identity() : mesh.frame[e];
            Eigen::Matrix<double, 12, 1> local;
            for (int v = 0; v < 4; ++v) local.segment<3>(3 * v) = r * dx[std::size_t(mesh.elements[e][std::size_t(v)])];
            const Eigen::Matrix<double, 12, 1> force = j * (mesh.material[e] * (j.transpose() * local));
            for (int v = 0; v < 4; ++v)
                expected[std::size_t(mesh.elements[e][std::size_t(v)])] -=
                    k * (r.transpose() * force.segment<3>(3 * v));
        }
        std::vector<Vec3> scalar_df;
        for (const KernelPath path : supported_paths()) {
            detail::TetrahedronLargeBlocks blocks;
            mesh.store(blocks, path);
            std::vector<Vec3> df(dx.size(), Vec3::Zero());
            const detail::DeferredTerms none;
            const detail::ElementRange all{0, mesh.elements.size()};
            if (method == FemMethod::Small) detail::small_blocks_dforce(blocks, mesh.elements, all, df, dx, k, none);
            else detail::large_blocks_dforce(blocks, path, mesh.elements, all, df, dx, k, none);
            const std::string where =
                std::string(method == FemMethod::Small ? "small" : "large") + ", path " + to_string(path);
            double scale = 0.0, diff = 0.0;
            for (std::size_t i = 0; i < df.size(); ++i) {
                scale = std::max(scale, expected[i].norm());
                diff = std::max(diff, (df[i] - expected[i]).norm());
            }
            EXPECT_GT(scale, 1.0) << where;
            EXPECT_LT(diff, 1e-12 * scale) << where;
            if (scalar_df.empty()) scalar_df = df;
            EXPECT_TRUE(test::same_bits(df, scalar_df)) << where;
        }
    }
}

TEST(TetrahedronLargeBlocks, PolarForceLeavesEachElementsPolarFrameInItsLane) {
    std::mt19937 rng(13);
    RandomMesh mesh(9, FemMethod::Polar, rng);
    detail::TetrahedronLargeBlocks blocks;
    mesh.store(blocks, KernelPath::scalar);
    std::vector<Vec3> x = mesh.x0;
    const Mat3 q = Eigen::AngleAxisd(0.4, Vec3(1, 1, 0).normalized()).toRotationMatrix();
    for (Vec3& p : x) p = q * p;  // a rigid rotation: no force, the frames turned by q
    std::vector<Vec3> f(x.size(), Vec3::Zero());
    const double energy =
        detail::per_element_blocks_force(blocks, FemMethod::Polar, mesh.rest_local, mesh.elements,
                                         {0, mesh.elements.size()}, f, x, detail::DeferredTerms{}, nullptr, nullptr);
    EXPECT_NEAR(energy, 0.0, 1e-9);
    for (const Vec3& v : f) EXPECT_LT(v.norm(), 1e-9);
    for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
        const std::array<Vec3, 4> p = RandomMesh::points(mesh.elements[e], x);
        EXPECT_TRUE(detail::large_block_rotation(blocks, e) ==
                    polar_rotation(detail::edge_rows(p[0], p[1], p[2], p[3])))
            << e;
        EXPECT_TRUE(detail::large_block_rotation(blocks, e).isApprox(mesh.frame[e] * q.transpose(), 1e-12)) << e;
    }
}

}  // namespace
}  // namespace penalty
