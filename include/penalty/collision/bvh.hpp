#pragma once
/// @file
/// Axis-aligned bounding-box tree over the element boxes of one collision model (the role of
/// SOFA's CubeCollisionModel, spec §3.8). Leaves hold at most `leaf_size` elements; internal
/// nodes are split at the median element (by box centre, ties by element index) along the
/// largest extent of the element centres of the node. Nodes are stored in depth-first pre-order: the left child of
/// node i is i + 1, the right child is `right`. The tree only prunes: the leaf boxes are exactly
/// CollisionModel::element_box(i), so a traversal finds the same element pairs as an
/// exhaustive loop with the same box test.

#include "penalty/collision/collision_model.hpp"

#include <cstdint>
#include <vector>

namespace penalty {

/// One node of a Bvh.
struct BvhNode {
    Aabb box;                 ///< union of the element boxes below
    std::uint32_t first = 0;  ///< first slot in Bvh::order() of the elements below
    std::uint32_t count = 0;  ///< number of elements below
    std::uint32_t right = 0;  ///< right child index; 0 for a leaf (left child = this + 1)
    [[nodiscard]] bool leaf() const { return right == 0; }
};

/// Bounding-box tree of one model.
class Bvh {
public:
    /// Recomputes the element boxes of `model` (in parallel) and rebuilds the tree.
    /// Throws std::invalid_argument naming the model and the element if a box is not finite.
    void build(const CollisionModel& model, std::size_t leaf_size = 4);
    /// Recomputes the element boxes and refits the node boxes bottom-up, keeping the topology of
    /// the tree. Rebuilds instead when the model size changed or when the summed surface area of
    /// the internal nodes exceeds `rebuild_ratio` × its value at the last build (the tree has
    /// degraded). Returns true if it rebuilt. Same errors as build().
    bool refit(const CollisionModel& model, double rebuild_ratio = 2.0, std::size_t leaf_size = 4);

    [[nodiscard]] bool empty() const { return nodes_.empty(); }
    [[nodiscard]] const std::vector<BvhNode>& nodes() const { return nodes_; }
    /// Element indices, permuted so that every node covers a contiguous range.
    [[nodiscard]] const std::vector<std::uint32_t>& order() const { return order_; }
    /// element_box(i) of the model at the last build/refit, indexed by element.
    [[nodiscard]] const std::vector<Aabb>& element_boxes() const { return boxes_; }
    /// The element boxes in tree order: ordered_boxes()[s] == element_boxes()[order()[s]]
    /// (contiguous per node, for the traversal).
    [[nodiscard]] const std::vector<Aabb>& ordered_boxes() const { return ordered_; }
    [[nodiscard]] const Aabb& root_box() const { return nodes_.front().box; }
    /// Depth of the tree (a single leaf has depth 1; 0 when empty).
    [[nodiscard]] int depth() const;
    /// Number of builds since construction (refits that rebuilt included).
    [[nodiscard]] std::size_t build_count() const { return builds_; }

private:
    void compute_boxes(const CollisionModel& model);
    void reorder_boxes();
    double refit_nodes();  // returns the summed surface area of the internal nodes

    std::vector<BvhNode> nodes_;
    std::vector<std::uint32_t> order_;
    std::vector<Aabb> boxes_;
    std::vector<Aabb> ordered_;
    double built_area_ = 0.0;
    std::size_t builds_ = 0;
};

}  // namespace penalty
