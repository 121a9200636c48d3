// TriangularFEMForceField (SOFA's co-rotational membrane): closed forms for one stretched
// triangle, rigid-motion invariance, derivatives against finite differences, the product on
// threads (the bits of one thread).
#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/triangular_fem.hpp"

#include "penalty_test/element_products_on_threads.hpp"
#include "penalty_test/force_field_derivatives.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>

namespace penalty {
namespace {

/// A 3×3-vertex square [0, 2]² in the x-y plane cut into 8 triangles (alternating diagonals).
MeshTopology square_mesh(std::vector<Vec3>& points) {
    points.clear();
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) points.emplace_back(i, j, 0);
    std::vector<Triangle> t;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            const PointId a = 3 * j + i, b = a + 1, c = a + 3, d = a + 4;
            if ((i + j) % 2 == 0) {
                t.push_back({a, b, d});
                t.push_back({a, d, c});
            } else {
                t.push_back({a, b, c});
                t.push_back({b, d, c});
            }
        }
    MeshTopology topo;
    topo.set_triangles(t);
    return topo;
}

struct Membrane {
    Vec3Object state;
    MeshTopology topology;
    std::unique_ptr<TriangularFEMForceField> ff;

    Membrane(FemMethod method, double young = 1000.0, double poisson = 0.3) {
        std::vector<Vec3> x;
        topology = square_mesh(x);
        state.position = x;
        state.init();
        ff = std::make_unique<TriangularFEMForceField>(state, topology, young, poisson, method);
        ff->init();
    }
    void force() {
        std::fill(state.force.begin(), state.force.end(), Vec3::Zero());
        ff->accumulate_force();
    }
};

Mat3 some_rotation() { return Eigen::AngleAxisd(0.7, Vec3(1, 2, -0.5).normalized()).toRotationMatrix(); }

TEST(TriangularFEM, StretchedTriangleMatchesClosedForm) {
    // a = 0, b = (1, 0), c = (0, 1), stretched by λ along x. SOFA's strain is measured with the
    // CURRENT local triangle (J of d_b = (λ, 0), d_c = (0, 1)) and D = rest − current:
    //   ε = ((1 − λ)/λ, 0, 0), σ = E'A₀ (ε, ν ε, 0) with E' = E/(1 − ν²), A₀ = ½;
    //   f_b,x = J(2,0) σ₀ = E'A₀ (1 − λ)/λ², f_c,y = J(5,1) σ₁ = E'A₀ ν (1 − λ)/λ, f_a = −f_b − f_c.
    for (const FemMethod method : {FemMethod::Large, FemMethod::Small}) {
        Vec3Object s;
        s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
        s.init();
        MeshTopology topo;
        topo.set_triangles({{0, 1, 2}});
        const double e = 200.0, nu = 0.3, lambda = 1.1;
        TriangularFEMForceField ff(s, topo, e, nu, method);
        ff.init();
        EXPECT_DOUBLE_EQ(ff.rest_areas()[0], 0.5);
        s.position[1].x() = lambda;
        std::fill(s.force.begin(), s.force.end(), Vec3::Zero());
        ff.accumulate_force();
        const double stiff = e / (1 - nu * nu) * 0.5;
        const double fbx = stiff * (1 - lambda) / (lambda * lambda);
        const double fcy = stiff * nu * (1 - lambda) / lambda;
        EXPECT_NEAR((s.force[1] - Vec3(fbx, 0, 0)).norm(), 0.0, 1e-12);
        EXPECT_NEAR((s.force[2] - Vec3(0, fcy, 0)).norm(), 0.0, 1e-12);
        EXPECT_NEAR((s.force[0] + s.force[1] + s.force[2]).norm(), 0.0, 1e-12);
        const double strain = (1 - lambda) / lambda;
        EXPECT_NEAR(ff.potential_energy(), 0.5 * stiff * strain * strain, 1e-12);
    }
}

TEST(TriangleFEM, ThicknessPlaneStrainAndQuadsAsSofasOlderComponent) {
    // TriangleFEMForceField: Dₐ scaled by thickness; plane strain E/((1+ν)(1−2ν))·[[1−ν, ν, 0], …]:
    // with λ as above, f_b,x = k (1−ν)(1−λ)/λ², f_c,y = k ν (1−λ)/λ, k = E/((1+ν)(1−2ν))·t·A₀.
    const double e = 200.0, nu = 0.3, lambda = 1.1, thickness = 2.0;
    for (const FemMethod method : {FemMethod::Large, FemMethod::Small})
        for (const bool plane_strain : {false, true}) {
            Vec3Object s;
            s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
            s.init();
            MeshTopology topo;
            topo.set_triangles({{0, 1, 2}});
            TriangularFEMForceField ff(s, topo,
                                       TriangleFemParameters{.young_modulus = e,
                                                             .poisson_ratio = nu,
                                                             .method = method,
                                                             .flavor = TriangleFemFlavor::TriangleFEM,
                                                             .thickness = thickness,
                                                             .plane_strain = plane_strain});
            ff.init();
            s.position[1].x() = lambda;
            std::fill(s.force.begin(), s.force.end(), Vec3::Zero());
            ff.accumulate_force();
            const double k =
                plane_strain ? e / ((1 + nu) * (1 - 2 * nu)) * thickness * 0.5 : e / (1 - nu * nu) * thickness * 0.5;
            const double diagonal = plane_strain ? 1 - nu : 1.0;
            EXPECT_NEAR((s.force[1] - Vec3(k * diagonal * (1 - lambda) / (lambda * lambda), 0, 0)).norm(), 0.0, 1e-12);
            EXPECT_NEAR((s.force[2] - Vec3(0, k * nu * (1 - lambda) / lambda, 0)).norm(), 0.0, 1e-12);
        }
    // a quad mesh without triangles: each quad q split into (q0, q1, q2), (q0, q2, q3)
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
    s.init();
    MeshTopology quads;
    quads.set_quads({{0, 1, 2, 3}});
    TriangularFEMForceField split(s, quads, TriangleFemParameters{.flavor = TriangleFemFlavor::TriangleFEM});
    ASSERT_EQ(split.triangles().size(), 2u);
    EXPECT_EQ(split.triangles()[1], (Triangle{0, 2, 3}));
    EXPECT_TRUE(TriangularFEMForceField(s, quads, 10.0, 0.3).triangles().empty());  // Triangular: triangles only
    EXPECT_THROW(TriangularFEMForceField(
                     s, quads, TriangleFemParameters{.flavor = TriangleFemFlavor::TriangleFEM, .thickness = 0}),
                 std::invalid_argument);
}

TEST(TriangularFEM, LargeMethodIsInvariantUnderRigidMotion) {
    Membrane m(FemMethod::Large);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.05, 0.05);
    std::vector<Vec3> deformed = m.state.rest_position;
    for (Vec3& p : deformed) p += Vec3(u(rng), u(rng), u(rng));
    m.state.position = deformed;
    m.force();
    const std::vector<Vec3> f0 = m.state.force;
    const double e0 = m.ff->potential_energy();
    EXPECT_GT(e0, 1e-3);
    const Mat3 r = some_rotation();
    const Vec3 t(3, -1, 2);
    for (std::size_t i = 0; i < deformed.size(); ++i) m.state.position[i] = r * deformed[i] + t;
    m.force();
    for (std::size_t i = 0; i < f0.size(); ++i) EXPECT_NEAR((m.state.force[i] - r * f0[i]).norm(), 0.0, 1e-10) << i;
    EXPECT_NEAR(m.ff->potential_energy(), e0, 1e-12 * e0);
    // and the rest shape moved rigidly is stress-free
    for (std::size_t i = 0; i < deformed.size(); ++i) m.state.position[i] = r * m.state.rest_position[i] + t;
    m.force();
    for (const Vec3& f : m.state.force) EXPECT_LT(f.norm(), 1e-10);
}

TEST(TriangularFEM, SmallMethodActsInTheWorldXYPlaneOnly) {
    Membrane m(FemMethod::Small);
    for (Vec3& p : m.state.position) p.z() += 0.3 * p.x();  // out of plane: no force in SOFA's small
    m.force();
    for (const Vec3& f : m.state.force) EXPECT_LT(f.norm(), 1e-12);
    m.state.position[4] += Vec3(0.1, -0.05, 0.2);
    m.force();
    double in_plane = 0;
    for (const Vec3& f : m.state.force) {
        EXPECT_EQ(f.z(), 0.0);
        in_plane = std::max(in_plane, f.norm());
    }
    EXPECT_GT(in_plane, 1.0);
}

TEST(TriangularFEM, StiffnessIsExactAtARotatedRestShape) {
    // K = −Rᵀ[J Dₐ Jᵀ]R ignores dR/dx and dJ/dx, which multiply the stress: exact where it is zero.
    for (const FemMethod method : {FemMethod::Large, FemMethod::Small}) {
        Membrane m(method);
        if (method == FemMethod::Large)
            for (Vec3& p : m.state.position) p = some_rotation() * p + Vec3(1, 2, 3);
        const auto d = test::check_force_field_derivatives(*m.ff, m.state, {1e-6, 1e-12, std::nullopt});
        EXPECT_GT(d.k_fd.cwiseAbs().maxCoeff(), 100.0);  // not vacuous
        EXPECT_TRUE(test::near_relative(d.k_dforce, Eigen::MatrixXd(d.k_dforce.transpose()), 1e-12));
    }
}

TEST(TriangularFEM, StiffnessApproximatesTheTangentUnderSmallStrain) {
    // Away from the rest shape the dropped terms are O(stress): relative error of the order of
    // the strain (here ≈ 1e-3), and the assembled matrix equals add_dforce exactly.
    Membrane m(FemMethod::Large);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1e-3, 1e-3);
    for (Vec3& p : m.state.position) p = some_rotation() * (p + Vec3(u(rng), u(rng), u(rng)));
    test::check_force_field_derivatives(*m.ff, m.state, {2e-2, 1e-12, std::nullopt});
}

TEST(TriangularFEM, BadInputThrows) {
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
    s.init();
    MeshTopology topo;
    topo.set_triangles({{0, 1, 2}});
    EXPECT_THROW(TriangularFEMForceField(s, topo, -1.0, 0.3), std::invalid_argument);
    EXPECT_THROW(TriangularFEMForceField(s, topo, 10.0, 0.5), std::invalid_argument);
    TriangularFEMForceField degenerate(s, topo, 10.0, 0.3);
    EXPECT_THROW(degenerate.init(), std::invalid_argument);  // collinear rest triangle
    MeshTopology out_of_range;
    out_of_range.set_triangles({{0, 1, 5}});
    TriangularFEMForceField bad_index(s, out_of_range, 10.0, 0.3);
    EXPECT_THROW(bad_index.init(), std::invalid_argument);
}

TEST(TriangularFEMForceField, LargeProductFollowsEachForceEvaluationOnEveryKernelPath) {
    // the product reads the frames and J of the last add_force (packed for the kernel): after a
    // second force evaluation at other positions it is a fresh field's product there, and the
    // scalar and AVX paths give the same bits
    std::vector<KernelPath> paths = {KernelPath::scalar};
    if (kernel_path_supported(KernelPath::avx)) paths.push_back(KernelPath::avx);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-0.2, 0.2);
    std::vector<Vec3> moved;
    for (const TriangleFemFlavor flavor : {TriangleFemFlavor::TriangularFEM, TriangleFemFlavor::TriangleFEM}) {
        const TriangleFemParameters p{.young_modulus = 1000.0, .poisson_ratio = 0.3, .flavor = flavor};
        std::vector<std::vector<Vec3>> products;
        for (const KernelPath path : paths) {
            Membrane m(FemMethod::Large);
            m.ff = std::make_unique<TriangularFEMForceField>(m.state, m.topology, p);
            m.ff->init();
            m.ff->set_kernel_path(path);
            EXPECT_EQ(m.ff->kernel_path(), path);
            const auto product = [&] {
                m.state.dx.assign(m.state.position.size(), Vec3::Zero());
                for (std::size_t i = 0; i < m.state.dx.size(); ++i)
                    m.state.dx[i] = Vec3(0.01 * double(i), -0.02, 0.005 * double(i % 3));
                m.state.df.assign(m.state.position.size(), Vec3::Zero());
                m.ff->accumulate_dforce(-0.5, 0.0);
                return m.state.df;
            };
            m.force();
            const std::vector<Vec3> at_rest = product();
            if (moved.empty())
                for (const Vec3& x : m.state.position) moved.push_back(x + Vec3(u(rng), u(rng), u(rng)));
            m.state.position = moved;
            m.force();
            const std::vector<Vec3> after = product();
            EXPECT_NE(after, at_rest);  // new frames and J
            Membrane fresh(FemMethod::Large);
            fresh.ff = std::make_unique<TriangularFEMForceField>(fresh.state, fresh.topology, p);
            fresh.ff->init();
            fresh.ff->set_kernel_path(KernelPath::scalar);
            fresh.state.position = moved;
            fresh.force();
            fresh.state.dx = m.state.dx;
            fresh.state.df.assign(moved.size(), Vec3::Zero());
            fresh.ff->accumulate_dforce(-0.5, 0.0);
            EXPECT_EQ(0, std::memcmp(after.data(), fresh.state.df.data(), after.size() * sizeof(Vec3)))
                << to_string(path);
            products.push_back(after);
        }
        for (const auto& other : products)
            EXPECT_EQ(0, std::memcmp(other.data(), products[0].data(), other.size() * sizeof(Vec3)));
    }
    EXPECT_THROW(Membrane(FemMethod::Large).ff->set_kernel_path(KernelPath::avx512), std::invalid_argument);
}

TEST(TriangularFEMForceField, ProductOnThreadsIsTheBitsOfOneThread) {
    // both flavors and methods (SOFA's operations for TriangleFEM and large, the others' for
    // TriangularFEM small); the force and the product on TBB's threads
    const TriangleFemParameters parameters[] = {{.method = FemMethod::Large},
                                                {.method = FemMethod::Small},
                                                {.method = FemMethod::Large, .flavor = TriangleFemFlavor::TriangleFEM},
                                                {.method = FemMethod::Small, .flavor = TriangleFemFlavor::TriangleFEM}};
    for (const bool shuffle : {false, true})
        for (const TriangleFemParameters& p : parameters) {
            const test::TriangleSheet sheet(shuffle);
            ASSERT_GE(sheet.topology.triangles().size(), detail::OrderedScatter::kMinElements);
            Vec3Object state;
            state.position = sheet.points;
            state.init();
            TriangularFEMForceField fem(state, sheet.topology, p);
            fem.init();
            test::expect_threads_give_one_threads_bits(
                fem, state,
                std::string(p.flavor == TriangleFemFlavor::TriangleFEM ? "TriangleFEM" : "TriangularFEM") +
                    (p.method == FemMethod::Large ? " large" : " small") + (shuffle ? ", shuffled" : ""));
        }
}

// A triangle degenerate at x (its three corners at one point, and so its neighbours): SOFA's pass
// stops at the first (accumulateForceLarge's catch: break), the triangles after it keeping their
// J and frames and adding nothing. On threads the pass runs as if none were, finds one, puts f
// back and runs the loop on one thread: force, energy and the product after it (which reads the
// kept frames) are one thread's bits, and a vertex of only later triangles gets no force.
TEST(TriangularFEMForceField, ADegenerateTriangleOnThreadsStopsThePassAsOnOneThread) {
    const TriangleFemParameters parameters[] = {{.method = FemMethod::Large},
                                                {.method = FemMethod::Small},
                                                {.method = FemMethod::Large, .flavor = TriangleFemFlavor::TriangleFEM},
                                                {.method = FemMethod::Small, .flavor = TriangleFemFlavor::TriangleFEM}};
    const test::TriangleSheet sheet(false);
    const std::vector<Triangle>& triangles = sheet.topology.triangles();
    constexpr std::size_t kCollapsed = 4000;
    std::vector<Vec3> x = sheet.points;
    for (Vec3& p : x) p *= 1.01;  // stretched: every triangle has a force
    for (const PointId v : triangles[kCollapsed])
        x[static_cast<std::size_t>(v)] = x[static_cast<std::size_t>(triangles[kCollapsed][0])];
    // the first degenerate triangle, and a vertex of none before it
    std::vector<std::size_t> first_triangle(x.size(), triangles.size());
    for (std::size_t e = triangles.size(); e-- > 0;)
        for (const PointId v : triangles[e]) first_triangle[static_cast<std::size_t>(v)] = e;
    std::size_t stop = triangles.size();
    for (std::size_t e = 0; e < triangles.size() && stop == triangles.size(); ++e) {
        const auto& t = triangles[e];
        if (x[std::size_t(t[0])] == x[std::size_t(t[1])] || x[std::size_t(t[1])] == x[std::size_t(t[2])] ||
            x[std::size_t(t[0])] == x[std::size_t(t[2])])
            stop = e;
    }
    ASSERT_LE(stop, kCollapsed);
    ASSERT_GT(stop, detail::OrderedScatter::kMinElements / 4);  // inside the sheet: not a chunk's first
    const auto later = static_cast<std::size_t>(
        std::find_if(first_triangle.begin(), first_triangle.end(), [&](std::size_t e) { return e > stop + 100; }) -
        first_triangle.begin());
    ASSERT_LT(later, x.size());
    std::mt19937 random(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<Vec3> dx(x.size()), v(x.size(), Vec3::Zero());
    for (Vec3& d : dx) d = Vec3(u(random), u(random), u(random));
    for (const TriangleFemParameters& p : parameters) {
        const std::string what =
            std::string(p.flavor == TriangleFemFlavor::TriangleFEM ? "TriangleFEM" : "TriangularFEM") +
            (p.method == FemMethod::Large ? " large" : " small");
        Vec3Object state;
        state.position = sheet.points;
        state.init();
        test::ElementProducts one;
        for (const int threads : {1, 2, 8}) {
            TriangularFEMForceField fem(state, sheet.topology, p);
            fem.init();
            test::ElementProducts run;
            run.force.assign(x.size(), Vec3::Zero());
            run.product.assign(x.size(), Vec3::Zero());
            tbb::task_arena(threads).execute([&] {
                fem.add_force(run.force, x, v);
                fem.add_dforce(run.product, dx, -0.37, 0.0);
            });
            run.energy = fem.potential_energy();
            if (threads == 1) {
                one = run;
                EXPECT_EQ(one.force[later], Vec3::Zero()) << what;  // the pass stopped before its triangles
                EXPECT_NE(one.force[static_cast<std::size_t>(triangles[0][0])], Vec3::Zero()) << what;
                continue;
            }
            const std::string where = what + ", " + std::to_string(threads) + " threads";
            EXPECT_TRUE(test::same_vectors_bits(run.force, one.force)) << where;
            EXPECT_TRUE(test::same_vectors_bits(run.product, one.product)) << where;
            EXPECT_EQ(std::memcmp(&run.energy, &one.energy, sizeof(double)), 0) << where;
        }
    }
}

}  // namespace
}  // namespace penalty
