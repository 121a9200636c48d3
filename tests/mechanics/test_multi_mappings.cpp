// CenterOfMassMapping, SubsetMultiMapping and IdentityMultiMapping: closed forms (the centre of
// mass, the picked DOFs), J against finite differences of apply, Jᵀ as the adjoint of J
// (⟨J dx, y⟩ = ⟨dx, Jᵀ y⟩), the triplets against apply_dx, and the bad inputs refused.
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/multi_mappings.hpp"

#include "penalty_test/finite_difference.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <random>

namespace penalty {
namespace {

std::mt19937 multi_rng(23);
double multi_uni() { return std::uniform_real_distribution<double>(-1, 1)(multi_rng); }
Vec3 multi_vec() { return Vec3(multi_uni(), multi_uni(), multi_uni()); }
Quat multi_rotation() { return Quat(Eigen::AngleAxisd(2 * multi_uni(), multi_vec().normalized())); }

/// A Rigid3 mass with given masses per frame (inertia: the identity times the mass), to give
/// CenterOfMassMapping unequal element masses.
class ListedRigidMass final : public BaseMass {
public:
    ListedRigidMass(Rigid3Object& s, std::vector<double> m) : state_(&s), masses_(std::move(m)) {}
    void add_gravity_force(const Vec3&) override {}
    void add_mdx(double) override {}
    void apply_inverse(const Eigen::Ref<const Eigen::VectorXd>&, Eigen::Ref<Eigen::VectorXd>) const override {}
    void add_mass_triplets(TripletList& t, Index offset, double factor) const override {
        for (std::size_t i = 0; i < masses_.size(); ++i)
            for (Index a = 0; a < 6; ++a)
                t.emplace_back(offset + 6 * Index(i) + a, offset + 6 * Index(i) + a, factor * masses_[i]);
    }
    [[nodiscard]] double kinetic_energy() const override { return 0; }
    [[nodiscard]] double gravity_potential_energy(const Vec3&) const override { return 0; }
    [[nodiscard]] double total_mass() const override { return 0; }
    [[nodiscard]] BaseState* state() const override { return state_; }

private:
    Rigid3Object* state_;
    std::vector<double> masses_;
};

/// Moves scalar c of an input: a point's coordinate, or a frame's centre or world rotation.
void multi_move(BaseState& s, double h, Eigen::Index c) {
    if (auto* v = dynamic_cast<Vec3Object*>(&s)) {
        v->position[std::size_t(c / 3)][c % 3] += h;
        return;
    }
    RigidFrame& f = dynamic_cast<Rigid3Object&>(s).position[std::size_t(c / 6)];
    if (c % 6 < 3) f.center[c % 6] += h;
    else f.orientation = Quat(Eigen::AngleAxisd(h, Vec3::Unit(c % 6 - 3))) * f.orientation;
}

/// The output's positions as numbers: a point's 3, a frame's centre and a rotation vector of its
/// orientation relative to `reference` (so that a small world rotation reads as its angle).
Eigen::VectorXd multi_positions(BaseState& out, const std::vector<RigidFrame>& reference) {
    if (auto* v = dynamic_cast<Vec3Object*>(&out))
        return ConstFlatVector(reinterpret_cast<const double*>(v->position.data()), Eigen::Index(v->scalar_size()));
    auto& r = dynamic_cast<Rigid3Object&>(out);
    Eigen::VectorXd x(Eigen::Index(6 * r.position.size()));
    for (std::size_t i = 0; i < r.position.size(); ++i) {
        x.segment<3>(Eigen::Index(6 * i)) = r.position[i].center;
        const Eigen::AngleAxisd d(r.position[i].orientation * reference[i].orientation.conjugate());
        x.segment<3>(Eigen::Index(6 * i + 3)) = d.angle() * d.axis();
    }
    return x;
}

/// J by apply_dx on unit vectors and by central differences of apply_position, for every input
/// in order (columns); J's triplets (the first input's and the second's blocks) are checked to be J.
void expect_jacobian_matches(BaseMapping& map, std::vector<BaseState*> inputs) {
    BaseState& out = *map.to();
    Eigen::Index columns = 0;
    for (BaseState* s : inputs) columns += Eigen::Index(s->scalar_size());
    const auto rows = Eigen::Index(out.scalar_size());
    Eigen::MatrixXd j(rows, columns), fd(rows, columns);
    map.apply_position();
    std::vector<RigidFrame> reference;
    if (auto* r = dynamic_cast<Rigid3Object*>(&out)) reference = r->position;
    const double h = 1e-6;
    Eigen::Index col = 0;
    for (BaseState* s : inputs) {
        for (Eigen::Index c = 0; c < Eigen::Index(s->scalar_size()); ++c, ++col) {
            for (BaseState* t : inputs) t->dx_flat().setZero();
            s->dx_flat()[c] = 1.0;
            map.apply_dx();
            j.col(col) = out.dx_flat();
            multi_move(*s, h, c);
            map.apply_position();
            const Eigen::VectorXd plus = multi_positions(out, reference);
            multi_move(*s, -2 * h, c);
            map.apply_position();
            const Eigen::VectorXd minus = multi_positions(out, reference);
            multi_move(*s, h, c);
            fd.col(col) = (plus - minus) / (2 * h);
        }
    }
    map.apply_position();
    EXPECT_TRUE(test::near_relative(j, fd, 1e-7)) << j << "\n--\n" << fd;
    EXPECT_GT(j.norm(), 0.5);
    TripletList t, t2;
    map.add_jacobian_triplets(t, 0, 0);
    if (inputs.size() > 1) map.add_second_input_jacobian_triplets(t2, 0, Eigen::Index(inputs[0]->scalar_size()));
    t.insert(t.end(), t2.begin(), t2.end());
    SparseMatrix js(rows, columns);
    js.setFromTriplets(t.begin(), t.end());
    EXPECT_TRUE(test::near_relative(Eigen::MatrixXd(js), j, 1e-15)) << Eigen::MatrixXd(js) << "\n--\n" << j;
}

/// ⟨J dx, y⟩ = ⟨dx, Jᵀ y⟩ over random dx (every input) and y, for apply_jt_df and apply_jt_force.
void expect_transpose_is_adjoint(BaseMapping& map, std::vector<BaseState*> inputs) {
    BaseState& out = *map.to();
    for (int trial = 0; trial < 3; ++trial) {
        std::vector<Eigen::VectorXd> dx;
        for (BaseState* s : inputs) {
            dx.push_back(Eigen::VectorXd::NullaryExpr(Eigen::Index(s->scalar_size()), [] { return multi_uni(); }));
            s->dx_flat() = dx.back();
            s->df_flat().setZero();
            s->force_flat().setZero();
        }
        map.apply_dx();
        const Eigen::VectorXd y =
            Eigen::VectorXd::NullaryExpr(Eigen::Index(out.scalar_size()), [] { return multi_uni(); });
        const double lhs = out.dx_flat().dot(y);
        out.df_flat() = y;
        out.force_flat() = y;
        map.apply_jt_df();
        map.apply_jt_force();
        double rhs_df = 0, rhs_force = 0;
        for (std::size_t k = 0; k < inputs.size(); ++k) {
            rhs_df += dx[k].dot(inputs[k]->df_flat());
            rhs_force += dx[k].dot(inputs[k]->force_flat());
        }
        EXPECT_NEAR(lhs, rhs_df, 1e-13 * std::max(1.0, std::abs(lhs)));
        EXPECT_EQ(rhs_df, rhs_force);
        EXPECT_GT(std::abs(lhs), 1e-6);
    }
}

Rigid3Object random_frames(int n) {
    Rigid3Object s;
    for (int i = 0; i < n; ++i) s.position.push_back({multi_vec() * 3, multi_rotation()});
    s.init();
    return s;
}

Vec3Object random_points(int n) {
    Vec3Object s;
    for (int i = 0; i < n; ++i) s.position.push_back(multi_vec() * 3);
    s.init();
    return s;
}

TEST(CenterOfMassMapping, MassWeightedCentreJacobianAndAdjoint) {
    Rigid3Object frames = random_frames(4);
    for (auto& v : frames.velocity) v = {multi_vec(), multi_vec()};
    ListedRigidMass mass(frames, {1.0, 2.0, 0.5, 4.5});
    Vec3Object centre;
    CenterOfMassMapping map(frames, centre, mass);
    map.init();
    ASSERT_EQ(centre.position.size(), 1u);
    EXPECT_DOUBLE_EQ(map.total_mass(), 8.0);
    // x = Σ m_i c_i / M, v = Σ m_i v_i / M
    Vec3 x = Vec3::Zero(), v = Vec3::Zero();
    const double m[] = {1.0, 2.0, 0.5, 4.5};
    for (std::size_t i = 0; i < 4; ++i) {
        x += m[i] * frames.position[i].center;
        v += m[i] * frames.velocity[i].linear;
    }
    EXPECT_TRUE(centre.position[0].isApprox(x / 8.0, 1e-15));
    EXPECT_TRUE(centre.velocity[0].isApprox(v / 8.0, 1e-15));
    // a force on the centre spreads as f·m_i/M, without torque
    frames.force.assign(4, RigidDeriv{});
    centre.force[0] = Vec3(8, -16, 4);
    map.apply_jt_force();
    for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_TRUE(frames.force[i].linear.isApprox(Vec3(8, -16, 4) * m[i] / 8.0, 1e-15));
        EXPECT_TRUE(frames.force[i].angular.isZero(0));
    }
    expect_jacobian_matches(map, {&frames});
    expect_transpose_is_adjoint(map, {&frames});
}

TEST(CenterOfMassMapping, NeedsAPositiveMassForEveryFrame) {
    Rigid3Object frames = random_frames(2);
    Vec3Object centre;
    ListedRigidMass none(frames, {0.0, 0.0});
    CenterOfMassMapping zero(frames, centre, none);
    EXPECT_THROW(zero.init(), std::invalid_argument);
    ListedRigidMass negative(frames, {1.0, -1.0});
    CenterOfMassMapping cancelling(frames, centre, negative);
    EXPECT_THROW(cancelling.init(), std::invalid_argument);
    // UniformMass's element masses: vertexMass each (SOFA's getElementMass)
    UniformMass<Rigid3Types> uniform(frames);
    uniform.set_vertex_mass(3.0);
    CenterOfMassMapping map(frames, centre, uniform);
    map.init();
    EXPECT_DOUBLE_EQ(map.total_mass(), 6.0);
    EXPECT_TRUE(centre.position[0].isApprox(0.5 * (frames.position[0].center + frames.position[1].center), 1e-15));
}

TEST(SubsetMultiMapping, PicksPointsOfTwoStates) {
    Vec3Object a = random_points(3), b = random_points(2), out;
    SubsetMultiMapping<Vec3Types, Vec3Types> map(a, &b, out, {{1, 1}, {0, 2}, {0, 0}, {1, 0}, {0, 2}});
    map.init();
    ASSERT_EQ(out.position.size(), 5u);
    EXPECT_EQ(out.position[0], b.position[1]);
    EXPECT_EQ(out.position[1], a.position[2]);
    EXPECT_EQ(out.position[3], b.position[0]);
    EXPECT_EQ(out.position[4], a.position[2]);
    EXPECT_EQ(map.second_from(), &b);
    expect_jacobian_matches(map, {&a, &b});
    expect_transpose_is_adjoint(map, {&a, &b});
    // Jᵀ adds in output order: a point picked twice gets both forces
    a.force.assign(3, Vec3::Zero());
    b.force.assign(2, Vec3::Zero());
    for (std::size_t k = 0; k < 5; ++k) out.force[k] = Vec3::Constant(double(k + 1));
    map.apply_jt_force();
    EXPECT_EQ(a.force[2], Vec3::Constant(2.0 + 5.0));
    EXPECT_EQ(a.force[1], Vec3::Zero());
    EXPECT_EQ(b.force[1], Vec3::Constant(1.0));
}

TEST(SubsetMultiMapping, RigidInputsOntoPointsAndFrames) {
    Rigid3Object a = random_frames(2), b = random_frames(2);
    Vec3Object points;
    SubsetMultiMapping<Rigid3Types, Vec3Types> to_points(a, &b, points, {{0, 0}, {0, 1}, {1, 0}, {1, 1}});
    to_points.init();
    EXPECT_EQ(points.position[2], b.position[0].center);  // core::eq: the frame's centre
    expect_jacobian_matches(to_points, {&a, &b});
    expect_transpose_is_adjoint(to_points, {&a, &b});
    Rigid3Object frames;
    SubsetMultiMapping<Rigid3Types, Rigid3Types> to_frames(a, &b, frames, {{1, 1}, {0, 0}});
    to_frames.init();
    EXPECT_EQ(frames.position[0].center, b.position[1].center);
    EXPECT_EQ(frames.position[0].orientation.coeffs(), b.position[1].orientation.coeffs());
    expect_jacobian_matches(to_frames, {&a, &b});
    expect_transpose_is_adjoint(to_frames, {&a, &b});
}

TEST(SubsetMultiMapping, RefusesPairsOutOfRange) {
    Vec3Object a = random_points(3), b = random_points(2), out;
    SubsetMultiMapping<Vec3Types, Vec3Types> past_end(a, &b, out, {{1, 2}});
    EXPECT_THROW(past_end.init(), std::invalid_argument);
    SubsetMultiMapping<Vec3Types, Vec3Types> no_second(a, nullptr, out, {{1, 0}});
    EXPECT_THROW(no_second.init(), std::invalid_argument);
    EXPECT_THROW((SubsetMultiMapping<Vec3Types, Vec3Types>(a, &a, out, {})), std::invalid_argument);
}

TEST(IdentityMultiMapping, ConcatenatesTheInputs) {
    Vec3Object a = random_points(3), b = random_points(2), out;
    auto map = SubsetMultiMapping<Vec3Types, Vec3Types>::concatenation(a, &b, out);
    map.init();
    ASSERT_EQ(out.position.size(), 5u);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(out.position[i], a.position[i]);
    for (std::size_t i = 0; i < 2; ++i) EXPECT_EQ(out.position[3 + i], b.position[i]);
    expect_jacobian_matches(map, {&a, &b});
    expect_transpose_is_adjoint(map, {&a, &b});
}

}  // namespace
}  // namespace penalty
