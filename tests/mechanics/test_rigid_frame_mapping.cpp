// RigidMapping Rigid3d → Rigid3d (J against finite differences of the map, Jᵀ its transpose,
// the assembled Jacobian), and the Rigid3d arithmetic SOFA HEAD uses that the joint-spring scenes
// exposed: a frame moved by the exponential of its rotation vector (RigidCoord::operator+=) and
// the rigid mass applied as (J·m·factor)·dx (UniformMass::addMDx with RigidMass).
#include "penalty/mechanics/mass.hpp"
#include "penalty/mechanics/rigid_frame_mapping.hpp"

#include "penalty_test/rigid_derivatives.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace penalty {
namespace {

struct TwoBodies {
    Rigid3Object in, out;
    TwoBodies() {
        in.position = {RigidFrame{Vec3(0.1, 0.2, -0.3), Quat(Eigen::AngleAxisd(0.6, Vec3(1, 2, 3).normalized()))},
                       RigidFrame{Vec3(2, -1, 0.5), Quat(Eigen::AngleAxisd(-1.2, Vec3(0, 1, -1).normalized()))}};
        in.init();
    }
};

TEST(RigidFrameMapping, OutputFramesAreTheLocalFramesCarriedByTheInput) {
    TwoBodies b;
    RigidFrameMapping m(b.in, b.out);
    const RigidFrame local{Vec3(1, 0, 0), Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ()))};
    m.set_frames({local, local, RigidFrame{}}, {0, 1, 1});
    m.init();
    ASSERT_EQ(b.out.position.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) {
        const RigidFrame& f = b.in.position[i == 0 ? 0 : 1];
        const RigidFrame& l = i == 2 ? RigidFrame{} : local;
        EXPECT_NEAR((b.out.position[i].center - (f.center + f.orientation * l.center)).norm(), 0.0, 1e-15);
        EXPECT_NEAR(b.out.position[i].orientation.angularDistance(f.orientation * l.orientation), 0.0, 1e-14);
    }
    RigidFrameMapping bad(b.in, b.out);
    bad.set_frames({local}, {2});
    EXPECT_THROW(bad.init(), std::invalid_argument);
    EXPECT_THROW(bad.set_frames({local}, {0, 1}), std::invalid_argument);
}

TEST(RigidFrameMapping, JacobianMatchesFiniteDifferencesAndItsTransposeMapsForces) {
    TwoBodies b;
    RigidFrameMapping m(b.in, b.out);
    m.set_frames({RigidFrame{Vec3(1, -0.5, 0.2), Quat(Eigen::AngleAxisd(0.4, Vec3::UnitX()))},
                  RigidFrame{Vec3(0, 0.3, 0.7), Quat::Identity()}},
                 {1, 0});
    m.init();
    const std::vector<RigidFrame> x0 = b.in.position;
    // output displacement per input displacement δ: centre difference and the rotation vector of q' q⁻¹
    const auto out_of = [&](const Eigen::VectorXd& delta) {
        b.in.position = test::displaced_frames(x0, delta);
        m.apply_position();
        Eigen::VectorXd y(14);
        for (std::size_t i = 0; i < 2; ++i) {
            y.segment<3>(static_cast<Eigen::Index>(7 * i)) = b.out.position[i].center;
            y.segment<4>(static_cast<Eigen::Index>(7 * i + 3)) = b.out.position[i].orientation.coeffs();
        }
        return y;
    };
    const Eigen::VectorXd y0 = out_of(Eigen::VectorXd::Zero(12));
    TripletList t;
    m.add_jacobian_triplets(t, 0, 0);
    SparseMatrix js(12, 12);
    js.setFromTriplets(t.begin(), t.end());
    const Eigen::MatrixXd j(js);
    for (Eigen::Index c = 0; c < 12; ++c) {
        const double h = 1e-7;
        Eigen::VectorXd d = Eigen::VectorXd::Zero(12);
        d[c] = h;
        const Eigen::VectorXd yp = out_of(d);
        d[c] = -h;
        const Eigen::VectorXd ym = out_of(d);
        for (std::size_t i = 0; i < 2; ++i) {
            const auto o = static_cast<Eigen::Index>(7 * i);
            const Vec3 dc = (yp.segment<3>(o) - ym.segment<3>(o)) / (2 * h);
            Quat qp, qm;
            qp.coeffs() = yp.segment<4>(o + 3);
            qm.coeffs() = ym.segment<4>(o + 3);
            const Eigen::AngleAxisd turn(qp * qm.conjugate());
            const Vec3 dw = turn.axis() * turn.angle() / (2 * h);
            const auto r = static_cast<Eigen::Index>(6 * i);
            EXPECT_NEAR((j.block<3, 1>(r, c) - dc).norm(), 0.0, 1e-7) << "column " << c << ", output " << i;
            EXPECT_NEAR((j.block<3, 1>(r + 3, c) - dw).norm(), 0.0, 1e-7) << "column " << c << ", output " << i;
        }
    }
    out_of(Eigen::VectorXd::Zero(12));
    // apply_j is J, apply_jt is Jᵀ
    Eigen::VectorXd v(12), f(12);
    for (Eigen::Index i = 0; i < 12; ++i) {
        v[i] = std::sin(1.0 + i);
        f[i] = std::cos(2.0 * i);
    }
    std::vector<RigidDeriv> vin(2), vout(2), fout(2), fin(2);
    Rigid3Object::flat(vin) = v;
    Rigid3Object::flat(fout) = f;
    m.apply_j(vout, vin);
    m.apply_jt(fin, fout);
    const Eigen::VectorXd jv = j * v, jtf = j.transpose() * f;
    const Eigen::VectorXd got_v = Rigid3Object::flat(vout), got_f = Rigid3Object::flat(fin);
    EXPECT_TRUE(got_v.isApprox(jv, 1e-14)) << (got_v - jv).transpose();
    EXPECT_TRUE(got_f.isApprox(jtf, 1e-14)) << (got_f - jtf).transpose();
}

TEST(RigidArithmetic, FramesMoveByTheExponentialOfTheRotationVector) {
    // SOFA HEAD's RigidCoord::operator+=: a finite turn h·ω is exact, not first order
    const RigidFrame x{Vec3(1, 2, 3), Quat(Eigen::AngleAxisd(0.2, Vec3::UnitY()))};
    RigidDeriv v;
    v.linear = Vec3(0.5, 0, -1);
    v.angular = Vec3(0, 0, 10);  // 1 rad over h = 0.1
    const RigidFrame y = rigid_add(x, v, 0.1);
    EXPECT_NEAR((y.center - Vec3(1.05, 2, 2.9)).norm(), 0.0, 1e-15);
    const Quat expected = Quat(Eigen::AngleAxisd(1.0, Vec3::UnitZ())) * x.orientation;
    EXPECT_NEAR(y.orientation.angularDistance(expected), 0.0, 1e-15);
    EXPECT_NEAR(y.orientation.norm(), 1.0, 1e-15);
}

TEST(RigidArithmetic, RigidMassScalesItsInertiaByTheFactorBeforeTheProduct) {
    Rigid3Object s;
    s.position.resize(1);
    s.init();
    UniformMass<Rigid3Types> mass(s);
    mass.set_vertex_mass(0.7);
    Mat3 j;
    j << 0.1, 0.01, 0.0, 0.01, 0.2, 0.03, 0.0, 0.03, 0.15;
    mass.set_inertia(j);
    mass.init();
    s.dx[0].linear = Vec3(0.3, -0.1, 0.2);
    s.dx[0].angular = Vec3(0.123456789, -0.987654321, 0.5555555);
    const double factor = 1.0 / 3.0;
    mass.add_mdx(factor);
    // RigidMass: inertiaMassMatrix = J·m, then ·factor, then the row sums (J m f)(i,0)w₀ + …
    const Mat3 jm = j * 0.7 * factor;
    const Vec3 w = s.dx[0].angular;
    for (int i = 0; i < 3; ++i) EXPECT_EQ(s.df[0].angular[i], jm(i, 0) * w[0] + jm(i, 1) * w[1] + jm(i, 2) * w[2]);
    EXPECT_EQ(s.df[0].linear, s.dx[0].linear * (0.7 * factor));
}

}  // namespace
}  // namespace penalty
