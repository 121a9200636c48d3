// MeshMatrixMass<Vec1d, Vec3d> (ScalarMeshMatrixMass): the masses of one tetrahedron of volume 1
// and density 6 (closed form: 6/10 a vertex, 6/20 an edge, lumped 6/4), applied to a scalar
// state: M·dx, the triplets, the kinetic energy and its finite-difference gradient, gravity's
// x component, M⁻¹ (lumped only) and the errors.
#include "penalty/mechanics/scalar_mesh_matrix_mass.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <random>
#include <stdexcept>
#include <string>

namespace penalty {
namespace {

/// The tetrahedron (0,0,0), (2,0,0), (0,3,0), (0,0,1) (volume 1) as a geometry state, and a
/// scalar state of four values.
struct ScalarMassTetrahedron {
    Vec3Object geometry;
    Vec1Object values;
    MeshTopology topology;
    std::unique_ptr<ScalarMeshMatrixMass> mass;
    explicit ScalarMassTetrahedron(bool lumping, std::size_t value_count = 4) {
        geometry.position = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 3, 0), Vec3(0, 0, 1)};
        geometry.init();
        values.resize(value_count);
        values.init();
        topology.set_tetrahedra({{0, 1, 2, 3}});
        mass = std::make_unique<ScalarMeshMatrixMass>(values, geometry, topology);
        mass->masses().set_mass_density({6.0});
        mass->masses().set_lumping(lumping);
    }
};

/// M of the scalar mass from its triplets.
Eigen::Matrix4d scalar_mass_matrix(const ScalarMeshMatrixMass& m) {
    TripletList t;
    m.add_mass_triplets(t, 0, 1.0);
    Eigen::Matrix4d dense = Eigen::Matrix4d::Zero();
    for (const auto& e : t) dense(e.row(), e.col()) += e.value();
    return dense;
}

TEST(ScalarMeshMatrixMass, OneTetrahedronsConsistentAndLumpedMatrices) {
    ScalarMassTetrahedron consistent(false);
    consistent.mass->init();
    EXPECT_NEAR(consistent.mass->total_mass(), 6.0, 1e-14);
    const Eigen::Matrix4d m = scalar_mass_matrix(*consistent.mass);
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) EXPECT_NEAR(m(i, j), i == j ? 0.6 : 0.3, 1e-15) << i << ", " << j;
    ScalarMassTetrahedron lumped(true);
    lumped.mass->init();
    EXPECT_EQ(lumped.mass->masses().lumping_coefficient(), 2.5);
    const Eigen::Matrix4d ml = scalar_mass_matrix(*lumped.mass);
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) EXPECT_NEAR(ml(i, j), i == j ? 1.5 : 0.0, 1e-15) << i << ", " << j;
    // the two have the same row sums (each vertex's share of the mass)
    EXPECT_LT((m.rowwise().sum() - ml.rowwise().sum()).norm(), 1e-14);
}

TEST(ScalarMeshMatrixMass, MdxIsTheMatrixTimesDxWithItsFactor) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (const bool lumping : {false, true}) {
        ScalarMassTetrahedron t(lumping);
        t.mass->init();
        Eigen::Vector4d dx;
        for (int i = 0; i < 4; ++i) dx[i] = u(rng);
        for (int i = 0; i < 4; ++i) {
            t.values.dx[std::size_t(i)] = dx[i];
            t.values.df[std::size_t(i)] = 1.0;  // add_mdx adds
        }
        t.mass->add_mdx(-0.7);
        const Eigen::Vector4d expected = Eigen::Vector4d::Ones() - 0.7 * scalar_mass_matrix(*t.mass) * dx;
        for (int i = 0; i < 4; ++i) EXPECT_NEAR(t.values.df[std::size_t(i)], expected[i], 1e-15) << lumping << i;
    }
}

TEST(ScalarMeshMatrixMass, KineticEnergyIsHalfVMvAndItsGradientIsMv) {
    ScalarMassTetrahedron t(false);
    t.mass->init();
    // v = (1, −1, 0, 0): ½(0.6 + 0.6 − 2·0.3) = 0.3
    t.values.velocity = {1.0, -1.0, 0.0, 0.0};
    EXPECT_NEAR(t.mass->kinetic_energy(), 0.3, 1e-15);
    // at v = (0.3, −0.2, 0.5, 0.1): central differences of the energy against M·v (add_mdx)
    const std::vector<double> v{0.3, -0.2, 0.5, 0.1};
    t.values.dx = v;
    std::fill(t.values.df.begin(), t.values.df.end(), 0.0);
    t.mass->add_mdx(1.0);
    const double h = 1e-6;
    double norm = 0.0;
    for (std::size_t i = 0; i < 4; ++i) {
        t.values.velocity = v;
        t.values.velocity[i] = v[i] + h;
        const double up = t.mass->kinetic_energy();
        t.values.velocity[i] = v[i] - h;
        const double down = t.mass->kinetic_energy();
        EXPECT_NEAR((up - down) / (2 * h), t.values.df[i], 1e-9) << i;
        norm += t.values.df[i] * t.values.df[i];
    }
    EXPECT_GT(norm, 0.01);
}

TEST(ScalarMeshMatrixMass, GravityActsThroughItsXComponent) {
    // f_i += g_x·c·m_i = g_x·6/4 (consistent or lumped: the rows of M sum to 6/4); the potential
    // −Σ g_x·x_i·c·m_i
    const Vec3 g(-2.0, -9.81, 5.0);
    for (const bool lumping : {false, true}) {
        ScalarMassTetrahedron t(lumping);
        t.mass->init();
        t.values.position = {1.0, 2.0, 3.0, 4.0};
        t.values.force = {0.5, 0.0, 0.0, 0.0};
        t.mass->add_gravity_force(g);
        EXPECT_NEAR(t.values.force[0], 0.5 - 3.0, 1e-14) << lumping;
        for (std::size_t i = 1; i < 4; ++i) EXPECT_NEAR(t.values.force[i], -3.0, 1e-14) << lumping;
        EXPECT_NEAR(t.mass->gravity_potential_energy(g), 2.0 * 1.5 * 10.0, 1e-13) << lumping;
    }
}

TEST(ScalarMeshMatrixMass, OnlyTheLumpedMatrixIsInvertedAndTheStatesMustAgree) {
    ScalarMassTetrahedron lumped(true);
    lumped.mass->init();
    const Eigen::Vector4d in(3.0, -1.5, 0.75, 0.0);
    Eigen::Vector4d out = Eigen::Vector4d::Constant(9.0);
    lumped.mass->apply_inverse(in, out);
    EXPECT_EQ(out, Eigen::Vector4d(2.0, -1.0, 0.5, 0.0));
    ScalarMassTetrahedron consistent(false);
    consistent.mass->init();
    try {
        consistent.mass->apply_inverse(in, out);
        ADD_FAILURE() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()),
                  "MeshMatrixMass<Vec1d,Vec3d>: an explicit solver needs M⁻¹, which the consistent mass matrix does "
                  "not give (SOFA's accFromF refuses it too): set lumping=\"1\"");
    }
    ScalarMassTetrahedron mismatched(false, 3);
    try {
        mismatched.mass->init();
        ADD_FAILURE() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()),
                  "MeshMatrixMass<Vec1d,Vec3d>: the geometry state has 4 points, the state 3 values");
    }
}

}  // namespace
}  // namespace penalty
