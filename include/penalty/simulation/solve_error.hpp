#pragma once
/// @file
/// The error a solve raises when a value is not finite.

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

}  // namespace penalty
