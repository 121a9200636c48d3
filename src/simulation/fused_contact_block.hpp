#pragma once
/// @file
/// The fused contact block of a subtree's products (private to the simulation stage).
///
/// A pile of bodies has thousands of contact pairs, each with two contact-point states, two
/// ContactPointMappings and a PenaltyInteraction, every one its own small heap object and
/// arrays: a product through them is one virtual call and a cache miss per object. The contact
/// fields whose states are each either the output of a barycentric contact mapping
/// (BaseMapping::contact_barycentric_rows) read by that field alone, or an external state (dx 0,
/// df scratch), are applied by the block under a FixedReaders: the mappings' rows are copied once
/// a solve into one array, their contact points' dx and df live in two flat arrays, each field's
/// add_dforce runs on those arrays right after the mappings' J (it reads and writes nothing else:
/// nothing else reads those contact points), and each mapping's Jᵀ runs at its own force step,
/// with the rows' combine and spread. Same operations on the same values in the same order: the
/// same bits.
/// A barycentric contact mapping whose contact points nobody in the subtree reads (a contact
/// between two bodies of this solver whose field lies above the solver's node: explicit, SOFA's
/// §2.1) is fused too: its dx is read by nobody, its df stays +0, and its Jᵀ adds only w·(+0) to
/// its parent's df rows. Adding a zero changes a sum only when the sum is −0 (it becomes +0 when
/// the zero is +0) or the zero is NaN (w not finite), whatever the place of that addition among
/// the others, so one addition of +0 (or NaN) per parent row it touches, before the other steps,
/// gives the same bits.
/// The springs of the fused contact fields on SOFA's path (no damping, no friction) are read by a
/// product from one flat list of the active ones (FusedSpring, made once a force evaluation),
/// not from each field's contact list: the same operations in the same order
/// (add_sofa_contact_dforce), 40 bytes read per active spring instead of a 216-byte
/// PenaltyContact per spring, active or not. A contact point no active spring (and no field of
/// its own product) reads has df +0 in every product, so its Jᵀ adds w·(+0): as for the unread
/// mappings, one addition of +0 (or NaN) per parent row, before the other steps, stands for it,
/// and J and Jᵀ run over the read points only (more than half of a pile's points are inactive).
/// A large field (a soft body on an organ: one field of thousands of springs) runs on TBB's
/// threads inside: its points' J, then its springs in ranges when each spring has its own
/// contact points (an external side's df to the task thread's scratch, which nobody reads); a
/// large mapping's Jᵀ gathers each parent row's terms in the rows' order (the same additions in
/// the same order per parent row), the parent rows on threads: the same bits.

#include "step_chains.hpp"
#include "subtree_layout.hpp"

#include "penalty/core/pointer_index.hpp"
#include "penalty/mechanics/mapping.hpp"
#include "penalty/response/penalty_force_field.hpp"

#include <tbb/enumerable_thread_specific.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace penalty::detail {

class FusedContactBlock {
public:
    /// Finds the fields and mappings of `layout` to fuse (none when !fuse) and marks the layout's
    /// steps that are fused (ForceStep::fused); what an earlier find() found is cleared first,
    /// the lists keeping their capacity.
    void find(SubtreeLayout& layout, bool fuse);
    [[nodiscard]] bool empty() const { return mappings_.empty(); }
    /// Fused fields, read fused mappings, unread fused mappings.
    [[nodiscard]] std::array<std::size_t, 3> counts() const;
    /// The rows must be copied again before the next fused product (a new FixedReaders).
    void invalidate() {
        ready_ = false;
        springs_ready_ = false;
    }
    /// The fields' forces were computed again (their active sets may have changed): the spring
    /// list is made again before the next fused product.
    void forces_computed() { springs_ready_ = false; }
    /// A fused product's start: the rows copied (once under a FixedReaders), the unread mappings'
    /// zeros added to their parents' df, J and each fused field's add_dforce(k, b). `parallel`:
    /// the fields as TBB tasks (each writes only its own contact points' df, and external df
    /// scratch, which then goes to a buffer of the task's thread: nobody reads it); the same bits.
    void begin_product(double k, double b, bool parallel);
    /// from.df += Jᵀ·df of fused mapping `index` (ForceStep::fused), row by row.
    void spread(std::size_t index) const;
    /// The layout's steps without the fused fields and the unread fused mappings (the read fused
    /// mappings' Jᵀ stay, at their places): what a fused product visits.
    [[nodiscard]] const std::vector<ForceStep>& steps() const { return steps_; }
    /// The layout's mappings the block does not apply (a fused product's J passes).
    [[nodiscard]] const std::vector<std::size_t>& unfused_mappings() const { return unfused_mappings_; }
    /// steps() and unfused_mappings() in chains (step_chains.hpp), made by find().
    [[nodiscard]] const StepChains& chains() const { return chains_; }
    [[nodiscard]] std::size_t field_count() const { return fields_.size(); }
    /// A field's springs, a mapping's read points or its Jᵀ's parent terms, or the zero additions
    /// run on TBB's threads from this many (and more than one thread in the calling arena), in
    /// tasks of kItemsPerTask.
    static constexpr std::size_t kMinItemsOnThreads = 4096;
    static constexpr std::size_t kItemsPerTask = 1024;
    /// How many fields' springs and mappings' Jᵀ run on threads (made by the last product's
    /// make_springs).
    [[nodiscard]] std::array<std::size_t, 2> on_threads() const;

private:
    /// Empties every list (keeping its capacity) and flag for a find() again.
    void clear();
    struct FusedMapping {
        std::size_t mapping_index = 0;  ///< in SubtreeLayout::mappings
        Vec3Object* from = nullptr;
        Vec3Object* to = nullptr;
        const std::vector<ContactBarycentricRow>* rows = nullptr;
        bool live = true;  ///< read by a fused field (false: read by nobody)
        /// Range of the mapping's contact points in rows_, dx_, df_ (this solve)
        std::size_t first = 0;
        std::size_t count = 0;
        /// Its points a product reads: read_rows_[first_read, first_read + read_count), each an
        /// index from `first` (made by make_springs)
        std::size_t first_read = 0;
        std::size_t read_count = 0;
        /// Its Jᵀ as gathers (make_springs, kMinItemsOnThreads terms or more): the parent rows
        /// gather_row_[first_gather, first_gather + gather_count), row j's terms
        /// gather_terms_[gather_first_[j], gather_first_[j + 1]) in the rows' order.
        bool gathered = false;
        std::size_t first_gather = 0;
        std::size_t gather_count = 0;
    };
    struct FusedSide {
        std::ptrdiff_t mapping = -1;    ///< index in mappings_, or -1: external state
        Vec3Object* state = nullptr;    ///< the external state (mapping == -1)
        std::size_t external_slot = 0;  ///< the external state's place among the block's (parallel scratch)
    };
    struct FusedField {
        Vec3InteractionForceField* field = nullptr;
        std::array<FusedSide, 2> sides{};
        const PenaltyForceField* penalty = nullptr;  ///< a contact field's springs, else nullptr
        /// Its active springs are springs_[first_spring, end_spring) (made by make_springs):
        /// a penalty field on SOFA's path whose contacts lie in its sides' sizes.
        bool flat_springs = false;
        std::size_t first_spring = 0;
        std::size_t end_spring = 0;
        /// Its points' J and its springs on TBB's threads (make_springs): flat springs,
        /// kMinItemsOnThreads or more, no contact point of a mapped side read by two.
        bool on_threads = false;
    };
    /// One active spring of a fused field: its contact points' rows in the field's two sides, its
    /// normal (side 1 toward side 2) and ks (N/m).
    struct FusedSpring {
        std::uint32_t m1 = 0;
        std::uint32_t m2 = 0;
        Vec3 normal = Vec3::Zero();
        double ks = 0.0;
    };
    struct ZeroAdd {
        Vec3* target = nullptr;
        double value = 0.0;
    };
    /// One term of a gathered Jᵀ: parent row += weight·df[point] (point: the mapping's row).
    struct GatherTerm {
        double weight = 0.0;
        std::uint32_t point = 0;
    };
    /// Copies the rows of the fused mappings (current under the FixedReaders), sizes the flat
    /// arrays and lists the unread mappings' zero additions.
    void prepare();
    /// springs_: the active springs of the fields on SOFA's path, field by field, in order; the
    /// points each live mapping's products read (read_rows_) and the zero additions of the others
    /// (unread_point_adds_).
    void make_springs();
    /// read_rows_ and unread_point_adds_ from the flags of point_read_ (one per row of rows_).
    void list_read_points();
    /// The gathers of mapping m's Jᵀ over its read points (a counting sort by parent row, stable).
    void make_gathers(FusedMapping& m);
    /// J and the zeroed df of mapping m at its read points [begin, end) (read_rows_ order).
    void map_read_points(const FusedMapping& m, std::size_t begin, std::size_t end);
    /// Field f's J, zeroed df and springs with its points and springs in ranges on TBB's threads
    /// (f.on_threads).
    void apply_field_on_threads(const FusedField& f, double k);
    /// The zero additions `adds` (each target once), on TBB's threads when many.
    static void add_zeros(const std::vector<ZeroAdd>& adds);
    /// J of the fused mappings, zeroed df, and fields [begin, end)'s add_dforce(k, b) (from
    /// springs_ for the fields that have them); an external
    /// side's df goes to `external_df[slot]` when given (grown to the state's size), else to the
    /// state's df.
    void apply_fields(std::size_t begin, std::size_t end, double k, double b,
                      std::vector<std::vector<Vec3>>* external_df);
    /// Fields a task of the parallel begin_product applies (a field is a few contacts' work).
    static constexpr std::size_t kFieldsPerTask = 16;
    void mark_steps(SubtreeLayout& layout, const std::vector<std::ptrdiff_t>& fused_mapping_of,
                    const PointerIndex<BaseForceField>& fused_field_of);

    std::vector<FusedMapping> mappings_;
    std::vector<FusedField> fields_;
    std::vector<ForceStep> steps_;
    std::vector<std::size_t> unfused_mappings_;
    /// The parents of the fused mappings nobody reads, each with those mappings (mappings_
    /// indices), and the additions their Jᵀ amounts to in this solve: value (+0 or NaN) added to
    /// the three components of *target.
    std::vector<std::pair<Vec3Object*, std::vector<std::size_t>>> unread_by_parent_;
    std::vector<ZeroAdd> zero_adds_;
    std::vector<std::uint8_t> zero_add_kind_;  ///< scratch: per parent DOF 0 none, 1 +0, 2 NaN
    std::vector<ContactBarycentricRow> rows_;
    std::vector<Vec3> dx_;
    std::vector<Vec3> df_;
    std::vector<FusedSpring> springs_;
    std::vector<std::uint32_t> read_rows_;
    std::vector<std::uint8_t> point_read_;  ///< make_springs' scratch: per row, read by a product
    /// The additions of +0 (or NaN) that stand for the Jᵀ of the points no product reads, one per
    /// parent row (made by make_springs).
    std::vector<ZeroAdd> unread_point_adds_;
    std::vector<std::uint32_t> gather_row_;    ///< the gathered mappings' parent rows
    std::vector<std::uint32_t> gather_first_;  ///< per parent row: its first term; one more at the end
    std::vector<GatherTerm> gather_terms_;
    std::vector<std::uint32_t> gather_cursor_;  ///< make_gathers' scratch: per parent row, 0 between calls
    std::size_t external_slots_ = 0;
    /// Per thread of the parallel begin_product: each external state's df scratch, by slot.
    tbb::enumerable_thread_specific<std::vector<std::vector<Vec3>>> external_scratch_;
    StepChains chains_;
    bool ready_ = false;          ///< rows_ copied under the current FixedReaders
    bool springs_ready_ = false;  ///< springs_ made since the fields' last force evaluation
};

}  // namespace penalty::detail
