#pragma once
// A contact stage that runs a test's function at the start of each step (Simulation::step's
// respond stage): a hand-made contact, an update() counted apart.

#include "penalty/simulation/simulation.hpp"

#include <functional>
#include <utility>

namespace penalty::test {

/// Registers itself with `simulation` for its lifetime; detect() does nothing, respond() runs `f`.
class FunctionStage final : public ContactStage {
public:
    FunctionStage(Simulation& simulation, std::function<void()> f) : simulation_(simulation), f_(std::move(f)) {
        simulation_.add_contact_stage(*this);
    }
    ~FunctionStage() override { simulation_.remove_contact_stage(*this); }
    FunctionStage(const FunctionStage&) = delete;
    FunctionStage& operator=(const FunctionStage&) = delete;
    void detect() override {}
    void respond() override { f_(); }

private:
    Simulation& simulation_;
    std::function<void()> f_;
};

}  // namespace penalty::test
