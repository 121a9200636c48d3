#pragma once
/// @file
/// The errors a solve raises: a value that is not finite (the run diverged, or a parameter
/// overflows), and a system with nothing to solve (a defect of the scene).

#include <stdexcept>
#include <string>

namespace penalty {

class BaseForceField;
class BaseMass;
class BaseState;

/// A non-finite value in a solve (forces, right-hand side or CG solution): the run diverged, or a
/// parameter makes a product overflow. Names what produced it where the solver can tell: the
/// first force field whose contribution is not finite (nullptr: unknown, or the gravity force of
/// a mass, see `mass`), and the state where it shows.
class NonFiniteSolveError : public std::runtime_error {
public:
    NonFiniteSolveError(const std::string& what, const BaseForceField* force_field, const BaseMass* mass,
                        const BaseState* state)
        : std::runtime_error(what), force_field_(force_field), mass_(mass), state_(state) {}
    [[nodiscard]] const BaseForceField* force_field() const { return force_field_; }
    [[nodiscard]] const BaseMass* mass() const { return mass_; }
    [[nodiscard]] const BaseState* state() const { return state_; }

private:
    const BaseForceField* force_field_;
    const BaseMass* mass_;
    const BaseState* state_;
};

/// A direct solver's system matrix without a stored entry: the states it solves have no mass, no
/// stiffness and no constraint. Not a divergence (no time step helps): the scene lacks a mass.
/// `solver` is the DirectLinearSolver that raised it (the scene names its component).
class SingularSystemError : public std::invalid_argument {
public:
    SingularSystemError(const std::string& what, const void* solver) : std::invalid_argument(what), solver_(solver) {}
    [[nodiscard]] const void* solver() const { return solver_; }

private:
    const void* solver_;
};

}  // namespace penalty
