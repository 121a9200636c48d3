#include "penalty/simulation/simulation.hpp"

#include "penalty/core/error.hpp"
#include "penalty/simulation/ode_solver.hpp"

#include "simulation_internal.hpp"

#include <algorithm>

namespace penalty {

Simulation::Simulation() : root_("root") {}
Simulation::~Simulation() = default;

void Simulation::set_threads(int threads) {
    if (threads < 0 || threads > kMaxThreads)
        throw_invalid_argument("Simulation: threads must be between 0 and ", kMaxThreads, ", got ", threads);
    if (threads != threads_) arena_.reset();
    threads_ = threads;
}

/// SOFA's Simulation::init ends with MechanicalProjectPositionAndVelocityVisitor (time 0) and
/// the propagation of positions and velocities: each constraint's project_position then
/// project_velocity, and the mappings under a node with a constraint that moves positions
/// applied again (the others' outputs are already what they map).
void Simulation::project_initial_state(Node& node, bool moved_above) {
    bool moved = moved_above;
    for (const auto& c : node.constraints()) {
        c->project_position();
        c->project_velocity();
        moved = moved || c->projects_positions();
    }
    if (moved && node.mapping()) {
        node.mapping()->apply_position();
        node.mapping()->apply_velocity();
    }
    for (const auto& child : node.children()) project_initial_state(*child, moved);
}

void Simulation::init() {
    detail::for_each_node(root_, [](Node& n) {
        if (n.mapping()) {
            n.mapping()->init();
        } else if (n.state()) {
            n.state()->init();
        }
    });
    detail::for_each_node(root_, [](Node& n) {
        if (n.mass()) n.mass()->init();
        for (const auto& ff : n.force_fields()) ff->init();
        for (const auto& c : n.constraints()) c->init();
        if (n.ode_solver()) n.ode_solver()->init(n);
    });
    project_initial_state(root_, false);
    initialized_ = true;
}

void Simulation::set_multi_step(int collision_steps, int integration_steps, bool sofa_time) {
    constexpr int kMaxSubsteps = 1000000;
    if (collision_steps < 1 || collision_steps > kMaxSubsteps || integration_steps < 1 ||
        integration_steps > kMaxSubsteps)
        throw_invalid_argument("Simulation: collision and integration steps must be between 1 and ", kMaxSubsteps,
                               ", got ", collision_steps, " and ", integration_steps);
    collision_steps_ = collision_steps;
    integration_steps_ = integration_steps;
    sofa_multi_step_time_ = sofa_time;
}

void Simulation::add_contact_stage(ContactStage& stage) {
    if (std::find(contact_stages_.begin(), contact_stages_.end(), &stage) != contact_stages_.end())
        throw_invalid_argument("Simulation: the contact stage is already registered");
    contact_stages_.push_back(&stage);
}

void Simulation::remove_contact_stage(const ContactStage& stage) { std::erase(contact_stages_, &stage); }

}  // namespace penalty
