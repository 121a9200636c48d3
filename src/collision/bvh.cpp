#include "penalty/collision/bvh.hpp"

#include "kernels/prefetch.hpp"
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

// Element centres (twice the centre: min + max) with the element index, permuted in place.
struct Item {
    double c[3];
    std::uint32_t id;
};

struct Builder {
    std::vector<BvhNode>& nodes;
    std::vector<Item>& items;
    std::uint32_t leaf;

    // builds the topology of the subtree of items[first, first+count) at node index `at`
    // (node boxes are filled afterwards by Bvh::refit_nodes)
    void build(std::uint32_t at, std::uint32_t first, std::uint32_t count) {
        BvhNode& node = nodes[at];
        node.first = first;
        node.count = count;
        if (count <= leaf) {
            node.right = 0;
            return;
        }
        double lo[3] = {items[first].c[0], items[first].c[1], items[first].c[2]};
        double hi[3] = {lo[0], lo[1], lo[2]};
        for (std::uint32_t k = first + 1; k < first + count; ++k)
            for (int d = 0; d < 3; ++d) {
                lo[d] = std::min(lo[d], items[k].c[d]);
                hi[d] = std::max(hi[d], items[k].c[d]);
            }
        int axis = 0;
        if (hi[1] - lo[1] > hi[axis] - lo[axis]) axis = 1;
        if (hi[2] - lo[2] > hi[axis] - lo[axis]) axis = 2;
        const std::uint32_t half = count / 2;
        Item* b = items.data() + first;
        std::nth_element(b, b + half, b + count, [axis](const Item& i, const Item& j) {
            return i.c[axis] < j.c[axis] || (i.c[axis] == j.c[axis] && i.id < j.id);
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
    static_assert(sizeof(Aabb) == 6 * sizeof(double), "an Aabb is six packed doubles");
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        Aabb* out = boxes_.data() + r.begin();
        model.element_boxes(r.begin(), r.end(), out);
        // one vectorised pass over the range's bounds; the first bad box searched only on failure
        if (all_finite(out->min.data(), 6 * r.size())) return;
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            if (!boxes_[i].min.allFinite() || !boxes_[i].max.allFinite()) {
                std::size_t cur = bad.load();
                while (i < cur && !bad.compare_exchange_weak(cur, i)) {
                }
                break;
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

void Bvh::reorder_boxes() {
    ordered_.resize(boxes_.size());
    const bool prefetch = detail::prefetch::worth_it(boxes_.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, boxes_.size(), 4096),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          // boxes_ is read in tree order, no memory order
                          const std::size_t ahead = detail::prefetch::kAhead;
                          for (std::size_t s = r.begin(); s != r.end(); ++s) {
                              if (prefetch && s + ahead < r.end())
                                  detail::prefetch::object(boxes_.data() + order_[s + ahead], sizeof(Aabb));
                              ordered_[s] = boxes_[order_[s]];
                          }
                      });
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
        ordered_.clear();
        built_area_ = 0.0;
        return;
    }
    nodes_.resize(subtree_nodes(n, leaf));
    std::vector<Item> items(n);
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, 4096), [&](const tbb::blocked_range<std::uint32_t>& r) {
        for (std::uint32_t i = r.begin(); i != r.end(); ++i) {
            const Aabb& b = boxes_[i];
            items[i] = Item{{b.min[0] + b.max[0], b.min[1] + b.max[1], b.min[2] + b.max[2]}, i};
        }
    });
    Builder{nodes_, items, leaf}.build(0, 0, n);
    for (std::uint32_t s = 0; s < n; ++s) order_[s] = items[s].id;
    reorder_boxes();
    built_area_ = refit_nodes();
}

double Bvh::refit_nodes() {
    double sum = 0.0;
    for (std::size_t k = nodes_.size(); k-- > 0;) {
        BvhNode& node = nodes_[k];
        Aabb box;
        if (node.leaf()) {
            for (std::uint32_t s = node.first; s < node.first + node.count; ++s) box.extend(ordered_[s]);
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
    reorder_boxes();
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
