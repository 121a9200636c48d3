#pragma once
/// @file
/// An index list that a Data link may replace while the scene runs. SOFA's projective constraints
/// read `d_indices.getValue()` at each projection; when `indices` links an engine output
/// (`indices="@roi.indices"`) whose input changed, that read runs the engine first
/// (DDGNode::updateIfDirty → DataEngine::update) and gives its new output.

#include "penalty/core/types.hpp"

#include <functional>
#include <vector>

namespace penalty {

/// A component whose index list follows a source: the source is called before each read and may
/// replace the list (src/scene/live_engines.cpp connects it to an engine over moving positions).
class FollowedIndices {
public:
    using IndexSource = std::function<void(std::vector<Index>& indices)>;
    virtual ~FollowedIndices() = default;
    void set_index_source(IndexSource source) { index_source_ = std::move(source); }

protected:
    [[nodiscard]] bool has_index_source() const { return static_cast<bool>(index_source_); }
    /// `indices` after the source, if any, replaced them.
    const std::vector<Index>& follow(std::vector<Index>& indices) const {
        if (index_source_) index_source_(indices);
        return indices;
    }

private:
    IndexSource index_source_;
};

}  // namespace penalty
