#include "penalty/collision/bvh.hpp"

#include "penalty/core/error.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <atomic>
#include <limits>
#include <map>

namespace penalty {

namespace {

constexpr std::uint32_t kParallelBuildMin = 8192;  // subtrees at least this large build in parallel

double area(const Aabb& b) {
    const Vec3 d = b.max - b.min;
    return 2.0 * (d.x() * d.y() + d.y() * d.z() + d.z() * d.x());
}

// number of leaves of a subtree of n elements (median split, leaves of <= leaf elements)
std::uint32_t leaves(std::uint32_t n, std::uint32_t leaf, std::map<std::uint32_t, std::uint32_t>& memo) {
    if (n <= leaf) return 1;
    if (auto it = memo.find(n); it != memo.end()) return it->second;
    const std::uint32_t r = leaves(n / 2, leaf, memo) + leaves(n - n / 2, leaf, memo);
    memo.emplace(n, r);
    return r;
}

std::uint32_t subtree_nodes(std::uint32_t n, std::uint32_t leaf) {
    std::map<std::uint32_t, std::uint32_t> memo;
    return 2 * leaves(n, leaf, memo) - 1;
}

struct Builder {
    std::vector<BvhNode>& nodes;
    std::vector<std::uint32_t>& order;
    const std::vector<Aabb>& boxes;
    std::uint32_t leaf;

    // builds the subtree of elements order[first, first+count) at node index `at`
    void build(std::uint32_t at, std::uint32_t first, std::uint32_t count) {
        BvhNode& node = nodes[at];
        node.first = first;
        node.count = count;
        Aabb box;
        for (std::uint32_t k = first; k < first + count; ++k) box.extend(boxes[order[k]]);
        node.box = box;
        if (count <= leaf) {
            node.right = 0;
            return;
        }
        int axis = 0;
        const Vec3 ext = box.max - box.min;
        if (ext.y() > ext[axis]) axis = 1;
        if (ext.z() > ext[axis]) axis = 2;
        const std::uint32_t half = count / 2;
        auto* b = order.data() + first;
        std::nth_element(b, b + half, b + count, [&](std::uint32_t i, std::uint32_t j) {
            const double ci = boxes[i].min[axis] + boxes[i].max[axis];
            const double cj = boxes[j].min[axis] + boxes[j].max[axis];
            return ci < cj || (ci == cj && i < j);
        });
        const std::uint32_t right = at + 1 + subtree_nodes(half, leaf);
        node.right = right;
        if (count >= kParallelBuildMin) {
            tbb::parallel_invoke([&] { build(at + 1, first, half); },
                                 [&] { build(right, first + half, count - half); });
        } else {
            build(at + 1, first, half);
            build(right, first + half, count - half);
        }
    }
};

}  // namespace

void Bvh::compute_boxes(const CollisionModel& model) {
    const std::size_t n = model.size();
    if (n >= std::size_t(std::numeric_limits<std::uint32_t>::max() / 2)) {
        throw_invalid_argument(model_type_name(model.type()), "Model '", model.name(), "': ", n,
                               " elements is too many for the bounding tree");
    }
    boxes_.resize(n);
    std::atomic<std::size_t> bad{n};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            boxes_[i] = model.element_box(Index(i));
            if (!boxes_[i].min.allFinite() || !boxes_[i].max.allFinite()) {
                std::size_t cur = bad.load();
                while (i < cur && !bad.compare_exchange_weak(cur, i)) {
                }
            }
        }
    });
    if (const std::size_t i = bad.load(); i < n) {
        const Aabb& b = boxes_[i];
        throw_invalid_argument(model_type_name(model.type()), "Model '", model.name(), "': element ", i,
                               ": bounding box is not finite (min ", b.min.x(), ", ", b.min.y(), ", ", b.min.z(),
                               "; max ", b.max.x(), ", ", b.max.y(), ", ", b.max.z(),
                               "): a position or radius is NaN or infinite");
    }
}

void Bvh::build(const CollisionModel& model, std::size_t leaf_size) {
    compute_boxes(model);
    const auto n = std::uint32_t(boxes_.size());
    const auto leaf = std::uint32_t(std::max<std::size_t>(1, leaf_size));
    ++builds_;
    order_.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) order_[i] = i;
    nodes_.clear();
    if (n == 0) {
        built_area_ = 0.0;
        return;
    }
    nodes_.resize(subtree_nodes(n, leaf));
    Builder{nodes_, order_, boxes_, leaf}.build(0, 0, n);
    double sum = 0.0;
    for (const auto& node : nodes_)
        if (!node.leaf()) sum += area(node.box);
    built_area_ = sum;
}

double Bvh::refit_nodes() {
    double sum = 0.0;
    for (std::size_t k = nodes_.size(); k-- > 0;) {
        BvhNode& node = nodes_[k];
        Aabb box;
        if (node.leaf()) {
            for (std::uint32_t s = node.first; s < node.first + node.count; ++s) box.extend(boxes_[order_[s]]);
        } else {
            box = nodes_[k + 1].box;
            box.extend(nodes_[node.right].box);
            sum += area(box);
        }
        node.box = box;
    }
    return sum;
}

bool Bvh::refit(const CollisionModel& model, double rebuild_ratio, std::size_t leaf_size) {
    if (nodes_.empty() || model.size() != boxes_.size()) {
        build(model, leaf_size);
        return true;
    }
    compute_boxes(model);
    const double sum = refit_nodes();
    if (sum > rebuild_ratio * built_area_) {
        build(model, leaf_size);
        return true;
    }
    return false;
}

int Bvh::depth() const {
    if (nodes_.empty()) return 0;
    // iterative: depth of each node from its parent (pre-order: parents come first)
    std::vector<int> d(nodes_.size(), 1);
    int best = 1;
    for (std::size_t k = 0; k < nodes_.size(); ++k) {
        if (!nodes_[k].leaf()) {
            d[k + 1] = d[k] + 1;
            d[nodes_[k].right] = d[k] + 1;
        }
        best = std::max(best, d[k]);
    }
    return best;
}

}  // namespace penalty
