#pragma once
/// @file
/// The order in which SOFA's BVHNarrowPhase visits the element pairs of a model pair, so that
/// penalty's detection outputs come in SOFA's order. The order matters beyond ties: it is the
/// order of a pair's contacts, hence of the sums of their forces on shared vertices (spec §4,
/// §7.1), and SOFA's trajectories are only reproduced to the last bit with it.
///
/// SOFA's tree (CubeCollisionModel::computeBoundingTree) is built once, at the model's first
/// detection, and afterwards only refitted (CubeCollisionModel::updateCubes): the root cell
/// holds every element; level by level down to `depth`, a cell with more than 4 elements is
/// split at its median (element index first + (n + 1) / 2) after a stable sort of its elements
/// by box centre (min + max) along the longest extent of the cell's box (ties: x only if
/// l.x > l.y and l.x > l.z, else y if l.y > l.z, else z). A cell that is not split keeps its
/// elements as its children.
///
/// BVHNarrowPhase (processInternalCell / visitCollisionElements / visitExternalChildren) visits
/// two child ranges element by element (first range outer, second inner): a pair of two
/// elements is intersected at once; any other pair of boxes (a cell against a cell or an
/// element) is pushed on a stack, and after the loop the pushed pairs are visited last pushed
/// first. Pruning by box overlap removes pairs but does not reorder the others, so the order of
/// the element pairs is a function of the two trees only: sofa_visits_before.
#include "penalty/collision/collision_model.hpp"
#include "penalty/collision/detection_output.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace penalty {

/// One step of an element's path from the root: its position in the child range it belongs
/// to, and the size of that range.
struct SofaTreeStep {
    std::uint32_t index = 0;
    std::uint32_t size = 1;
};

/// SOFA's bounding tree of one model, kept as each element's path from the root (its leaf cell
/// and its place there).
class SofaCubeTree {
public:
    /// Builds the tree from the model's element boxes at their current positions (SOFA's leaf
    /// cubes: the same boxes as CollisionModel::element_box). `depth`: the pipeline's `depth`.
    void build(const CollisionModel& model, int depth);
    [[nodiscard]] bool empty() const { return places_.empty(); }
    /// Elements it was built for.
    [[nodiscard]] std::size_t size() const { return places_.size(); }
    /// The path of an element from the root's children down to it, in two parts: the path of
    /// its leaf cell (the cells' split steps {s, 2}, shared by the cell's elements; few, so they
    /// stay in cache) and its last step {place in the cell, cell size}, read from 8 bytes per
    /// element.
    struct Path {
        std::span<const SofaTreeStep> cell;
        SofaTreeStep leaf;
        [[nodiscard]] std::size_t size() const { return cell.size() + 1; }
        [[nodiscard]] SofaTreeStep operator[](std::size_t t) const { return t < cell.size() ? cell[t] : leaf; }
    };
    [[nodiscard]] Path path(Index e) const {
        const Place p = places_[e];
        return {{cell_steps_.data() + cell_offsets_[p.cell], cell_steps_.data() + cell_offsets_[p.cell + 1]},
                {p.index, cell_sizes_[p.cell]}};
    }
    /// Where element e's place is stored: a caller that reads the paths of many elements in no
    /// memory order fetches it ahead (src/kernels/prefetch.hpp).
    [[nodiscard]] const void* place_address(Index e) const { return places_.data() + e; }
    /// The longest path (levels below the root).
    [[nodiscard]] std::size_t levels() const { return level_max_size_.size(); }
    /// The largest child range at level t (1 beyond the tree's levels: an element whose path
    /// has ended counts as the only child of itself).
    [[nodiscard]] std::uint32_t max_range(std::size_t t) const {
        return t < level_max_size_.size() ? level_max_size_[t] : 1;
    }

    /// sort_in_sofa_order's packed key of each element paired with the element of a
    /// one-element model (the tree's model first if `as_first`), the same for any one-element
    /// partner; computed at build. Empty if the keys do not fit in 64 bits.
    [[nodiscard]] std::span<const std::uint64_t> keys_against_one_element(bool as_first) const {
        return as_first ? key_as_first_ : key_as_second_;
    }

private:
    void compute_keys_against_one_element();

    struct Place {
        std::uint32_t cell = 0;   ///< leaf cell
        std::uint32_t index = 0;  ///< position in the cell
    };
    std::vector<Place> places_;                // per element
    std::vector<SofaTreeStep> cell_steps_;     // the leaf cells' paths, one after the other
    std::vector<std::uint32_t> cell_offsets_;  // leaf cell c's path: [offsets[c], offsets[c + 1])
    std::vector<std::uint32_t> cell_sizes_;    // elements per leaf cell
    std::vector<std::uint32_t> level_max_size_;
    std::vector<std::uint64_t> key_as_first_, key_as_second_;
};

/// True if BVHNarrowPhase, traversing t1 against t2, intersects (a1, b1) before (a2, b2)
/// (a = element of the first model, b = element of the second). A strict weak order.
[[nodiscard]] bool sofa_visits_before(const SofaCubeTree& t1, const SofaCubeTree& t2, Index a1, Index b1, Index a2,
                                      Index b2);

/// Buffers of sort_in_sofa_order, kept from call to call (a steady state allocates nothing).
struct SofaOrderScratch {
    struct Keyed {
        std::uint64_t key;
        std::uint32_t index;
    };
    std::vector<std::uint32_t> permutation;
    std::vector<Keyed> keyed;
    std::vector<Keyed> keyed_swap;          ///< the radix sort's second buffer
    std::vector<std::size_t> radix_counts;  ///< the radix sort's digit counts, every pass
    std::vector<std::uint64_t> level_span;  ///< per level: the number of loop positions
    std::vector<int> level_shift;           ///< per level: the bit position of its digit
    DetectionOutputList sorted;
    std::vector<std::uint64_t> sorted_keys;
};

/// Sorts a model pair's outputs into SOFA's visiting order; the outputs of one element pair
/// keep their kernel order. The order is sofa_visits_before's; when the two trees' digits fit
/// in 64 bits (always with SOFA's default depth and fewer than ~10⁸ elements), each output's
/// place is first packed into one integer key (one digit per level) and the keys are sorted.
void sort_in_sofa_order(const SofaCubeTree& t1, const SofaCubeTree& t2, DetectionOutputList& outputs,
                        SofaOrderScratch& scratch);

/// Sorts element pairs given as keys (PairKey(element 1, element 2).bits(), each pair once) into SOFA's
/// visiting order, as sort_in_sofa_order sorts outputs.
void sort_keys_in_sofa_order(const SofaCubeTree& t1, const SofaCubeTree& t2, std::span<std::uint64_t> keys,
                             SofaOrderScratch& scratch);

/// SOFA's bounding trees of a pipeline's models (CubeCollisionModel::computeBoundingTree): each
/// built at the model's first detection and only refitted after, so built again here only when
/// the model's size changed. They order each pair's outputs as SOFA's BVHNarrowPhase visits them.
class SofaOrderTrees {
public:
    /// `depth`: the pipeline's `depth`.
    explicit SofaOrderTrees(int depth = 6) : depth_(depth) {}
    /// Forgets the trees; `models` entries.
    void reset(std::size_t models) { trees_.assign(models, SofaCubeTree{}); }
    void add_model() { trees_.emplace_back(); }
    /// Builds the trees of the active, non-empty models that have none or an outdated one.
    void build_all(const std::vector<CollisionModel*>& models);
    /// Sorts the outputs of pair (models[i1], models[i2]) into SOFA's order.
    void sort_outputs(const std::vector<CollisionModel*>& models, std::size_t i1, std::size_t i2,
                      DetectionOutputList& outputs, SofaOrderScratch& scratch);
    /// Sorts the pair's candidate keys into SOFA's order.
    void sort_keys(const std::vector<CollisionModel*>& models, std::size_t i1, std::size_t i2,
                   std::span<std::uint64_t> keys, SofaOrderScratch& scratch);

private:
    void ensure(const std::vector<CollisionModel*>& models, std::size_t i1, std::size_t i2);
    int depth_;
    std::vector<SofaCubeTree> trees_;
};

}  // namespace penalty
