// Uses the installed library: SOFA's first unit-test case, f0 = (−1, 0, 0).
#include <penalty/response/penalty_force_field.hpp>

#include <cstdio>

int main() {
    penalty::Vec3List x{penalty::Vec3(0, 0, 0), penalty::Vec3(2, 0, 0)};
    penalty::Vec3List v(2, penalty::Vec3::Zero()), f(2, penalty::Vec3::Zero());
    penalty::PenaltyForceField ff;
    ff.add_contact(penalty::DofIndex(0), penalty::DofIndex(1), penalty::ElementIndex(0), penalty::ElementIndex(0),
                   penalty::Vec3::UnitX(), 3.0, 1.0);
    ff.add_force(f, f, x, x, v, v);
    std::printf("f0 = (%g, %g, %g)\n", f[0].x(), f[0].y(), f[0].z());
    return f[0].isApprox(penalty::Vec3(-1, 0, 0)) ? 0 : 1;
}
