#pragma once
/// @file
/// The mechanical system of one solver subtree (SubtreeSystem), the CG's system over it and the
/// cache that keeps it while the graph does not change. A SubtreeSystem is a const layout (the
/// states, components and order of one solve, src/simulation/subtree_layout.hpp, built when the
/// graph's structure changes), a scratch of per-product numbers and the fused contact block
/// (src/simulation/fused_contact_block.hpp).

#include "penalty/simulation/cg_linear_solver.hpp"
#include "penalty/simulation/node.hpp"
#include "penalty/simulation/solve_error.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace penalty {

namespace detail {
struct ForceStep;
struct StepChains;
struct SubtreeLayout;
struct SubtreeScratch;
struct DxReaders;
struct RowLists;
class FusedContactBlock;
}  // namespace detail

/// The independent and mapped states, masses, force fields, mappings and constraints of one
/// solver subtree, with flat-vector operations over its independent DOFs (concatenated in
/// depth-first order of their nodes).
class SubtreeSystem {
public:
    /// `mapping_graph_order`: compute_force and apply_mbk (the right-hand side's addMBKv and the
    /// CG's product) sum in the order of SOFA HEAD's MappingGraph instead of its visitors'
    /// (OdeSolver::sofa_mapping_graph_order; detail::order_as_mapping_graph).
    /// `fuse_contact_products`: apply_mbk under a FixedReaders runs the fused contact block;
    /// false: every product through the objects. The two give the same bits.
    /// std::invalid_argument for a mapping whose output is not its node's state and for a mass
    /// on a mapped state.
    explicit SubtreeSystem(Node& root, bool mapping_graph_order = false, bool fuse_contact_products = true);
    ~SubtreeSystem();
    SubtreeSystem(const SubtreeSystem&) = delete;
    SubtreeSystem& operator=(const SubtreeSystem&) = delete;
    /// A static outside state of fewer DOFs has its scratch cleared whole (clear_external_scratch):
    /// listing the rows of its contacts would cost more than the pass, 72 bytes a DOF.
    static constexpr std::size_t kMinDofsForScratchRows = 2048;
    /// Fewest force steps a product needs to run its chains on TBB's threads (step_chains.hpp).
    static constexpr std::size_t kMinStepsForConcurrentProducts = 256;
    /// The CG's vector passes (direction_and_mbk, update_and_residual, dot) run state by state on
    /// TBB's threads, each state's sum added in order after (the same bits), from this many
    /// unknowns in two states or more; a task takes kUnknownsPerStatePassTask unknowns or more.
    static constexpr Eigen::Index kMinUnknownsForConcurrentStatePasses = 8192;
    static constexpr Eigen::Index kUnknownsPerStatePassTask = 2048;
    [[nodiscard]] bool mapping_graph_order() const { return mapping_graph_order_; }
    [[nodiscard]] bool fuses_contact_products() const { return fuse_contact_products_; }
    /// Beyond SOFA (off by default): dot, direction_and_mbk and update_and_residual sum their dot
    /// products in fixed blocks of DOFs on TBB's threads (blocked_reductions.hpp): the same bits
    /// at any thread count, SOFA's when every state fits in one block.
    void set_blocked_reductions(bool on);
    [[nodiscard]] bool blocked_reductions() const { return blocked_reductions_; }
    /// What the fused contact block applies: contact force fields, the barycentric contact
    /// mappings they read, and the barycentric contact mappings nobody reads (all 0: none
    /// qualifies, or fusion is off); of those, as the last fused product found them, the fields
    /// whose springs ran on TBB's threads and the mappings whose Jᵀ ran as gathers on them
    /// (FusedContactBlock::kMinItemsOnThreads springs or read points and more than one thread).
    struct FusedContactCounts {
        std::size_t force_fields = 0;
        std::size_t read_mappings = 0;
        std::size_t unread_mappings = 0;
        std::size_t fields_on_threads = 0;
        std::size_t gathered_mappings = 0;
    };
    [[nodiscard]] FusedContactCounts fused_contact_counts() const;
    /// How many products so far ran their force steps in chains on TBB's threads
    /// (src/simulation/step_chains.hpp), and how many chains a product under a FixedReaders has.
    [[nodiscard]] std::size_t concurrent_products() const;
    [[nodiscard]] std::size_t product_chains() const;
    /// How many compute_force calls so far ran their force steps in the same chains.
    [[nodiscard]] std::size_t concurrent_force_evaluations() const;
    /// How many vector passes (dot, direction_and_mbk, update_and_residual) ran state by state on
    /// TBB's threads (kMinUnknownsForConcurrentStatePasses).
    [[nodiscard]] std::size_t concurrent_state_passes() const;

    [[nodiscard]] Eigen::Index size() const;
    /// True while every independent state has the size it had when the system was built (the
    /// offsets are still right).
    [[nodiscard]] bool offsets_valid() const;
    [[nodiscard]] const std::vector<BaseState*>& independent_states() const;
    [[nodiscard]] const std::vector<BaseMapping*>& mappings() const;
    [[nodiscard]] const std::vector<BaseForceField*>& force_fields() const;
    /// The masses (each with its node's gravity) and projective constraints, in visiting order, and
    /// the mapped states (mapped_states()[i] is mappings()[i]->to()): what an assembly reads.
    [[nodiscard]] const std::vector<std::pair<BaseMass*, Vec3>>& masses() const;
    [[nodiscard]] const std::vector<BaseProjectiveConstraint*>& constraints() const;
    [[nodiscard]] const std::vector<BaseState*>& mapped_states() const;
    /// Scalar offset of a state in the system, or size() for a state outside it.
    [[nodiscard]] Index offset(const BaseState* s) const;
    /// Appends the independent, mapped and external states to `out` (external: used by a force
    /// field or a mapping of the subtree but not part of it; the solve reads them, and writes
    /// their force and dx scratch), then those its force fields only read
    /// (BaseForceField::list_read_states).
    void append_states(std::vector<const BaseState*>& out) const;

    /// aᵀb summed as SOFA's VectorOperations::v_dot (MechanicalVDotVisitor over the independent
    /// states in visiting order, each MechanicalObject::vDot): per DOF d = Σ_c a_c·b_c left to right
    /// (Vec3: 3 components; Rigid3 deriv: 6, RigidDeriv::operator*), per state r = 0, r += d for
    /// each DOF in order, total = 0, total += r for each state in order.
    [[nodiscard]] double dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const;

    void gather_velocity(Eigen::VectorXd& v) const;
    void scatter_velocity(const Eigen::VectorXd& v) const;
    /// x <- x + h·v for every independent state.
    void add_to_positions(double h, const Eigen::VectorXd& v) const;
    /// Propagates positions and velocities to the mapped states (top-down).
    void propagate_positions_and_velocities() const;
    /// f = external forces + gravity + Σ force fields, mapped forces brought up by Jᵀ (in the
    /// products' chains on TBB's threads when they are worth tasks: the same bits).
    /// Throws NonFiniteSolveError naming the first non-finite contribution.
    void compute_force(Eigen::VectorXd& f) const;
    /// After an overflow in the solve with finite forces: evaluates each mass's gravity and each
    /// force field alone and throws NonFiniteSolveError(what + ...) naming the largest one.
    /// Leaves the states' force vectors overwritten (the step is abandoned).
    [[noreturn]] void throw_naming_largest_force(const std::string& what) const;
    /// out = (m·M + b·B + k·K)·dx (matrix-free, through the mappings), projected if asked.
    /// External states count as fixed: their dx is 0 and their df is scratch nobody reads; both
    /// are zeroed by the first product after compute_force (or the first ever), not by every one
    /// (nothing in the subtree writes an external dx, and the solvers do not interleave).
    /// accumulate: out += (m·M + b·B + k·K)·dx, each contribution added to out in turn (out must
    /// have size()); the projection, if asked, applies to the sum.
    void apply_mbk(const Eigen::VectorXd& dx, Eigen::VectorXd& out, double m, double b, double k, bool project,
                   bool accumulate = false) const;
    /// A CG iteration's direction and product in one pass over the vectors where apply_mbk and
    /// dot take three: p = r (first) or r + β·p, written into the states' dx as it is formed;
    /// q = (m·M + b·B + k·K)·p projected; returns dot(p, q), summed while q is copied out of the
    /// states when no constraint projects it. The bits of those calls one after the other. r
    /// and p are vectors apart.
    double direction_and_mbk(const Eigen::VectorXd& r, double beta, bool first, Eigen::VectorXd& p, Eigen::VectorXd& q,
                             double m, double b, double k) const;
    /// x += α·p, r −= α·q and returns dot(r, r), in one pass: the bits of the three apart.
    double update_and_residual(double alpha, const Eigen::VectorXd& p, const Eigen::VectorXd& q, Eigen::VectorXd& x,
                               Eigen::VectorXd& r) const;
    /// While one lives, the readers of the mapped states (the contacts' force fields and
    /// mappings) do not change: the rows of a mapped state that apply_mbk maps are found by the
    /// first product and kept for the next ones (a solve's right-hand side and CG products), and
    /// the fused contact block copies its rows once. Without one, each product finds them again
    /// and no product is fused. Not nested; the system outlives it.
    class FixedReaders {
    public:
        explicit FixedReaders(const SubtreeSystem& system);
        ~FixedReaders();
        FixedReaders(const FixedReaders&) = delete;
        FixedReaders& operator=(const FixedReaders&) = delete;

    private:
        const SubtreeSystem& system_;
    };
    /// Applies every projective constraint to a flat vector.
    void project(Eigen::VectorXd& v) const;
    /// out = M⁻¹·in (independent states; each must have a mass).
    void apply_inverse_mass(const Eigen::VectorXd& in, Eigen::VectorXd& out) const;
    /// Assembled m·M + k·K (Jᵀ K J for mapped states), constraints not applied.
    [[nodiscard]] SparseMatrix assemble(double m, double k) const;
    /// Σ potential energies of the force fields (J) plus gravity potential and kinetic energy.
    [[nodiscard]] double total_energy() const;

private:
    friend class SubtreeSystemCache;
    /// Builds the layout, scratch and fused block of the subtree of `root` again, in place (the
    /// lists keep their capacity); std::invalid_argument as the constructor.
    void build(Node& root, bool mapping_graph_order, bool fuse_contact_products);
    /// After a non-finite total force: evaluates the contributions again one at a time (external
    /// forces, each mass's gravity, each force field) and throws naming the first non-finite one.
    [[noreturn]] void throw_non_finite_force() const;
    /// Independent, mapped and external states, in that order (the diagnostics' walk).
    [[nodiscard]] std::vector<BaseState*> all_states() const;
    void reset_forces() const;
    /// apply_mbk's products, once the independent states hold dx and their df is set: external
    /// work vectors, mappings (J·dx), masses, force fields and Jᵀ, into the independent states' df.
    void apply_mbk_to_states(double m, double b, double k) const;
    /// Zeroes each external state's scratch, its force (`forces`) or its dx and df: the whole
    /// vectors, or, for a static state (BaseState::is_static) of kMinDofsForScratchRows DOFs or
    /// more whose readers all list their rows, only the rows its record names (the solves before
    /// may have written those); the rows read now become the record. The same values as whole
    /// vectors zeroed.
    void clear_external_scratch(bool forces) const;
    /// Lists into `listed` the DOFs of `state` that the force fields and mappings read
    /// (BaseForceField::list_dx_read, BaseMapping::list_inputs_read); false when one cannot tell.
    bool list_rows_read(const BaseState& state, const std::vector<const BaseForceField*>& force_fields,
                        const std::vector<const BaseMapping*>& mappings, std::vector<std::uint32_t>& listed) const;
    /// The rows mapping `index` maps in this product (the scratch's dx_rows[index]): those its
    /// readers read, when they can all tell; `lists` is the calling thread's scratch.
    void find_read_rows(std::size_t index, detail::RowLists& lists) const;
    /// to.dx = J from.dx for mapping `index`, only the rows its readers read when they can tell.
    void map_dx(std::size_t index, detail::RowLists& lists) const;
    /// Zeroes the df of mapping `index`'s output (the rows its readers read, when known).
    void zero_mapped_df(std::size_t index) const;
    /// One force step of a product: a mass's m·M·dx, a field's k·K·dx + b·B·dx, a mapping's Jᵀ,
    /// or (fused) a fused mapping's spread.
    void apply_step(const detail::ForceStep& step, double m, double b, double k, bool fused) const;
    /// Whether a product's chains go to TBB's threads: two chains or more, at least
    /// kMinStepsForConcurrentProducts steps, none with more than half of them, and more than one
    /// thread in the calling arena.
    [[nodiscard]] bool chains_worth_tasks(const detail::StepChains& chains, std::size_t steps) const;

    std::unique_ptr<detail::SubtreeLayout> layout_;     ///< made by build(), then only read
    std::unique_ptr<detail::SubtreeScratch> scratch_;   ///< the products' numbers from call to call
    std::unique_ptr<detail::FusedContactBlock> fused_;  ///< the contact products on flat arrays
    bool mapping_graph_order_ = false;
    bool fuse_contact_products_ = true;
    bool blocked_reductions_ = false;
};

/// The CG's system of a subtree, A = m·M + b·B + k·K projected (SubtreeSystem::apply_mbk), with
/// the system's fused passes (direction_and_mbk, update_and_residual). The system outlives it.
class MbkCgSystem final : public CgSystem {
public:
    MbkCgSystem(const SubtreeSystem& system, double m, double b, double k) : system_(system), m_(m), b_(b), k_(k) {}
    /// The factors of A = m·M + b·B + k·K.
    [[nodiscard]] double m() const { return m_; }
    [[nodiscard]] double b() const { return b_; }
    [[nodiscard]] double k() const { return k_; }
    void apply(const Eigen::VectorXd& p, Eigen::VectorXd& q) override;
    [[nodiscard]] double dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const override;
    double direction_and_product(const Eigen::VectorXd& r, double beta, bool first, Eigen::VectorXd& p,
                                 Eigen::VectorXd& q) override;
    double update_and_residual(double alpha, const Eigen::VectorXd& p, const Eigen::VectorXd& q, Eigen::VectorXd& x,
                               Eigen::VectorXd& r) override;

private:
    const SubtreeSystem& system_;
    double m_, b_, k_;
};

/// The SubtreeSystem of one solver node, built at the first use and built again only when the
/// graph changed (Node::structure_version: a contact pipeline adding or removing a pair's
/// force field and contact-point nodes, a component added or removed), the node is another
/// one, or an independent state was resized. In steady state a solve reuses it as is.
class SubtreeSystemCache {
public:
    [[nodiscard]] SubtreeSystem& get(Node& node, bool mapping_graph_order = false, bool fuse_contact_products = true);
    /// Number of builds so far.
    [[nodiscard]] int builds() const { return builds_; }
    /// The system of the last get(), or nullptr before the first.
    [[nodiscard]] const SubtreeSystem* current() const { return system_ ? &*system_ : nullptr; }

private:
    std::optional<SubtreeSystem> system_;
    const Node* node_ = nullptr;
    std::uint64_t version_ = 0;
    int builds_ = 0;
};

}  // namespace penalty
