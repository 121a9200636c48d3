// SubtreeSystem's diagnostics of a non-finite solve: which contribution is not finite, or the
// largest force when a finite one overflowed the solve.
#include "penalty/simulation/subtree_system.hpp"

#include "subtree_layout.hpp"

#include <cstdio>

namespace penalty {

std::vector<BaseState*> SubtreeSystem::all_states() const {
    std::vector<BaseState*> all(layout_->independent);
    all.insert(all.end(), layout_->mapped.begin(), layout_->mapped.end());
    all.insert(all.end(), layout_->external.begin(), layout_->external.end());
    return all;
}

void SubtreeSystem::throw_non_finite_force() const {
    // The states a contribution writes into, checked after each contribution in compute_force's
    // order; velocities that are already non-finite are named first (the runner checks positions).
    const std::vector<BaseState*> all = all_states();
    const auto first_bad = [&](bool kinematics) -> const BaseState* {
        for (const BaseState* s : all) {
            if (kinematics ? !const_cast<BaseState*>(s)->velocity_flat().allFinite()
                           : !const_cast<BaseState*>(s)->force_flat().allFinite())
                return s;
        }
        return nullptr;
    };
    if (const BaseState* s = first_bad(true))
        throw NonFiniteSolveError("the velocities of state '" + std::string(s->state_name()) + "' are not finite",
                                  nullptr, nullptr, s);
    reset_forces();
    if (const BaseState* s = first_bad(false))
        throw NonFiniteSolveError("the external forces on state '" + std::string(s->state_name()) + "' are not finite",
                                  nullptr, nullptr, s);
    for (const auto& [mass, g] : layout_->masses) {
        mass->add_gravity_force(g);
        if (const BaseState* s = first_bad(false))
            throw NonFiniteSolveError(
                "the gravity force m·g on state '" + std::string(s->state_name()) + "' is not finite", nullptr, mass,
                s);
    }
    for (BaseForceField* ff : layout_->force_fields) {
        ff->accumulate_force();
        if (const BaseState* s = first_bad(false))
            throw NonFiniteSolveError(
                "a force field's force on state '" + std::string(s->state_name()) + "' is not finite", ff, nullptr, s);
    }
    throw NonFiniteSolveError("the forces are not finite after the mappings' Jᵀ", nullptr, nullptr, nullptr);
}

void SubtreeSystem::throw_naming_largest_force(const std::string& what) const {
    // Each contribution alone, in compute_force's order; the one with the largest |f|∞ is named
    // (an overflow of |b| or of a CG product starts from the largest force).
    const std::vector<BaseState*> all = all_states();
    const auto largest = [&](const BaseState*& where) {
        double m = 0.0;
        for (BaseState* s : all) {
            const double v = s->force_flat().size() > 0 ? s->force_flat().cwiseAbs().maxCoeff() : 0.0;
            if (!(v <= m)) {  // NaN counts as largest
                m = v;
                where = s;
            }
        }
        return m;
    };
    double best = -1.0;
    const BaseForceField* best_ff = nullptr;
    const BaseMass* best_mass = nullptr;
    const BaseState* best_state = nullptr;
    const auto consider = [&](const BaseForceField* ff, const BaseMass* mass) {
        const BaseState* where = nullptr;
        const double m = largest(where);
        if (!(m <= best)) {
            best = m;
            best_ff = ff;
            best_mass = mass;
            best_state = where;
        }
    };
    for (const auto& [mass, g] : layout_->masses) {
        reset_forces();
        for (BaseState* s : all) s->force_flat().setZero();
        mass->add_gravity_force(g);
        consider(nullptr, mass);
    }
    for (BaseForceField* ff : layout_->force_fields) {
        for (BaseState* s : all) s->force_flat().setZero();
        ff->accumulate_force();
        consider(ff, nullptr);
    }
    std::string source;
    char magnitude[32];
    std::snprintf(magnitude, sizeof magnitude, "%.6g", best);
    if (best_state != nullptr)
        source = "; the largest force (" + std::string(magnitude) + " N) is " +
                 (best_mass != nullptr ? "the gravity force m·g" : "a force field's") + " on state '" +
                 std::string(best_state->state_name()) + "'";
    throw NonFiniteSolveError(what + source, best_ff, best_mass, best_state);
}

}  // namespace penalty
