// TetrahedralCorotationalFEMForceField (SOFA's corotational tetrahedra): a single tetrahedron under
// uniaxial stretch against linear elasticity (each method), rotation invariance, the stiffness
// against finite differences, the updated strain-displacement matrix in closed form,
// localStiffnessFactor, the polar + computeGlobalMatrix quirk, equality with
// TetrahedronFEMForceField at the default options, and the force and product on threads (the
// bits of one thread).
#include "penalty/mechanics/corotational_fem.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"

#include "penalty_test/element_products_on_threads.hpp"
#include "penalty_test/force_field_derivatives.hpp"
#include "penalty_test/grid_meshes.hpp"
#include "penalty_test/same_bits.hpp"
#include "penalty_test/sanitizer.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>

namespace penalty {
namespace {

constexpr double kYoung = 1000.0, kPoisson = 0.3, kEdge = 2.0, kStrain = 1e-3;
constexpr FemMethod kMethods[] = {FemMethod::Small, FemMethod::Large, FemMethod::Polar};

/// The corner tetrahedron (0,0,0), (L,0,0), (0,L,0), (0,0,L).
struct CornerTetrahedron {
    Vec3Object state;
    std::vector<Tetrahedron> tetrahedra{{0, 1, 2, 3}};
    CornerTetrahedron() {
        state.position = {Vec3(0, 0, 0), Vec3(kEdge, 0, 0), Vec3(0, kEdge, 0), Vec3(0, 0, kEdge)};
        state.init();
    }
    /// Stretch along x: x ← (1 + ε)·x (an affine field: uniform strain εxx = ε).
    void stretch(double strain) {
        for (std::size_t i = 0; i < 4; ++i)
            state.position[i] = state.rest_position[i] + Vec3(strain * state.rest_position[i].x(), 0, 0);
    }
};

/// Linear elasticity under uniform strain εxx = ε: σxx = (λ+2μ)ε, σyy = σzz = λε, and the nodal
/// forces f_k = −V σ ∇N_k of a linear tetrahedron (V = L³/6; ∇N1..3 = e_x/L, e_y/L, e_z/L).
std::array<Vec3, 4> uniaxial_forces(double strain, double area_scale_y = 1.0, double area_scale_z = 1.0) {
    const double lambda = kYoung * kPoisson / ((1 + kPoisson) * (1 - 2 * kPoisson));
    const double mu = kYoung / (2 * (1 + kPoisson));
    const Vec3 sigma((lambda + 2 * mu) * strain, lambda * strain, lambda * strain);
    const double area = kEdge * kEdge / 6.0;  // V·|∇N_k| = L³/6 · 1/L
    std::array<Vec3, 4> f;
    f[1] = Vec3(-area * sigma.x(), 0, 0);
    f[2] = Vec3(0, -area * area_scale_y * sigma.y(), 0);
    f[3] = Vec3(0, 0, -area * area_scale_z * sigma.z());
    f[0] = -(f[1] + f[2] + f[3]);
    return f;
}

TEST(TetrahedralCorotationalFem, UniaxialStretchGivesTheLinearElasticForcesForEachMethod) {
    const std::array<Vec3, 4> expected = uniaxial_forces(kStrain);
    for (FemMethod method : kMethods) {
        CornerTetrahedron t;
        TetrahedralCorotationalFEMForceField ff(t.state, t.tetrahedra, kYoung, kPoisson, {.method = method});
        ff.init();
        t.stretch(kStrain);
        ff.accumulate_force();
        // the corner tetrahedron's large frame and polar rotation are the identity under this stretch
        for (std::size_t k = 0; k < 4; ++k)
            EXPECT_TRUE(t.state.force[k].isApprox(expected[k], 1e-12) ||
                        (t.state.force[k] - expected[k]).norm() < 1e-12)
                << "method " << int(method) << " node " << k << ": " << t.state.force[k].transpose() << " vs "
                << expected[k].transpose();
        // energy ½uᵀK^e u = V·½σ:ε = L³/6 · ½(λ+2μ)ε²
        const double lambda = kYoung * kPoisson / ((1 + kPoisson) * (1 - 2 * kPoisson));
        const double mu = kYoung / (2 * (1 + kPoisson));
        const double energy = std::pow(kEdge, 3) / 6 * 0.5 * (lambda + 2 * mu) * kStrain * kStrain;
        EXPECT_NEAR(ff.potential_energy(), energy, 1e-12 * energy);
    }
}

TEST(TetrahedralCorotationalFem, UpdatedStiffnessUsesTheCurrentShapeAndTheRestVolume) {
    // updateStiffnessMatrix: J from the stretched shape, K^e = J D Jᵀ/(36 V⁰). Under x ← (1+ε)x the
    // cofactors of nodes 2 and 3 grow by (1+ε) (they are edge products containing e1), node 1's not.
    const double strain = 0.05;
    const std::array<Vec3, 4> expected = uniaxial_forces(strain, 1 + strain, 1 + strain);
    for (FemMethod method : {FemMethod::Large, FemMethod::Polar}) {
        CornerTetrahedron t;
        TetrahedralCorotationalFEMForceField ff(t.state, t.tetrahedra, kYoung, kPoisson,
                                                {.method = method, .update_stiffness = true});
        ff.init();
        t.stretch(strain);
        ff.accumulate_force();
        for (std::size_t k = 0; k < 4; ++k)
            EXPECT_LT((t.state.force[k] - expected[k]).norm(), 1e-12 * expected[1].norm()) << "node " << k;
    }
    // method small ignores the option (accumulateForceSmall never rebuilds J)
    CornerTetrahedron t;
    TetrahedralCorotationalFEMForceField ff(t.state, t.tetrahedra, kYoung, kPoisson,
                                            {.method = FemMethod::Small, .update_stiffness = true});
    ff.init();
    t.stretch(strain);
    ff.accumulate_force();
    const std::array<Vec3, 4> linear = uniaxial_forces(strain);
    for (std::size_t k = 0; k < 4; ++k) EXPECT_LT((t.state.force[k] - linear[k]).norm(), 1e-12 * linear[1].norm());
}

TEST(TetrahedralCorotationalFem, LargeAndPolarForcesRotateWithTheBody) {
    const Mat3 q = Eigen::AngleAxisd(1.1, Vec3(0.3, -1, 0.7).normalized()).toRotationMatrix();
    const Vec3 shift(0.4, -2, 1.5);
    for (FemMethod method : {FemMethod::Large, FemMethod::Polar}) {
        for (bool update : {false, true}) {
            CornerTetrahedron t;
            TetrahedralCorotationalFEMForceField ff(t.state, t.tetrahedra, kYoung, kPoisson,
                                                    {.method = method, .update_stiffness = update});
            ff.init();
            t.state.position = {Vec3(0.01, -0.02, 0.0), Vec3(2.1, 0.05, -0.03), Vec3(-0.04, 1.9, 0.02),
                                Vec3(0.03, 0.01, 2.2)};
            const auto force = [&] {
                std::fill(t.state.force.begin(), t.state.force.end(), Vec3::Zero());
                ff.accumulate_force();
            };
            force();
            const std::vector<Vec3> f = t.state.force;
            EXPECT_GT(f[1].norm(), 1.0);
            for (auto& p : t.state.position) p = q * p + shift;
            force();
            for (std::size_t k = 0; k < 4; ++k)
                EXPECT_LT((t.state.force[k] - q * f[k]).norm(), 1e-10 * f[1].norm()) << "node " << k;
            // a rigid motion of the rest shape is stress-free
            for (std::size_t k = 0; k < 4; ++k) t.state.position[k] = q * t.state.rest_position[k] + shift;
            force();
            for (std::size_t k = 0; k < 4; ++k) EXPECT_LT(t.state.force[k].norm(), 1e-10);
        }
    }
}

struct Block {
    RegularGridTopology grid{{3, 2, 3}, Vec3(0, 0, 0), Vec3(2, 1, 1.5)};
    MeshTopology topo = test::kuhn_tetrahedra(grid);
    Vec3Object state;
    Block() {
        state.position = grid.points();
        state.init();
    }
};

TEST(TetrahedralCorotationalFem, SmallMethodStiffnessAndEnergyMatchFiniteDifferences) {
    Block b;
    TetrahedralCorotationalFEMForceField ff(b.state, b.topo.tetrahedra(), 800, 0.35,
                                            {.method = FemMethod::Small, .local_stiffness_factors = {1, 2.5, 0.5}});
    ff.init();
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-0.05, 0.05);
    for (auto& p : b.state.position) p += Vec3(u(rng), u(rng), u(rng));
    const test::DerivativeTolerances tol{.dforce_vs_fd = 1e-7, .assembled_vs_dforce = 1e-12, .force_vs_energy = 1e-7};
    const test::ForceFieldDerivatives d = test::check_force_field_derivatives(ff, b.state, tol);
    EXPECT_GT(d.force.cwiseAbs().maxCoeff(), 1.0);
    EXPECT_TRUE(d.k_dforce.isApprox(d.k_dforce.transpose(), 1e-12));
}

TEST(TetrahedralCorotationalFem, CorotationalStiffnessMatchesFiniteDifferencesAtARotatedRestState) {
    // K = −Rᵀ K^e R leaves out ∂R/∂x, as SOFA: exact where the element is stress-free.
    const Mat3 q = Eigen::AngleAxisd(0.7, Vec3(1, 2, -1).normalized()).toRotationMatrix();
    for (FemMethod method : {FemMethod::Large, FemMethod::Polar}) {
        for (bool update : {false, true}) {
            Block b;
            TetrahedralCorotationalFEMForceField ff(b.state, b.topo.tetrahedra(), 800, 0.35,
                                                    {.method = method, .update_stiffness = update});
            ff.init();
            for (std::size_t i = 0; i < b.state.position.size(); ++i)
                b.state.position[i] = q * b.state.rest_position[i] + Vec3(1, -0.5, 0.2);
            const test::DerivativeTolerances tol{
                .dforce_vs_fd = 1e-6, .assembled_vs_dforce = 1e-12, .force_vs_energy = std::nullopt};
            const test::ForceFieldDerivatives d = test::check_force_field_derivatives(ff, b.state, tol);
            EXPECT_GT(d.k_fd.cwiseAbs().maxCoeff(), 100.0);
            EXPECT_LT(d.force.cwiseAbs().maxCoeff(), 1e-9);
            EXPECT_TRUE(d.k_dforce.isApprox(d.k_dforce.transpose(), 1e-12));
        }
    }
}

TEST(TetrahedralCorotationalFem, DeformedStiffnessIsTheRotatedElementStiffness) {
    // away from rest, add_dforce is −Rᵀ K^e R·dx with R and K^e of the last add_force (updated J
    // when asked), which differs from ∂f/∂x by the rotation-derivative terms: check it directly.
    Block b;
    TetrahedralCorotationalFEMForceField ff(b.state, b.topo.tetrahedra(), 800, 0.35, {.update_stiffness = true});
    ff.init();
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(-0.1, 0.1);
    for (auto& p : b.state.position) p += Vec3(u(rng), u(rng), u(rng));
    ff.accumulate_force();
    std::vector<Vec3> dx(b.state.num_dofs());
    for (auto& v : dx) v = Vec3(u(rng), u(rng), u(rng));
    std::vector<Vec3> df(dx.size(), Vec3::Zero());
    ff.add_dforce(df, dx, 2.0, 0.0);
    std::vector<Vec3> expected(dx.size(), Vec3::Zero());
    for (std::size_t e = 0; e < ff.tetrahedra().size(); ++e) {
        const auto& t = ff.tetrahedra()[e];
        std::array<Vec3, 4> p;
        for (std::size_t k = 0; k < 4; ++k) p[k] = b.state.position[static_cast<std::size_t>(t[k])];
        const Mat3 r = tetrahedron_rotation(p, FemMethod::Large);
        // K^e from the current local shape: (V_current² / V_rest)·BᵀDB
        std::array<Vec3, 4> local;
        for (std::size_t k = 0; k < 4; ++k) local[k] = r * (p[k] - p[0]);
        Mat3 m;
        m << local[1] - local[0], local[2] - local[0], local[3] - local[0];
        Mat3 m0;
        for (int k = 0; k < 3; ++k)
            m0.col(k) = b.state.rest_position[static_cast<std::size_t>(t[static_cast<std::size_t>(k + 1)])] -
                        b.state.rest_position[static_cast<std::size_t>(t[0])];
        const double v = std::abs(m.determinant()) / 6, v0 = std::abs(m0.determinant()) / 6;
        const Mat3 inv = m.inverse();
        const std::array<Vec3, 4> g{-(inv.row(0) + inv.row(1) + inv.row(2)).transpose(), inv.row(0).transpose(),
                                    inv.row(1).transpose(), inv.row(2).transpose()};
        const Eigen::Matrix<double, 12, 12> ke =
            tetrahedron_stiffness_from_gradients(g, isotropic_elasticity(800, 0.35), v * v / v0);
        Eigen::Matrix<double, 12, 1> local_dx;
        for (std::size_t k = 0; k < 4; ++k)
            local_dx.segment<3>(3 * static_cast<Eigen::Index>(k)) = r * dx[static_cast<std::size_t>(t[k])];
        const Eigen::Matrix<double, 12, 1> fl = ke * local_dx;
        for (std::size_t k = 0; k < 4; ++k)
            expected[static_cast<std::size_t>(t[k])] -=
                2.0 * r.transpose() * fl.segment<3>(3 * static_cast<Eigen::Index>(k));
    }
    double scale = 0, diff = 0;
    for (std::size_t i = 0; i < df.size(); ++i) {
        scale = std::max(scale, expected[i].norm());
        diff = std::max(diff, (df[i] - expected[i]).norm());
    }
    EXPECT_GT(scale, 1.0);
    EXPECT_LT(diff, 1e-10 * scale);
}

TEST(TetrahedralCorotationalFem, LocalStiffnessFactorScalesYoungsModulusOfElementIMOverN) {
    Block b;
    const std::size_t n = b.topo.tetrahedra().size();
    TetrahedralCorotationalFEMForceField plain(b.state, b.topo.tetrahedra(), 800, 0.35);
    TetrahedralCorotationalFEMForceField scaled(b.state, b.topo.tetrahedra(), 800, 0.35,
                                                {.local_stiffness_factors = {2, 3, 0.5}});
    plain.init();
    scaled.init();
    for (std::size_t e = 0; e < n; ++e) {
        const double factor = std::array{2.0, 3.0, 0.5}[e * 3 / n];
        EXPECT_EQ(scaled.stiffness_factor(e), factor);
        EXPECT_TRUE(scaled.element_stiffness()[e].isApprox(factor * plain.element_stiffness()[e], 1e-14)) << e;
    }
    EXPECT_EQ(scaled.stiffness_factor(0), 2.0);
    EXPECT_EQ(scaled.stiffness_factor(n - 1), 0.5);
}

TEST(TetrahedralCorotationalFem, DefaultOptionsGiveTetrahedronFemBitsOnEveryKernelPath) {
    // with its default options the component computes what TetrahedronFEMForceField computes: the
    // same element data and loops (tetrahedron_large_blocks.hpp), so the same force, energy and
    // product to the bit, on each kernel path, and every path the scalar one's bits
    std::vector<KernelPath> paths{KernelPath::scalar};
    for (const KernelPath path : {KernelPath::avx, KernelPath::avx512}) {
        if (kernel_path_supported(path)) {
            paths.push_back(path);
        } else {  // a path this CPU cannot run is refused, naming the component
            CornerTetrahedron t;
            TetrahedralCorotationalFEMForceField ff(t.state, t.tetrahedra, kYoung, kPoisson);
            EXPECT_THROW(ff.set_kernel_path(path), std::invalid_argument);
        }
    }
    for (FemMethod method : kMethods) {
        std::vector<Vec3> first_force, first_product;
        for (const KernelPath path : paths) {
            Block a, b;
            TetrahedralCorotationalFEMForceField corotational(a.state, a.topo.tetrahedra(), 500, 0.4,
                                                              {.method = method});
            TetrahedronFEMForceField tetrahedron(b.state, b.topo, 500, 0.4, method);
            corotational.set_kernel_path(path);
            tetrahedron.set_kernel_path(path);
            corotational.init();
            tetrahedron.init();
            EXPECT_EQ(corotational.kernel_path(), path);
            std::mt19937 rng(11);
            std::uniform_real_distribution<double> u(-0.2, 0.2);
            for (std::size_t i = 0; i < a.state.position.size(); ++i) {
                a.state.position[i] += Vec3(u(rng), u(rng), u(rng));
                b.state.position[i] = a.state.position[i];
            }
            corotational.accumulate_force();
            tetrahedron.accumulate_force();
            std::vector<Vec3> dx(a.state.num_dofs());
            for (auto& v : dx) v = Vec3(u(rng), u(rng), u(rng));
            std::vector<Vec3> df_a(dx.size(), Vec3::Zero()), df_b(dx.size(), Vec3::Zero());
            corotational.add_dforce(df_a, dx, -0.37, 0.0);
            tetrahedron.add_dforce(df_b, dx, -0.37, 0.0);
            const std::string where = "method " + std::to_string(int(method)) + ", path " + to_string(path);
            EXPECT_GT(std::max_element(a.state.force.begin(), a.state.force.end(),
                                       [](const Vec3& l, const Vec3& r) { return l.norm() < r.norm(); })
                          ->norm(),
                      1.0)
                << where;
            EXPECT_TRUE(test::same_bits(a.state.force, b.state.force)) << where;
            EXPECT_TRUE(test::same_bits(df_a, df_b)) << where;
            EXPECT_TRUE(test::same_bits(corotational.potential_energy(), tetrahedron.potential_energy())) << where;
            if (first_force.empty()) {
                first_force = a.state.force;
                first_product = df_a;
            }
            EXPECT_TRUE(test::same_bits(a.state.force, first_force)) << where;
            EXPECT_TRUE(test::same_bits(df_a, first_product)) << where;
        }
    }
}

TEST(TetrahedralCorotationalFem, ElementStiffnessOnSofasPathIsMadeWhenAskedAsTheCommonPathMakesItAtInit) {
    // on SOFA's path no product reads K^e: it is made by the first element_stiffness() (an
    // assembling solver's add_stiffness_triplets), the matrices computeGlobalMatrix's path makes
    // at init, to the bit; the assembled matrix is the product's and the force's Jacobian
    for (const FemMethod method : kMethods) {
        Block a, b;
        std::mt19937 rng(17);
        std::uniform_real_distribution<double> u(-0.03, 0.03);
        for (std::size_t i = 0; i < a.state.rest_position.size(); ++i) {
            a.state.rest_position[i] += Vec3(u(rng), u(rng), u(rng));
            b.state.rest_position[i] = a.state.rest_position[i];
        }
        a.state.position = a.state.rest_position;
        b.state.position = b.state.rest_position;
        const std::vector<double> factors{1.0, 3.0};
        TetrahedralCorotationalFEMForceField on_demand(a.state, a.topo.tetrahedra(), 700, 0.3,
                                                       {.method = method, .local_stiffness_factors = factors});
        TetrahedralCorotationalFEMForceField at_init(
            b.state, b.topo.tetrahedra(), 700, 0.3,
            {.method = method, .local_stiffness_factors = factors, .assembling = true});
        on_demand.init();
        at_init.init();
        const auto& k = on_demand.element_stiffness();
        ASSERT_EQ(k.size(), a.topo.tetrahedra().size());
        EXPECT_EQ(std::memcmp(k.data(), at_init.element_stiffness().data(), k.size() * sizeof(k[0])), 0) << int(method);
        // at rest (stress-free: the rotation derivative SOFA leaves out is 0 there)
        const test::DerivativeTolerances tol{
            .dforce_vs_fd = 1e-6, .assembled_vs_dforce = 1e-12, .force_vs_energy = std::nullopt};
        const test::ForceFieldDerivatives d = test::check_force_field_derivatives(on_demand, a.state, tol);
        EXPECT_GT(d.k_fd.cwiseAbs().maxCoeff(), 10.0) << int(method);
    }
}

TEST(TetrahedralCorotationalFem, PolarWithComputeGlobalMatrixAddsNoForceButKeepsItsStiffness) {
    // SOFA's accumulateForcePolar with computeGlobalMatrix only logs an error (reproduced).
    CornerTetrahedron t;
    TetrahedralCorotationalFEMForceField ff(t.state, t.tetrahedra, kYoung, kPoisson,
                                            {.method = FemMethod::Polar, .assembling = true});
    ff.init();
    t.stretch(0.01);
    ff.accumulate_force();
    for (const Vec3& f : t.state.force) EXPECT_EQ(f, Vec3::Zero());
    std::vector<Vec3> dx(4, Vec3::Zero()), df(4, Vec3::Zero());
    dx[1] = Vec3(1e-3, 0, 0);
    ff.add_dforce(df, dx, 1.0, 0.0);
    // K^e's (b, b, x, x) entry: V·(λ+2μ)·|∇N_b|² = L(λ+2μ)/6 (the frame is the identity here)
    const double lambda = kYoung * kPoisson / ((1 + kPoisson) * (1 - 2 * kPoisson));
    const double mu = kYoung / (2 * (1 + kPoisson));
    EXPECT_NEAR(df[1].x(), -kEdge * (lambda + 2 * mu) / 6 * 1e-3, 1e-12);
}

TEST(TetrahedralCorotationalFem, RefusesDegenerateTetrahedraAndBadMaterial) {
    CornerTetrahedron t;
    t.state.rest_position[3] = Vec3(1, 1, 0);  // in the plane of the others
    TetrahedralCorotationalFEMForceField flat(t.state, t.tetrahedra, kYoung, kPoisson);
    EXPECT_THROW(flat.init(), std::invalid_argument);
    CornerTetrahedron u;
    EXPECT_THROW(TetrahedralCorotationalFEMForceField(u.state, u.tetrahedra, kYoung, 0.5), std::invalid_argument);
    EXPECT_THROW(TetrahedralCorotationalFEMForceField(u.state, u.tetrahedra, -1.0, 0.3), std::invalid_argument);
}

TEST(TetrahedralCorotationalFem, ForceAndProductOnThreadsAreTheBitsOfOneThread) {
    // 13 × 12 × 9 cells, 8 424 tetrahedra (above OrderedScatter::kMinElements), in the grid's
    // order and shuffled; SOFA's operations (small, large, polar) and the common path
    // (updateStiffnessMatrix: each K^e from the current shape)
    const RegularGridTopology grid({14, 13, 10}, Vec3::Zero(), Vec3(1.3, 1.2, 0.9));
    const MeshTopology spatial = test::kuhn_tetrahedra(grid);
    ASSERT_GE(spatial.tetrahedra().size(), detail::OrderedScatter::kMinElements);
    std::vector<Tetrahedron> shuffled = spatial.tetrahedra();
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(4));
    const CorotationalFemOptions options[] = {{.method = FemMethod::Small},
                                              {.method = FemMethod::Large},
                                              {.method = FemMethod::Polar},
                                              {.method = FemMethod::Large, .update_stiffness = true},
                                              {.method = FemMethod::Polar, .update_stiffness = true}};
    for (const bool shuffle : {false, true})
        for (const CorotationalFemOptions& o : options) {
            Vec3Object state;
            state.position = grid.points();
            state.init();
            TetrahedralCorotationalFEMForceField fem(state, shuffle ? shuffled : spatial.tetrahedra(), 3e4, 0.35, o);
            fem.init();
            const test::ElementProducts one = test::element_products_on_threads(fem, state, 1, 0.02, -0.37);
            EXPECT_EQ(one.chunks, 0U);
            EXPECT_GT(one.energy, 0.0);
            for (const int threads : test::thread_counts_to_compare({2, 3, 8})) {
                const test::ElementProducts many = test::element_products_on_threads(fem, state, threads, 0.02, -0.37);
                const std::string where = "method " + std::to_string(static_cast<int>(o.method)) +
                                          (o.update_stiffness ? ", updated stiffness, " : ", ") +
                                          std::to_string(threads) + " threads" + (shuffle ? ", shuffled" : "");
                EXPECT_GT(many.chunks, 1U) << where;
                EXPECT_GT(many.deferred, 0U) << where;
                EXPECT_TRUE(test::same_vectors_bits(many.force, one.force)) << where;
                EXPECT_TRUE(test::same_vectors_bits(many.product, one.product)) << where;
                EXPECT_EQ(std::memcmp(&many.energy, &one.energy, sizeof(double)), 0) << where;
            }
        }
}

}  // namespace
}  // namespace penalty
