#include "penalty/mechanics/fem.hpp"
#include "penalty/mechanics/regular_grid_topology.hpp"

#include "penalty_test/force_field_derivatives.hpp"
#include "penalty_test/grid_meshes.hpp"

#include <gtest/gtest.h>
#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>

namespace penalty {
namespace {

using test::kuhn_tetrahedra;

bool is_boundary(const RegularGridTopology& g, int i, int j, int k) {
    return i == 0 || j == 0 || k == 0 || i == g.n()[0] - 1 || j == g.n()[1] - 1 || k == g.n()[2] - 1;
}

/// Patch test: x = x0 + G x0 (uniform strain ε = sym(G)); interior nodal forces vanish and the
/// energy equals ½ ε:D:ε · volume.
template <class Field>
void patch_test(const MeshTopology& topo, const RegularGridTopology& g, FemMethod method) {
    Vec3Object s;
    s.position = g.points();
    s.init();
    const double e = 1000.0, nu = 0.3;
    Field ff(s, topo, e, nu, method);
    ff.init();
    Mat3 grad;
    grad << 1e-3, 2e-4, -3e-4, 2e-4, -5e-4, 1e-4, -3e-4, 1e-4, 7e-4;  // symmetric: pure strain
    for (std::size_t i = 0; i < s.position.size(); ++i) s.position[i] = s.rest_position[i] + grad * s.rest_position[i];
    std::fill(s.force.begin(), s.force.end(), Vec3::Zero());
    ff.accumulate_force();
    int interior = 0;
    double max_boundary = 0;
    for (int k = 0; k < g.n()[2]; ++k)
        for (int j = 0; j < g.n()[1]; ++j)
            for (int i = 0; i < g.n()[0]; ++i) {
                const Vec3& f = s.force[static_cast<std::size_t>(g.point_index(i, j, k))];
                if (is_boundary(g, i, j, k)) {
                    max_boundary = std::max(max_boundary, f.norm());
                } else {
                    // rounding only: TetrahedronFEMForceField's small method forms δ from world
                    // coordinates as SOFA does (x⁰_b − x⁰_a − p_b + p_a, coordinates up to 3 m),
                    // about 1e-12 N here; a wrong element leaves 1e-4 N or more
                    EXPECT_LT(f.norm(), 1e-11) << i << " " << j << " " << k;
                    ++interior;
                }
            }
    EXPECT_GT(interior, 0);
    EXPECT_GT(max_boundary, 1e-4);  // the boundary carries the traction: the test is not vacuous
    Eigen::Matrix<double, 6, 1> eps;
    eps << grad(0, 0), grad(1, 1), grad(2, 2), 2 * grad(0, 1), 2 * grad(1, 2), 2 * grad(0, 2);
    const Vec3 ext = g.max() - g.min();
    const double expected = 0.5 * eps.dot(isotropic_elasticity(e, nu) * eps) * ext.prod();
    EXPECT_NEAR(ff.potential_energy(), expected, 1e-10 * expected);
}

TEST(TetrahedronFEM, PatchTestSmall) {
    RegularGridTopology g({4, 4, 4}, Vec3(0, 0, 0), Vec3(1.5, 1, 2));
    const MeshTopology topo = kuhn_tetrahedra(g);
    patch_test<TetrahedronFEMForceField>(topo, g, FemMethod::Small);
}

TEST(HexahedronFEM, PatchTestSmall) {
    RegularGridTopology g({4, 3, 5}, Vec3(0, 0, 0), Vec3(1.5, 1, 2));
    patch_test<HexahedronFEMForceField>(g.mesh(), g, FemMethod::Small);
}

/// The shared derivative check (K by FD, assembled K, f = −∂E/∂x for the small-strain method, whose
/// energy is the potential of its force) at a rotated, optionally deformed, configuration; K is
/// symmetric, and a rigid motion is stress-free for the corotational method.
template <class Field>
void check_fem_derivatives(const MeshTopology& topo, std::vector<Vec3> rest, FemMethod method, bool rotate_only) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    Vec3Object s;
    s.position = rest;
    s.init();
    Field ff(s, topo, 500.0, 0.35, method);
    ff.init();
    const Mat3 r = Eigen::AngleAxisd(0.8, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
    for (std::size_t i = 0; i < rest.size(); ++i) {
        s.position[i] = r * rest[i] + Vec3(0.3, -1, 2);
        if (!rotate_only) s.position[i] += 0.05 * Vec3(u(rng), u(rng), u(rng));
    }
    // the small-strain energy is the potential of its force; the corotational one is not
    const test::DerivativeTolerances tol{
        .dforce_vs_fd = 1e-6,
        .assembled_vs_dforce = 1e-12,
        .force_vs_energy = method == FemMethod::Small ? std::optional<double>(1e-6) : std::nullopt};
    const test::ForceFieldDerivatives d = test::check_force_field_derivatives(ff, s, tol);
    EXPECT_GT(d.k_fd.cwiseAbs().maxCoeff(), 10.0);
    EXPECT_TRUE(d.k_dforce.isApprox(d.k_dforce.transpose(), 1e-12));
    if (method != FemMethod::Small && rotate_only) {
        EXPECT_LT(d.force.cwiseAbs().maxCoeff(), 1e-10);  // a rigid motion is stress-free
    }
}

TEST(TetrahedronFEM, StiffnessMatchesFiniteDifferences) {
    RegularGridTopology g({2, 2, 3}, Vec3(0, 0, 0), Vec3(1, 1.2, 2));
    const MeshTopology topo = kuhn_tetrahedra(g);
    check_fem_derivatives<TetrahedronFEMForceField>(topo, g.points(), FemMethod::Small, false);
    check_fem_derivatives<TetrahedronFEMForceField>(topo, g.points(), FemMethod::Large, true);
    // svd: its own force (accumulateForceSVD), large's product (polar: TetrahedronFEMPolar)
    check_fem_derivatives<TetrahedronFEMForceField>(topo, g.points(), FemMethod::Svd, true);
}

TEST(HexahedronFEM, StiffnessMatchesFiniteDifferences) {
    RegularGridTopology g({3, 2, 2}, Vec3(0, 0, 0), Vec3(2, 1, 1.5));
    check_fem_derivatives<HexahedronFEMForceField>(g.mesh(), g.points(), FemMethod::Small, false);
    check_fem_derivatives<HexahedronFEMForceField>(g.mesh(), g.points(), FemMethod::Large, true);
}

TEST(TetrahedronFEM, LargeMethodIsInvariantUnderRotation) {
    // Corotational forces of a deformed block, rotated, are the rotated forces.
    RegularGridTopology g({3, 2, 2}, Vec3(0, 0, 0), Vec3(2, 1, 1));
    const MeshTopology topo = kuhn_tetrahedra(g);
    Vec3Object s;
    s.position = g.points();
    s.init();
    TetrahedronFEMForceField ff(s, topo, 100, 0.3, FemMethod::Large);
    ff.init();
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-0.05, 0.05);
    std::vector<Vec3> deformed = s.rest_position;
    for (auto& p : deformed) p += Vec3(u(rng), u(rng), u(rng));
    s.position = deformed;
    ff.accumulate_force();
    const std::vector<Vec3> f1 = s.force;
    const Mat3 r = Eigen::AngleAxisd(1.1, Vec3(0.2, 1, -0.4).normalized()).toRotationMatrix();
    for (std::size_t i = 0; i < deformed.size(); ++i) s.position[i] = r * deformed[i];
    std::fill(s.force.begin(), s.force.end(), Vec3::Zero());
    ff.accumulate_force();
    double fmax = 0;
    for (std::size_t i = 0; i < f1.size(); ++i) {
        EXPECT_TRUE((s.force[i] - r * f1[i]).norm() < 1e-10);
        fmax = std::max(fmax, f1[i].norm());
    }
    EXPECT_GT(fmax, 1e-2);
}

/// Forces of one tetrahedron (rest: the unit corner tetrahedron) at positions `x`.
std::vector<Vec3> one_tetrahedron_forces(FemMethod method, const std::vector<Vec3>& x) {
    MeshTopology topo;
    topo.set_tetrahedra({Tetrahedron{0, 1, 2, 3}});
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    s.init();
    TetrahedronFEMForceField ff(s, topo, 100, 0.3, method);
    ff.init();
    s.position = x;
    ff.accumulate_force();
    return s.force;
}

TEST(TetrahedronFEM, SvdIsPolarUnlessTheElementIsInverted) {
    // TetrahedronFEMForceField::accumulateForceSVD: det(F) >= 1e-6 -> the polar rotation.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-0.1, 0.1);
    std::vector<Vec3> x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    for (auto& p : x) p += Vec3(u(rng), u(rng), u(rng));
    const Mat3 r = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
    for (auto& p : x) p = r * p;
    const auto svd = one_tetrahedron_forces(FemMethod::Svd, x);
    const auto polar = one_tetrahedron_forces(FemMethod::Polar, x);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(svd[i], polar[i]);
    // Inverted: p3 pushed through the base, F = diag(1, 1, -0.5). The stable decomposition gives
    // U = F·V·S⁻¹ = diag(1, 1, -1), inverted, so its column of the smallest value is negated:
    // R = I, and the force is the linear one (rest frame = world frame here).
    const std::vector<Vec3> inverted = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, -0.5)};
    const auto svd_inverted = one_tetrahedron_forces(FemMethod::Svd, inverted);
    const auto small_inverted = one_tetrahedron_forces(FemMethod::Small, inverted);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_LT((svd_inverted[i] - small_inverted[i]).norm(), 1e-12) << i;
    // it pushes the point back up (+z), with the linear stiffness
    EXPECT_GT(svd_inverted[3].z(), 10.0);
}

TEST(TetrahedronFEM, LargeMethodMatchesTheUniaxialStretchClosedForm) {
    // Unit corner tetrahedron, vertex 1 moved to (1 + ε, 0, 0): the frame stays the world's,
    // ε_xx = ε, σ = (λ+2μ, λ, λ)·ε, and f_k = −V·σ·∇N_k with V = 1/6, ∇N_0 = (−1, −1, −1).
    const double eps = 1e-3, e = 100, nu = 0.3;
    const double lambda = e * nu / ((1 + nu) * (1 - 2 * nu)), mu = e / (2 * (1 + nu));
    const auto f =
        one_tetrahedron_forces(FemMethod::Large, {Vec3(0, 0, 0), Vec3(1 + eps, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)});
    const double axial = (lambda + 2 * mu) * eps / 6, lateral = lambda * eps / 6;
    const std::array<Vec3, 4> expected{Vec3(axial, lateral, lateral), Vec3(-axial, 0, 0), Vec3(0, -lateral, 0),
                                       Vec3(0, 0, -lateral)};
    for (std::size_t k = 0; k < 4; ++k) EXPECT_LT((f[k] - expected[k]).norm(), 1e-12 * axial) << k;
}

/// Forces of the unit corner tetrahedron stretched by ε along x, evaluated `evaluations` times
/// with the plasticity p (TetrahedronFEMForceField::computeForce with plasticMaxThreshold > 0).
std::vector<Vec3> plastic_stretch_forces(const TetrahedronFEMForceField::Plasticity& p, int evaluations, double eps,
                                         std::array<double, 6>* plastic = nullptr) {
    MeshTopology topo;
    topo.set_tetrahedra({Tetrahedron{0, 1, 2, 3}});
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    s.init();
    TetrahedronFEMForceField ff(s, topo, 100, 0.3, FemMethod::Large);
    ff.init();
    ff.set_plasticity(p);
    s.position[1] = Vec3(1 + eps, 0, 0);
    for (int i = 0; i < evaluations; ++i) {
        std::fill(s.force.begin(), s.force.end(), Vec3::Zero());
        ff.accumulate_force();
    }
    if (plastic != nullptr) *plastic = ff.plastic_strain(0);
    return s.force;
}

TEST(TetrahedronFEM, PlasticityCreepsAndClampsThePlasticStrain) {
    // Uniaxial strain ε = (1e-3, 0, ...): with creep c each evaluation moves εp by c·(ε − εp)
    // while |ε − εp| > yield, so the force is (1 − c)ⁿ of the elastic one after n evaluations;
    // |εp| is clamped to plasticMaxThreshold along its direction.
    const double eps = 1e-3;
    const auto elastic =
        one_tetrahedron_forces(FemMethod::Large, {Vec3(0, 0, 0), Vec3(1 + eps, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)});
    const double scale = elastic[1].norm();
    ASSERT_GT(scale, 1e-3);
    const auto expect_ratio = [&](const std::vector<Vec3>& f, double ratio) {
        for (std::size_t k = 0; k < 4; ++k)
            EXPECT_LT((f[k] - ratio * elastic[k]).norm(), 1e-12 * scale) << k << " " << ratio;
    };
    // below the yield threshold: the elastic force (εp stays 0)
    std::array<double, 6> plastic{};
    expect_ratio(plastic_stretch_forces({.max_threshold = 1, .yield_threshold = 1e-2, .creep = 0.5}, 3, eps, &plastic),
                 1.0);
    for (const double v : plastic) EXPECT_EQ(v, 0.0);
    // creep 0.5: ½ after one evaluation, ¼ after two, εp = ¾ ε
    expect_ratio(plastic_stretch_forces({.max_threshold = 1, .yield_threshold = 1e-4, .creep = 0.5}, 1, eps), 0.5);
    expect_ratio(plastic_stretch_forces({.max_threshold = 1, .yield_threshold = 1e-4, .creep = 0.5}, 2, eps, &plastic),
                 0.25);
    // SOFA's D = r − R·x is minus the displacement: its strains, the plastic one included, are −ε
    EXPECT_NEAR(plastic[0], -0.75 * eps, 1e-15);
    // creep stops once |ε − εp| <= yield: 1e-3 → 5e-4 → 2.5e-4 (two evaluations), then no more
    expect_ratio(plastic_stretch_forces({.max_threshold = 1, .yield_threshold = 3e-4, .creep = 0.5}, 5, eps), 0.25);
    // clamp: εp = ½ε has norm 5e-4 > 2e-4 → εp = 0.2 ε, force 0.8 of the elastic one
    expect_ratio(
        plastic_stretch_forces({.max_threshold = 2e-4, .yield_threshold = 1e-4, .creep = 0.5}, 1, eps, &plastic), 0.8);
    EXPECT_NEAR(plastic[0], -2e-4, 1e-18);
}

TEST(TetrahedronFEM, PlasticityIsRefusedOffMethodLargeAndForBadValues) {
    MeshTopology topo;
    topo.set_tetrahedra({Tetrahedron{0, 1, 2, 3}});
    Vec3Object s;
    s.position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    s.init();
    TetrahedronFEMForceField polar(s, topo, 100, 0.3, FemMethod::Polar);
    EXPECT_THROW(polar.set_plasticity({.max_threshold = 1}), std::invalid_argument);
    polar.set_plasticity({});  // max 0: off, accepted
    TetrahedronFEMForceField large(s, topo, 100, 0.3, FemMethod::Large);
    EXPECT_THROW(large.set_plasticity({.max_threshold = 1, .yield_threshold = -1}), std::invalid_argument);
    EXPECT_THROW(large.set_plasticity({.max_threshold = 1, .creep = std::nan("")}), std::invalid_argument);
    // SOFA's float defaults
    EXPECT_EQ(TetrahedronFEMForceField::Plasticity{}.yield_threshold, double(0.0001f));
    EXPECT_EQ(TetrahedronFEMForceField::Plasticity{}.creep, double(0.9f));
}

TEST(TetrahedronFEM, LargeMethodIsTheRotatedElementStiffnessTimesTheLocalDisplacement) {
    // SOFA's J·(D/36V)·Jᵀ products (cofactors) against K^e = V·BᵀDB from the shape-function
    // gradients: f_k = −Rᵀ Σ_j K^e_kj (R(x_j − x_0) − r_j), R the element frame.
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-0.1, 0.1);
    MeshTopology topo;
    topo.set_tetrahedra({Tetrahedron{0, 1, 2, 3}});
    Vec3Object s;
    s.position = {Vec3(0.1, -0.2, 0.3), Vec3(1.2, 0.1, 0.2), Vec3(0.3, 0.9, -0.1), Vec3(0.2, 0.1, 1.4)};
    s.init();
    TetrahedronFEMForceField ff(s, topo, 250, 0.35, FemMethod::Large);
    ff.init();
    const Mat3 turn = Eigen::AngleAxisd(0.9, Vec3(-1, 2, 0.5).normalized()).toRotationMatrix();
    for (auto& p : s.position) p = turn * (p + Vec3(u(rng), u(rng), u(rng)));
    ff.accumulate_force();
    const auto frame = [](const std::vector<Vec3>& x) {
        return tetrahedron_rotation({x[0], x[1], x[2], x[3]}, FemMethod::Large);
    };
    const Mat3 r0 = frame(s.rest_position), r = frame(s.position);
    Eigen::Matrix<double, 12, 1> displacement;
    for (int k = 0; k < 4; ++k) {
        const auto uk = static_cast<std::size_t>(k);
        displacement.segment<3>(3 * k) =
            r * (s.position[uk] - s.position[0]) - r0 * (s.rest_position[uk] - s.rest_position[0]);
    }
    const Eigen::Matrix<double, 12, 1> local = ff.element_stiffness()[0] * displacement;
    double largest = 0;
    for (int k = 0; k < 4; ++k) largest = std::max(largest, local.segment<3>(3 * k).norm());
    EXPECT_GT(largest, 1.0);  // deformed: the comparison is not vacuous
    for (int k = 0; k < 4; ++k) {
        const Vec3 expected = -(r.transpose() * local.segment<3>(3 * k));
        EXPECT_LT((s.force[static_cast<std::size_t>(k)] - expected).norm(), 1e-12 * largest) << k;
    }
    // the stored energy ½ uᵀ K^e u of the same local displacement (every entry of it counts)
    const double energy = 0.5 * displacement.dot(local);
    EXPECT_GT(energy, 0.1);
    EXPECT_NEAR(ff.potential_energy(), energy, 1e-12 * energy);
}

// TetrahedronFEMForceField's products read its lane blocks, so K^e is made when first asked for
// (element_stiffness(), add_stiffness_triplets), from the rest coordinates init kept: the bits
// of the K^e made at init, which a localStiffnessFactor field still does (a factor of 1 leaves
// them as they are), for every method, on a grid with jittered rest positions (every frame a
// real rotation); a degenerate element is still refused at init.
TEST(TetrahedronFEM, ElementStiffnessMadeOnDemandIsTheOneInitMakes) {
    const RegularGridTopology grid({4, 4, 3}, Vec3::Zero(), Vec3(1.2, 1.1, 0.7));
    const MeshTopology mesh = kuhn_tetrahedra(grid);
    std::mt19937 random(20261201);
    std::uniform_real_distribution<double> jitter(-0.04, 0.04);
    Vec3Object state;
    state.position = grid.points();
    for (Vec3& x : state.position) x += Vec3(jitter(random), jitter(random), jitter(random));
    state.init();
    for (const FemMethod method : {FemMethod::Large, FemMethod::Small, FemMethod::Polar, FemMethod::Svd}) {
        TetrahedronFEMForceField on_demand(state, mesh, 2e4, 0.33, method);
        TetrahedronFEMForceField at_init(state, mesh, 2e4, 0.33, method);
        at_init.set_young_factors({1.0});
        on_demand.init();
        at_init.init();
        TripletList a, b;
        on_demand.add_stiffness_triplets(a, 3, -0.7);  // (the first ask: makes K^e)
        at_init.add_stiffness_triplets(b, 3, -0.7);
        ASSERT_EQ(a.size(), b.size());
        for (std::size_t i = 0; i < a.size(); ++i)
            ASSERT_TRUE(a[i].row() == b[i].row() && a[i].col() == b[i].col() &&
                        std::memcmp(&a[i].value(), &b[i].value(), sizeof(double)) == 0)
                << static_cast<int>(method) << ": triplet " << i;
        const auto& k = on_demand.element_stiffness();
        ASSERT_EQ(k.size(), mesh.tetrahedra().size());
        EXPECT_EQ(std::memcmp(k.data(), at_init.element_stiffness().data(), k.size() * sizeof(k[0])), 0)
            << static_cast<int>(method);
    }
    std::vector<Tetrahedron> flattened = mesh.tetrahedra();
    flattened[5][3] = flattened[5][1];
    MeshTopology bad;
    bad.set_tetrahedra(flattened);
    TetrahedronFEMForceField degenerate(state, bad, 2e4, 0.33, FemMethod::Large);
    try {
        degenerate.init();
        ADD_FAILURE() << "no error at init";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("tetrahedron 5 is degenerate"), std::string::npos) << e.what();
    }
}

TEST(TetrahedronFEM, StablePolarRotationOfDegenerateMatrices) {
    // a rotation times a stretch: the rotation
    const Mat3 r = Eigen::AngleAxisd(0.4, Vec3(0, 1, 1).normalized()).toRotationMatrix();
    const Mat3 stretch = Vec3(2.0, 1.0, 0.5).asDiagonal();
    EXPECT_LT((stable_polar_rotation(r * stretch) - r).norm(), 1e-12);
    // flat (one zero singular value): a proper rotation that maps the two kept directions as r does
    const Mat3 q = stable_polar_rotation(r * Mat3(Vec3(1.0, 2.0, 0.0).asDiagonal()));
    EXPECT_LT((q * q.transpose() - Mat3::Identity()).norm(), 1e-12);
    EXPECT_NEAR(q.determinant(), 1.0, 1e-12);
    EXPECT_LT((q - r).norm(), 1e-12);
    // collapsed to a line along x (two zero values): a proper rotation keeping x
    const Mat3 line = stable_polar_rotation(Mat3(Vec3(3.0, 0.0, 0.0).asDiagonal()));
    EXPECT_LT((line * line.transpose() - Mat3::Identity()).norm(), 1e-12);
    EXPECT_NEAR(line.determinant(), 1.0, 1e-12);
    EXPECT_LT((line.col(0) - Vec3(1, 0, 0)).norm(), 1e-12);
    // SOFA's two-zero branch builds its third edge from entries of two different columns
    // (U(0, o2), U(1, o0), U(2, o0)); reproduced, so a line off the axes gives no rotation.
    const Mat3 tilted = stable_polar_rotation(r * Mat3(Vec3(3.0, 0.0, 0.0).asDiagonal()));
    EXPECT_GT((tilted * tilted.transpose() - Mat3::Identity()).norm(), 1e-3);
    // collapsed to a point: the identity
    EXPECT_EQ(stable_polar_rotation(Mat3::Zero()), Mat3::Identity());
}

TEST(TetrahedronFEM, HexahedraSplitAsSofaFillsTheGrid) {
    RegularGridTopology g({4, 3, 3}, Vec3(0, 0, 0), Vec3(3, 2, 2));
    const auto tets = tetrahedra_from_hexahedra(g.mesh().hexahedra(), g.cells_x(), g.cells_y());
    ASSERT_EQ(tets.size(), 6u * 12u);
    const auto x = g.points();
    double volume = 0;
    for (const auto& t : tets) {
        Mat3 m;
        for (int k = 0; k < 3; ++k)
            m.col(k) =
                x[static_cast<std::size_t>(t[static_cast<std::size_t>(k + 1)])] - x[static_cast<std::size_t>(t[0])];
        EXPECT_GT(std::abs(m.determinant()), 1e-12);
        volume += std::abs(m.determinant()) / 6;
    }
    EXPECT_NEAR(volume, 12.0, 1e-12);
    // Conforming (a ball): V − E + F − T = 1 with F the distinct faces. (The split mixes
    // orientations, so MeshTopology's derived triangles, which only merge opposite orientations,
    // keep duplicates, as in SOFA.)
    MeshTopology topo;
    topo.set_tetrahedra(tets);
    std::set<std::array<PointId, 3>> faces;
    for (const auto& t : tets)
        for (const auto& f : MeshTopology::kTetraFaces) {
            std::array<PointId, 3> k{t[static_cast<std::size_t>(f[0])], t[static_cast<std::size_t>(f[1])],
                                     t[static_cast<std::size_t>(f[2])]};
            std::sort(k.begin(), k.end());
            faces.insert(k);
        }
    const long v = static_cast<long>(topo.num_points()), e = static_cast<long>(topo.edges().size());
    const long f = static_cast<long>(faces.size()), t = static_cast<long>(tets.size());
    EXPECT_EQ(v - e + f - t, 1);
    patch_test<TetrahedronFEMForceField>(topo, g, FemMethod::Small);
    Vec3Object s;
    s.position = g.points();
    s.init();
    TetrahedronFEMForceField from_grid(s, g, 100, 0.3);
    EXPECT_EQ(from_grid.tetrahedra(), tets);
    TetrahedronFEMForceField from_mesh(s, g.mesh(), 100, 0.3);  // SOFA's non-grid fallback nx=2, ny=1
    EXPECT_EQ(from_mesh.tetrahedra().size(), tets.size());
}

TEST(FEM, BadInputThrows) {
    Vec3Object s;
    s.position = {Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), Vec3(1, 1, 0)};
    s.init();
    MeshTopology topo;
    topo.set_tetrahedra({{0, 1, 2, 3}});
    EXPECT_THROW(TetrahedronFEMForceField(s, topo, 100, 0.5), std::invalid_argument);
    EXPECT_THROW(TetrahedronFEMForceField(s, topo, -1, 0.3), std::invalid_argument);
    EXPECT_THROW(TetrahedronFEMForceField(s, topo, std::numeric_limits<double>::quiet_NaN(), 0.3),
                 std::invalid_argument);
    TetrahedronFEMForceField flat(s, topo, 100, 0.3);
    EXPECT_THROW(flat.init(), std::invalid_argument);  // coplanar
    MeshTopology out;
    out.set_tetrahedra({{0, 1, 2, 9}});
    TetrahedronFEMForceField oob(s, out, 100, 0.3);
    EXPECT_THROW(oob.init(), std::invalid_argument);
}

/// Static cantilever along x (length 10, square section 1), clamped at x = 0, tip load P spread
/// on the tip nodes; returns the mean tip deflection.
double cantilever_tip_deflection(int nx, int ny) {
    const double length = 10, side = 1, e = 1e5, p = -1.0;
    RegularGridTopology g({nx + 1, ny + 1, ny + 1}, Vec3(0, 0, 0), Vec3(length, side, side));
    Vec3Object s;
    s.position = g.points();
    s.init();
    HexahedronFEMForceField ff(s, g.mesh(), e, 0.0, FemMethod::Small);
    ff.init();
    ff.accumulate_force();  // at rest: linearise
    TripletList t;
    ff.add_stiffness(
        t, [](const BaseState*) { return Index{0}; }, -1.0);  // K_spd = −∂f/∂x
    const auto n = static_cast<Eigen::Index>(3 * s.num_dofs());
    // Clamp: replace the rows/cols of x = 0 nodes by identity.
    std::vector<bool> fixed(static_cast<std::size_t>(n), false);
    for (int k = 0; k <= ny; ++k)
        for (int j = 0; j <= ny; ++j)
            for (int c = 0; c < 3; ++c) fixed[static_cast<std::size_t>(3 * g.point_index(0, j, k) + c)] = true;
    TripletList tf;
    for (const auto& tr : t)
        if (!fixed[static_cast<std::size_t>(tr.row())] && !fixed[static_cast<std::size_t>(tr.col())]) tf.push_back(tr);
    for (Eigen::Index i = 0; i < n; ++i)
        if (fixed[static_cast<std::size_t>(i)]) tf.emplace_back(i, i, 1.0);
    Eigen::SparseMatrix<double> k(n, n);
    k.setFromTriplets(tf.begin(), tf.end());
    Eigen::VectorXd f = Eigen::VectorXd::Zero(n);
    const int tip_nodes = (ny + 1) * (ny + 1);
    for (int kk = 0; kk <= ny; ++kk)
        for (int j = 0; j <= ny; ++j) f[3 * g.point_index(nx, j, kk) + 1] = p / tip_nodes;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(k);
    EXPECT_EQ(solver.info(), Eigen::Success);
    const Eigen::VectorXd u = solver.solve(f);
    double tip = 0;
    for (int kk = 0; kk <= ny; ++kk)
        for (int j = 0; j <= ny; ++j) tip += u[3 * g.point_index(nx, j, kk) + 1];
    return tip / tip_nodes;
}

TEST(HexahedronFEM, CantileverTipDeflectionConvergesToBeamFormula) {
    const double beam = -1.0 * 1000.0 / (3 * 1e5 * (1.0 / 12.0));  // P L³ / (3 E I) = −0.04
    const double d1 = cantilever_tip_deflection(10, 1);
    const double d2 = cantilever_tip_deflection(20, 2);
    const double d3 = cantilever_tip_deflection(40, 4);
    const double e1 = std::abs(d1 / beam - 1), e2 = std::abs(d2 / beam - 1), e3 = std::abs(d3 / beam - 1);
    ::testing::Test::RecordProperty("tip_10x1", std::to_string(d1));
    ::testing::Test::RecordProperty("tip_20x2", std::to_string(d2));
    ::testing::Test::RecordProperty("tip_40x4", std::to_string(d3));
    // Fully integrated trilinear hexahedra lock in bending: the error decreases with refinement.
    EXPECT_GT(e1, e2);
    EXPECT_GT(e2, e3);
    EXPECT_LT(e3, 0.1) << d1 << " " << d2 << " " << d3 << " beam " << beam;
    EXPECT_LT(d3, 0.0);
}

}  // namespace
}  // namespace penalty
