// The map-back stage's plan: the nodes' steps in waves of independent steps (map_back_plan.hpp).
#include "map_back_plan.hpp"

#include "penalty/core/first_error.hpp"
#include "simulation_internal.hpp"  // for_each_node

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace penalty::detail {

namespace {
/// Steps a TBB task takes at least (a contact pair's mapping is a few points: µs).
constexpr std::size_t kMapBackStepsPerTask = 16;
}  // namespace

void MapBackPlan::update(Node& root) {
    if (version_ == root.structure_version()) return;
    build(root);
    version_ = root.structure_version();
}

void MapBackPlan::build(Node& root) {
    nodes_.clear();
    wave_of_.clear();
    state_index_.clear();
    after_writer_.clear();
    after_reader_.clear();
    floor_ = 0;
    next_wave_ = 0;
    for_each_node(root, [this](Node& n) { add_node(n); });
    // the steps grouped by wave, depth first within a wave (a counting sort)
    wave_first_.assign(std::size_t(next_wave_) + 1, 0);
    for (const std::uint32_t w : wave_of_) ++wave_first_[w + 1];
    for (std::size_t w = 0; w < next_wave_; ++w) wave_first_[w + 1] += wave_first_[w];
    by_wave_.resize(nodes_.size());
    fill_.assign(wave_first_.begin(), wave_first_.end() - 1);
    for (std::size_t i = 0; i < nodes_.size(); ++i) by_wave_[fill_[wave_of_[i]]++] = std::uint32_t(i);
}

std::size_t MapBackPlan::slot(const BaseState* state) {
    const auto [index, added] = state_index_.emplace(state, after_writer_.size());
    if (added) {
        after_writer_.push_back(0);
        after_reader_.push_back(0);
    }
    return index;
}

void MapBackPlan::add_node(Node& node) {
    BaseMapping* mapping = node.mapping();
    const bool constrained = !node.constraints().empty();
    if (!constrained && mapping == nullptr) return;
    std::uint32_t wave = floor_;
    if (constrained || mapping->from() == nullptr || mapping->to() == nullptr) {
        // a wave of its own, after every earlier step: a constraint may read any state
        wave = next_wave_;
        floor_ = wave + 1;
    } else {
        // reads from() (and second_from()), writes to()
        const std::size_t out = slot(mapping->to());
        const std::size_t in1 = slot(mapping->from());
        const std::size_t in2 = mapping->second_from() != nullptr ? slot(mapping->second_from()) : in1;
        wave = std::max({wave, after_writer_[in1], after_writer_[in2], after_writer_[out], after_reader_[out]});
        after_reader_[in1] = std::max(after_reader_[in1], wave + 1);
        after_reader_[in2] = std::max(after_reader_[in2], wave + 1);
        after_writer_[out] = wave + 1;
    }
    next_wave_ = std::max(next_wave_, wave + 1);
    nodes_.push_back(&node);
    wave_of_.push_back(wave);
}

std::vector<const Node*> MapBackPlan::wave_nodes(std::size_t w) const {
    std::vector<const Node*> nodes;
    for (std::size_t k = wave_first_[w]; k < wave_first_[w + 1]; ++k) nodes.push_back(nodes_[by_wave_[k]]);
    return nodes;
}

void MapBackPlan::run_step(std::size_t depth_first_index) const {
    const Node& n = *nodes_[depth_first_index];
    for (const auto& c : n.constraints()) {
        c->project_position();
        c->project_velocity();
    }
    if (BaseMapping* m = n.mapping()) {
        m->apply_position();
        m->apply_velocity();
    }
}

void MapBackPlan::run(bool concurrent) const {
    if (!concurrent) {
        for (std::size_t i = 0; i < nodes_.size(); ++i) run_step(i);
        return;
    }
    // A failing step stops the depth-first pass: the steps after it in that order do not run
    // (those of later waves; those of its own wave may have), so the error raised is the first
    // in depth-first order, as the sequential pass's.
    FirstErrorInOrder failure;
    const auto run_steps = [&](std::size_t begin, std::size_t end, std::size_t stop) {
        for (std::size_t k = begin; k < end; ++k) {
            const std::size_t i = by_wave_[k];
            if (i >= stop) continue;
            if (!failure.run(i, [&] { run_step(i); })) return;
        }
    };
    for (std::size_t w = 0; w + 1 < wave_first_.size(); ++w) {
        const std::size_t begin = wave_first_[w], end = wave_first_[w + 1];
        const std::size_t stop = failure.first_index();  // between waves: no task runs
        if (end - begin < kMinStepsForConcurrentMapBack) {
            run_steps(begin, end, stop);
            continue;
        }
        tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, kMapBackStepsPerTask),
                          [&](const tbb::blocked_range<std::size_t>& r) { run_steps(r.begin(), r.end(), stop); });
    }
    failure.rethrow_if_any();
}

}  // namespace penalty::detail
