// find_step_chains: a subtree's force steps split into chains of disjoint written states.
#include "step_chains.hpp"

#include "penalty/core/error.hpp"
#include "penalty/core/pointer_index.hpp"

#include <algorithm>
#include <numeric>

namespace penalty::detail {

namespace {
/// Union-find over the states a product writes, kept by the thread from one build to the next.
struct ChainTables {
    PointerIndex<BaseState> id_of;
    std::vector<std::uint32_t> parent;
    std::vector<std::uint32_t> chain_of_root;  // per state id: its chain, or kNone
    std::vector<std::uint32_t> step_chain;     // per step: its chain
    std::vector<std::uint32_t> mapping_chain;  // per pass mapping: its chain
    std::vector<std::size_t> next;             // group_by_chain's cursors
    static constexpr std::uint32_t kNone = ~std::uint32_t{0};

    std::uint32_t id(const BaseState* s) {
        const auto [at, added] = id_of.emplace(s, parent.size());
        if (added) parent.push_back(static_cast<std::uint32_t>(at));
        return static_cast<std::uint32_t>(at);
    }
    std::uint32_t root(std::uint32_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    }
    void join(std::uint32_t a, std::uint32_t b) {
        a = root(a);
        b = root(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
    /// The chain of `state`'s root, numbered in order of first request.
    std::uint32_t chain(const BaseState* s, std::uint32_t& chains) {
        std::uint32_t& c = chain_of_root[root(id(s))];
        if (c == kNone) c = chains++;
        return c;
    }
};

/// The state a step writes first (the one that names its chain).
const BaseState* written_state(const ForceStep& s) {
    if (s.mass != nullptr) return s.mass->state();
    if (s.force_field != nullptr) return s.force_field->states()[0];
    return s.mapping->from();
}

/// Lists `items`' indices grouped by chain, each group in ascending order (a counting sort).
void group_by_chain(const std::vector<std::uint32_t>& chain_of, std::uint32_t chains, std::vector<std::size_t>& first,
                    std::vector<std::uint32_t>& of, std::vector<std::size_t>& next) {
    first.assign(chains + 1, 0);
    for (const std::uint32_t c : chain_of) ++first[c + 1];
    std::partial_sum(first.begin(), first.end(), first.begin());
    of.resize(chain_of.size());
    next.assign(first.begin(), first.end() - 1);
    for (std::size_t i = 0; i < chain_of.size(); ++i) of[next[chain_of[i]]++] = static_cast<std::uint32_t>(i);
}
}  // namespace

std::size_t StepChains::largest() const {
    std::size_t most = 0;
    for (std::size_t c = 0; c + 1 < step_first.size(); ++c) most = std::max(most, step_first[c + 1] - step_first[c]);
    return most;
}

void find_step_chains(const SubtreeLayout& layout, const std::vector<ForceStep>& steps,
                      const std::vector<std::size_t>& mapped, StepChains& chains) {
    thread_local ChainTables tables;
    ChainTables& t = tables;
    t.id_of.clear();
    t.parent.clear();
    // the written states joined: a step's states, a mapping's parent and child
    for (const ForceStep& s : steps) {
        if (s.mass != nullptr) {
            (void)t.id(s.mass->state());
        } else if (s.force_field != nullptr) {
            const ForceFieldStates states = s.force_field->states();
            PENALTY_DEMAND(states.size() > 0);
            for (std::size_t i = 1; i < states.size(); ++i) t.join(t.id(states[0]), t.id(states[i]));
            (void)t.id(states[0]);
        } else {
            // Jᵀ writes its input (and a second input: Multi2Mapping), reading its output
            t.join(t.id(s.mapping->from()), t.id(s.mapping->to()));
            if (const BaseState* second = s.mapping->second_from()) t.join(t.id(second), t.id(s.mapping->to()));
        }
    }
    for (const std::size_t m : mapped) {
        const BaseMapping& mapping = *layout.mappings[m];
        t.join(t.id(mapping.from()), t.id(mapping.to()));
        if (const BaseState* second = mapping.second_from()) t.join(t.id(second), t.id(mapping.to()));
    }
    t.chain_of_root.assign(t.parent.size(), ChainTables::kNone);
    std::uint32_t count = 0;
    t.step_chain.resize(steps.size());
    for (std::size_t i = 0; i < steps.size(); ++i) t.step_chain[i] = t.chain(written_state(steps[i]), count);
    t.mapping_chain.resize(mapped.size());
    for (std::size_t i = 0; i < mapped.size(); ++i)
        t.mapping_chain[i] = t.chain(layout.mappings[mapped[i]]->to(), count);
    group_by_chain(t.step_chain, count, chains.step_first, chains.steps_of, t.next);
    group_by_chain(t.mapping_chain, count, chains.mapping_first, chains.mappings_of, t.next);
    // mappings_of holds places in `mapped`: the layout's indices
    for (std::uint32_t& m : chains.mappings_of) m = static_cast<std::uint32_t>(mapped[m]);
}

}  // namespace penalty::detail
