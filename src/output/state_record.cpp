#include "penalty/output/state_record.hpp"

#include "penalty/core/error.hpp"
#include "penalty/simulation/node.hpp"
#include "penalty/simulation/solver.hpp"

namespace penalty::output {

std::vector<const StateRecord*> select_exported_states(std::span<const StateRecord> states, bool include_mapped) {
    std::vector<const StateRecord*> selected;
    for (const StateRecord& record : states)
        if (record.in_solver_subtree && (!record.mapped || include_mapped)) selected.push_back(&record);
    return selected;
}

namespace {

void collect(const Node& node, const std::string& path, bool under_solver, std::vector<StateRecord>& out) {
    const bool in_solver_subtree = under_solver || node.ode_solver() != nullptr;
    if (BaseState* state = node.state()) {
        StateRecord record;
        record.name = std::string(state->state_name());
        record.node_path = path;
        record.state = state;
        record.mapped = node.mapping() != nullptr && node.mapping()->to() == state;
        record.in_solver_subtree = in_solver_subtree;
        if (node.mass() != nullptr && node.mass()->state() == state) record.mass = node.mass();
        out.push_back(std::move(record));
    }
    for (const auto& child : node.children()) {
        const std::string child_path = (path == "/" ? path : path + "/") + child->name();
        collect(*child, child_path, in_solver_subtree, out);
    }
}

}  // namespace

std::vector<StateRecord> collect_state_records(const Node& root) {
    std::vector<StateRecord> records;
    collect(root, "/", false, records);
    return records;
}

int values_per_dof(const BaseState& state) {
    if (dynamic_cast<const Vec3Object*>(&state) != nullptr) return 3;
    if (dynamic_cast<const Rigid3Object*>(&state) != nullptr) return 7;
    if (dynamic_cast<const Vec1Object*>(&state) != nullptr) return 1;
    throw_invalid_argument("values_per_dof: state '", state.state_name(), "' is neither Vec3d, Rigid3d nor Vec1d");
}

bool has_points_in_space(const StateRecord& record) {
    return dynamic_cast<const Vec3Object*>(record.state) != nullptr ||
           dynamic_cast<const Rigid3Object*>(record.state) != nullptr;
}

std::string state_label(const StateRecord& record) {
    return (record.node_path.empty() || record.node_path.back() == '/' ? record.node_path : record.node_path + "/") +
           record.name;
}

}  // namespace penalty::output
