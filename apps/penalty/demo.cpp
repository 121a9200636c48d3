#include "demo.hpp"

#include "penalty/response/penalty_force_field.hpp"

#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>

namespace penalty::apps {

namespace {

std::string format(const char* pattern, auto... values) {
    char buffer[256];
    std::snprintf(buffer, sizeof buffer, pattern, values...);
    return buffer;
}

const char* state_name(FrictionState s) {
    switch (s) {
        case FrictionState::none:
            return "none";
        case FrictionState::sticking:
            return "stick";
        case FrictionState::sliding:
            return "slide";
    }
    return "?";
}

/// Part 1: a plate of 4 DOFs (state 2) pressed onto 4 fixed DOFs (state 1), slightly tilted.
void pressed_plates(const DemoOptions& options, std::ostream& out) {
    out << "== Two bodies pressed together (SOFA semantics: f = ks·pen·n, pen = dist − (x2 − x1)·n)\n";
    const Vec3List x1{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)};
    const Vec3List x2{Vec3(0, 0, 0.080), Vec3(1, 0, 0.085), Vec3(0, 1, 0.090), Vec3(1, 1, 0.095)};
    const Vec3List v(4, Vec3::Zero());
    Vec3List f1(4, Vec3::Zero()), f2(4, Vec3::Zero());
    PenaltyForceField ff;
    for (Index i = 0; i < 4; ++i)
        ff.add_contact(DofIndex(i), DofIndex(i), ElementIndex(i), ElementIndex(i), Vec3::UnitZ(), 0.1,
                       options.stiffness);
    ff.add_force(f1, f2, x1, x2, v, v);

    out << format("   ks = %g N/m, dist = 0.1 m, normal = (0, 0, 1) from body 1 to body 2\n", options.stiffness);
    out << "   contact  pen (m)    force on body 2 (N)            energy (J)\n";
    Vec3 total = Vec3::Zero();
    for (std::size_t i = 0; i < ff.size(); ++i) {
        const PenaltyContact& c = ff.contacts()[i];
        const Vec3& f = f2[static_cast<std::size_t>(c.m2)];
        out << format("   %7zu  %.6f   (%8.4f, %8.4f, %8.4f)   %.6e\n", i, c.pen, f.x(), f.y(), f.z(),
                      0.5 * c.ks * c.pen * c.pen);
        total += f1[i] + f2[i];
    }
    out << format("   total potential energy %.6e J, |sum of all forces| = %.1e N\n", ff.potential_energy(),
                  total.norm());
    const SparseMatrix K = ff.stiffness_matrix(4, 4, false);
    out << format("   stiffness K = df/dx (two-state layout, %ldx%ld, %ld non-zeros):\n", static_cast<long>(K.rows()),
                  static_cast<long>(K.cols()), static_cast<long>(K.nonZeros()));
    for (Eigen::Index row = 0; row < K.outerSize(); ++row)
        for (SparseMatrix::InnerIterator it(K, row); it; ++it)
            out << format("     K(%2ld,%2ld) = %+g\n", static_cast<long>(it.row()), static_cast<long>(it.col()),
                          it.value());
}

/// Part 2: a 1 kg particle dropped with a horizontal velocity on a fixed contact point, with
/// normal damping and Coulomb friction; symplectic Euler, the contact renewed every step.
bool damped_frictional_drop(const DemoOptions& options, std::ostream& out) {
    out << "\n== A 1 kg particle dropped on a floor, with damping and Coulomb friction (beyond SOFA)\n";
    PenaltyParameters parameters;
    parameters.damping = options.damping;
    parameters.friction = FrictionModel::coulomb;
    parameters.tangential_damping = 2.0 * std::sqrt(options.stiffness);
    parameters.time_step = 1e-4;
    PenaltyForceField ff(parameters);
    const double mass = 1.0, g = 9.81, dist = 0.05;
    Vec3List x1{Vec3::Zero()}, v1{Vec3::Zero()}, x2{Vec3(0, 0.2, 0)}, v2{Vec3(0.5, 0, 0)};
    ff.add_contact(DofIndex(0), DofIndex(0), ElementIndex(0), ElementIndex(0), Vec3::UnitY(), dist, options.stiffness,
                   options.friction, options.friction);
    const double initial = mass * g * x2[0].y() + 0.5 * mass * v2[0].squaredNorm();

    out << format("   ks = %g N/m, c = %g N·s/m, mu = %g, dt = %g s\n", options.stiffness, options.damping,
                  options.friction, parameters.time_step);
    out << "   t (s)   y (m)     vx (m/s)  vy (m/s)   pen (m)   f_n (N)   |f_t| (N)  state  stored (J)  dissipated "
           "(J)\n";
    const int steps = 8000;
    for (int i = 0; i <= steps; ++i) {
        Vec3List f1{Vec3::Zero()}, f2{Vec3(0, -mass * g, 0)};
        ff.add_force(f1, f2, x1, x2, v1, v2);
        const PenaltyContact& c = ff.contacts()[0];
        if (i % 500 == 0)
            out << format("   %.3f  %.5f  %8.5f  %8.5f  %8.5f  %8.4f  %8.4f   %-5s  %.4e  %.4e\n",
                          i * parameters.time_step, x2[0].y(), v2[0].x(), v2[0].y(), std::max(0.0, c.pen),
                          c.normal_force, c.tangential_force.norm(), state_name(c.friction_state),
                          ff.potential_energy(), ff.dissipated_energy());
        if (i == steps) break;
        v2[0] += parameters.time_step * f2[0] / mass;
        x2[0] += parameters.time_step * v2[0];
        ff.renew_contacts();
    }
    // energy balance: initial = gravity potential + kinetic + stored + dissipated
    Vec3List f1{Vec3::Zero()}, f2{Vec3::Zero()};
    ff.add_force(f1, f2, x1, x2, v1, v2);
    const double final_energy =
        mass * g * x2[0].y() + 0.5 * mass * v2[0].squaredNorm() + ff.potential_energy() + ff.dissipated_energy();
    const double error = std::abs(final_energy - initial) / initial;
    out << format(
        "   energy balance: initial %.6f J, final (potential + kinetic + stored + dissipated) "
        "%.6f J, relative error %.2e\n",
        initial, final_energy, error);
    out << format("   dissipated by damping %.6f J, by sliding %.6f J\n", ff.dissipated_by_damping(),
                  ff.dissipated_by_sliding());
    return error < 1e-2;
}

}  // namespace

int run_demo(const DemoOptions& options, std::ostream& out) {
    pressed_plates(options, out);
    const bool balanced = damped_frictional_drop(options, out);
    return balanced ? 0 : 2;
}

}  // namespace penalty::apps
