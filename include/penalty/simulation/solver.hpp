#pragma once
/// @file
/// ODE and linear solvers (spec §10.2, §10.3): EulerImplicitSolver with SOFA's matrix-free
/// CGLinearSolver, EulerExplicitSolver (symplectic), and the mechanical system of one solver
/// subtree (SubtreeSystem) they work on.

#include "penalty/core/pointer_index.hpp"
#include "penalty/simulation/node.hpp"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <optional>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

namespace penalty {

/// A non-finite value in a solve (forces, right-hand side or CG solution): the run diverged, or a
/// parameter makes a product overflow. Names what produced it where the solver can tell: the
/// first force field whose contribution is not finite (nullptr: unknown, or the gravity force of
/// a mass, see `mass`), and the state where it shows.
class NonFiniteSolveError : public std::runtime_error {
public:
    NonFiniteSolveError(const std::string& what, const BaseForceField* force_field, const BaseMass* mass,
                        const BaseState* state)
        : std::runtime_error(what), force_field_(force_field), mass_(mass), state_(state) {}
    [[nodiscard]] const BaseForceField* force_field() const { return force_field_; }
    [[nodiscard]] const BaseMass* mass() const { return mass_; }
    [[nodiscard]] const BaseState* state() const { return state_; }

private:
    const BaseForceField* force_field_;
    const BaseMass* mass_;
    const BaseState* state_;
};

/// Why a CG solve stopped (SOFA's CGLinearSolver end conditions).
enum class CgEndCondition : std::uint8_t {
    none,        ///< no solve yet
    iterations,  ///< the iteration limit was reached
    tolerance,   ///< |r|/|b| <= tolerance
    threshold,   ///< |pᵀAp| <= threshold
    den_zero,    ///< pᵀAp == 0
    b_zero,      ///< |b| == 0 (x = 0, no iteration)
};

/// The name printed for an end condition: "none", "iterations", "tolerance", "threshold",
/// "den=0", "b=0" (SOFA's log words).
[[nodiscard]] std::string_view cg_end_condition_name(CgEndCondition condition);
/// Writes cg_end_condition_name(condition).
std::ostream& operator<<(std::ostream& out, CgEndCondition condition);

/// Result of one CG solve.
struct CgStats {
    int iterations = 0;                                ///< iterations started (SOFA's nb_iter)
    CgEndCondition end_condition = CgEndCondition::none;
    double error = 0.0;                                ///< last |r|/|b| evaluated
};

/// A linear system A·x = b for CGLinearSolver: its product, its dot product, and the two vector
/// steps of a CG iteration, which a system may run as one pass over its vectors each. An
/// override must give the defaults' bits: the same IEEE operations on the same operands, each
/// sum in the same order.
class CgSystem {
public:
    virtual ~CgSystem() = default;
    /// q = A·p.
    virtual void apply(const Eigen::VectorXd& p, Eigen::VectorXd& q) = 0;
    /// aᵀb in the system's order of summation.
    [[nodiscard]] virtual double dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const = 0;
    /// The new direction and its product: p = r (first) or p = r + β·p, then q = A·p; returns pᵀq.
    virtual double direction_and_product(const Eigen::VectorXd& r, double beta, bool first, Eigen::VectorXd& p,
                                         Eigen::VectorXd& q);
    /// The update: x += α·p, r −= α·q; returns rᵀr.
    virtual double update_and_residual(double alpha, const Eigen::VectorXd& p, const Eigen::VectorXd& q,
                                       Eigen::VectorXd& x, Eigen::VectorXd& r);
};

/// SOFA's CGLinearSolver (GraphScattered, matrix-free), exact stopping rules: x₀ = 0, r = b; for
/// k = 1..iterations: ρ = r·r, err = √ρ/|b|; stop if err <= tolerance; p = r (k = 1) or
/// r + (ρ/ρ_prev) p; q = A p; den = p·q; stop if den == 0; stop if |den| <= threshold; x += α p,
/// r −= α q with α = ρ/den. The two "stop" tests at k = 1 are skipped (SOFA only warns) during the
/// very first solve of this instance. If |b| = 0, x = 0.
class CGLinearSolver {
public:
    using Operator = std::function<void(const Eigen::VectorXd& p, Eigen::VectorXd& q)>;
    /// Dot product of two flat vectors. SOFA sums in a fixed order (SubtreeSystem::dot); the
    /// rounding of ρ, pᵀq and |b| depends on it, so the solve uses the system's order.
    using Dot = std::function<double(const Eigen::VectorXd& a, const Eigen::VectorXd& b)>;
    int iterations = 25;
    double tolerance = 1e-5;
    double threshold = 1e-5;

    /// Validates the parameters (std::invalid_argument on iterations < 1 or negative/NaN values).
    void check() const;
    /// `dot` empty: the plain sequential sum Σ aᵢbᵢ.
    CgStats solve(const Operator& a, const Eigen::VectorXd& b, Eigen::VectorXd& x, const Dot& dot = {});
    /// The same iterations on `system`, through its fused steps (the same bits as its product and
    /// dot applied one after the other).
    CgStats solve(CgSystem& system, const Eigen::VectorXd& b, Eigen::VectorXd& x);
    [[nodiscard]] int solve_count() const { return solve_count_; }

private:
    int solve_count_ = 0;
    Eigen::VectorXd r_, p_, q_;  ///< residual, direction, A·p (kept: no allocation per solve)
};

/// The independent and mapped states, masses, force fields, mappings and constraints of one
/// solver subtree, with flat-vector operations over its independent DOFs (concatenated in
/// depth-first order of their nodes).
class SubtreeSystem {
public:
    /// `mapping_graph_order`: compute_force and apply_mbk (the right-hand side's addMBKv and the
    /// CG's product) sum in the order of SOFA HEAD's MappingGraph (graph_force_steps_) instead of
    /// its visitors' (OdeSolver::sofa_mapping_graph_order).
    /// `fuse_contact_products`: apply_mbk under a FixedReaders runs the fused contact block
    /// (below); false: every product through the objects. The two give the same bits.
    explicit SubtreeSystem(Node& root, bool mapping_graph_order = false, bool fuse_contact_products = true);
    /// A static outside state of fewer DOFs has its scratch cleared whole (clear_external_scratch):
    /// listing the rows of its contacts would cost more than the pass, 72 bytes a DOF. Measured:
    /// CompositeCollisionPipeline's 800-point torus with ~700 contacts on it ran 6 % slower with
    /// the rows cleared; SphereModel's 2 520-sphere floor with ~15 contacts, 1.5 % faster.
    static constexpr std::size_t kMinDofsForScratchRows = 2048;
    [[nodiscard]] bool mapping_graph_order() const { return mapping_graph_order_; }
    [[nodiscard]] bool fuses_contact_products() const { return fuse_contact_products_; }
    /// What the fused contact block (below) applies: contact force fields, the barycentric contact
    /// mappings they read, and the barycentric contact mappings nobody reads (all 0: none
    /// qualifies, or fusion is off).
    struct FusedContactCounts {
        std::size_t force_fields = 0;
        std::size_t read_mappings = 0;
        std::size_t unread_mappings = 0;
    };
    [[nodiscard]] FusedContactCounts fused_contact_counts() const;

    [[nodiscard]] Eigen::Index size() const { return size_; }
    /// True while every independent state has the size it had when the system was built (the
    /// offsets are still right).
    [[nodiscard]] bool offsets_valid() const;
    [[nodiscard]] const std::vector<BaseState*>& independent_states() const { return independent_; }
    [[nodiscard]] const std::vector<BaseMapping*>& mappings() const { return mappings_; }
    [[nodiscard]] const std::vector<BaseForceField*>& force_fields() const { return force_fields_; }
    /// Scalar offset of a state in the system, or size() for a state outside it.
    [[nodiscard]] Index offset(const BaseState* s) const;
    /// Appends the independent, mapped and external states to `out` (external: used by a force
    /// field or a mapping of the subtree but not part of it; the solve reads them, and writes
    /// their force and dx scratch).
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
    /// f = external forces + gravity + Σ force fields, mapped forces brought up by Jᵀ.
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
    /// mappings, DxReaders) do not change: the rows of a mapped state that apply_mbk maps are
    /// found by the first product and kept for the next ones (a solve's right-hand side and CG
    /// products). Without one, each product finds them again. Not nested; the system outlives it.
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
    /// After a non-finite total force: evaluates the contributions again one at a time (external
    /// forces, each mass's gravity, each force field) and throws naming the first non-finite one.
    [[noreturn]] void throw_non_finite_force() const;
    /// Independent, mapped and external states, in that order (the diagnostics' walk).
    [[nodiscard]] std::vector<BaseState*> all_states() const;
    void reset_forces() const;
    /// apply_mbk's products, once the independent states hold dx and their df is set: external
    /// work vectors, mappings (J·dx), masses, force fields and Jᵀ, into the independent states' df.
    void apply_mbk_to_states(double m, double b, double k) const;
    void collect(Node& node, bool is_root);
    std::vector<BaseState*> independent_;
    std::vector<Index> offsets_;
    /// Per independent state: its scalar_size() and deriv_size() when the system was built (the
    /// CG's passes read them for every state and iteration; offsets_valid() rebuilds the system
    /// when a size changes).
    std::vector<Index> sizes_;
    std::vector<Index> widths_;
    std::unordered_map<const BaseState*, Index> offset_of_;
    std::vector<BaseState*> mapped_;
    std::vector<BaseState*> external_;  ///< states used by the subtree's fields but outside it
    /// external_'s dx (and df) zeroed since the last compute_force (see apply_mbk)
    mutable bool external_work_zeroed_ = false;
    /// Per external_ entry: the subtree's force fields acting on it and mappings reading it.
    struct ExternalReaders {
        std::vector<const BaseForceField*> force_fields;
        std::vector<const BaseMapping*> mappings;
    };
    std::vector<ExternalReaders> external_readers_;
    /// Zeroes each external state's scratch, its force (`forces`) or its dx and df: the whole
    /// vectors, or, for a static state (BaseState::is_static) of kMinDofsForScratchRows DOFs or
    /// more whose readers all list their rows, only the rows its record names (the solves before
    /// may have written those); the rows read now become the record. The same values as whole
    /// vectors zeroed.
    void clear_external_scratch(bool forces) const;
    /// Lists into listed_rows_ the DOFs of `state` that the force fields and mappings read
    /// (BaseForceField::list_dx_read, BaseMapping::list_inputs_read); false when one cannot tell.
    bool list_rows_read(const BaseState& state, const std::vector<const BaseForceField*>& force_fields,
                        const std::vector<const BaseMapping*>& mappings) const;
    mutable std::vector<std::uint32_t> listed_rows_;  ///< scratch of list_rows_read
    std::vector<BaseMapping*> mappings_;  ///< pre-order: parents before children (J·dx)
    // ---- the fused contact block ----------------------------------------------------------
    // A pile of bodies has thousands of contact pairs, each with two contact-point states, two
    // ContactPointMappings and a PenaltyInteraction, every one its own small heap object and
    // arrays: a product through them is one virtual call and a cache miss per object. The
    // contact fields whose states are each either the output of a barycentric contact mapping
    // (BaseMapping::contact_barycentric_rows) read by that field alone, or an external state
    // (dx 0, df scratch), are applied by apply_mbk itself under a FixedReaders: the mappings'
    // rows are copied once a solve into one array, their contact points' dx and df live in two
    // flat arrays, each field's add_dforce runs on those arrays right after the mappings' J
    // (it reads and writes nothing else: nothing else reads those contact points), and each
    // mapping's Jᵀ runs at its own force step, with the rows' combine and spread. Same
    // operations on the same values in the same order: the same bits.
    // A barycentric contact mapping whose contact points nobody in the subtree reads (a contact
    // between two bodies of this solver whose field lies above the solver's node: explicit,
    // SOFA's §2.1) is fused too: its dx is read by nobody, its df stays +0, and its Jᵀ adds only
    // w·(+0) to its parent's df rows. Adding a zero changes a sum only when the sum is −0 (it
    // becomes +0 when the zero is +0) or the zero is NaN (w not finite), whatever the place of
    // that addition among the others, so one addition of +0 (or NaN) per parent row it touches,
    // before the other steps, gives the same bits (zero_adds_).
    struct FusedMapping {
        std::size_t mapping_index = 0;  ///< in mappings_
        Vec3Object* from = nullptr;
        Vec3Object* to = nullptr;
        const std::vector<ContactBarycentricRow>* rows = nullptr;
        bool live = true;  ///< read by a fused field (false: read by nobody)
        /// Range of the mapping's contact points in fused_rows_, fused_dx_, fused_df_ (this solve)
        mutable std::size_t first = 0;
        mutable std::size_t count = 0;
    };
    struct FusedSide {
        std::ptrdiff_t mapping = -1;   ///< index in fused_mappings_, or -1: external state
        Vec3Object* state = nullptr;   ///< the external state (mapping == -1)
    };
    struct FusedField {
        Vec3InteractionForceField* field = nullptr;
        std::array<FusedSide, 2> sides{};
    };
    void find_fused_contacts(bool fuse);
    /// Copies the rows of the fused mappings (current under the FixedReaders) and sizes the flat
    /// arrays.
    void prepare_fused_contacts() const;
    /// J of the fused mappings, zeroed df, and each fused field's add_dforce(k, b).
    void apply_fused_fields(double k, double b) const;
    /// from.df += Jᵀ·df of one fused mapping, row by row.
    void spread_fused_mapping(const FusedMapping& m) const;
    bool fuse_contact_products_ = true;
    std::vector<FusedMapping> fused_mappings_;
    std::vector<FusedField> fused_fields_;
    std::vector<std::ptrdiff_t> fused_mapping_of_;  ///< per mappings_ entry: index in fused_mappings_ or -1
    mutable std::vector<ContactBarycentricRow> fused_rows_;
    mutable std::vector<Vec3> fused_dx_;
    mutable std::vector<Vec3> fused_df_;
    mutable bool fused_ready_ = false;  ///< fused_rows_ copied under the current FixedReaders
    /// What a product visits: every mappings_ index (all_mappings_), or under fusion those not
    /// fused (and fused_steps_, below).
    std::vector<std::size_t> all_mappings_;
    std::vector<std::size_t> unfused_mappings_;
    /// The parents of the fused mappings nobody reads, each with those mappings (fused_mappings_
    /// indices), and the additions their Jᵀ amounts to in this solve: value (+0 or NaN) added to
    /// the three components of *target.
    std::vector<std::pair<Vec3Object*, std::vector<std::size_t>>> unread_by_parent_;
    struct ZeroAdd {
        Vec3* target = nullptr;
        double value = 0.0;
    };
    mutable std::vector<ZeroAdd> zero_adds_;
    mutable std::vector<std::uint8_t> zero_add_kind_;  ///< scratch: per parent DOF 0 none, 1 +0, 2 NaN

    /// One contribution to the forces, in SOFA's visiting order (MechanicalComputeForceVisitor,
    /// MechanicalAddMBKdxVisitor): top-down a node's mass, then its force fields; bottom-up
    /// (post-order, siblings in child order) a mapped node's Jᵀ into its parent.
    struct ForceStep {
        BaseMass* mass = nullptr;  ///< with `gravity`; or
        BaseForceField* force_field = nullptr;  ///< or
        BaseMapping* mapping = nullptr;
        std::size_t mapping_index = 0;  ///< of `mapping` in mappings_
        /// Index of `force_field` in fused_fields_ or of `mapping` in fused_mappings_; -1: not fused
        std::ptrdiff_t fused = -1;
        Vec3 gravity = Vec3::Zero();
        /// The one component this step calls.
        [[nodiscard]] const void* object() const {
            return mass != nullptr ? static_cast<const void*>(mass)
                                   : force_field != nullptr ? static_cast<const void*>(force_field)
                                                            : static_cast<const void*>(mapping);
        }
    };
    /// How many objects ahead apply_mbk's loops prefetch the next objects' first words.
    static constexpr std::size_t kObjectsAhead = 8;
    std::vector<ForceStep> force_steps_;
    /// The force steps of the system's order without the fused fields and the unread fused
    /// mappings (the read fused mappings' Jᵀ stay, at their places): what a fused product visits.
    std::vector<ForceStep> fused_steps_;
    /// Who reads a mapped state's dx in this subtree (force fields acting on it, mappings from
    /// it). When its mapping can map selected rows (BaseMapping::maps_selected_rows) and every
    /// reader can tell which DOFs it reads (and so writes in df), apply_mbk maps dx only in those
    /// rows, zeroes df only there and takes Jᵀ over them: the other rows' dx is read by nobody,
    /// their df would be +0, and the rows kept get the same operations (same bits).
    struct DxReaders {
        BaseMapping* mapping = nullptr;
        bool selective = false;  ///< mapping->maps_selected_rows()
        std::vector<const BaseForceField*> force_fields;
        std::vector<const BaseMapping*> mappings;
        /// This product: restricted to `rows` (ascending), or (false) every row.
        mutable bool restricted = false;
        mutable std::vector<std::uint32_t> rows;
        /// `restricted` and `rows` were found under the current FixedReaders.
        mutable bool found = false;
    };
    std::vector<DxReaders> dx_readers_;  ///< one per mappings_ (and mapped_) entry, same order
    mutable std::vector<std::uint8_t> dx_read_;  ///< scratch of map_dx: one flag per DOF
    mutable bool readers_fixed_ = false;         ///< a FixedReaders lives
    /// Sets r.restricted and r.rows: the rows r's readers read, when they can all tell.
    void find_read_rows(const DxReaders& r) const;
    /// to.dx = J from.dx for r.mapping, only the rows its readers read when they can tell.
    void map_dx(const DxReaders& r) const;
    /// The same contributions in the order of SOFA's MappingGraph, which computeForce and addMBKv
    /// use (EulerImplicitSolver::solve → MappingGraphMechanicalOperations): force fields and
    /// masses by component group (one group per distinct list of states acted on, groups in order
    /// of first appearance, members in visiting order), then every mapping's Jᵀ in the reverse of
    /// the graph's breadth-first order (MappingGraphAlgorithms::traverseBottomUp: siblings last
    /// first). The CG's product uses it too: measured, not read in SOFA's code, whose
    /// GraphScatteredMatrix::apply calls MechanicalOperations::addMBKdx (visitors); with the
    /// visitors' order for the product, AdvancedSolversMultipleGroupsSolver parts from SOFA at
    /// step 20, with this order it is bit for bit over 300 steps (docs/sofa-compatibility.md).
    std::vector<ForceStep> graph_force_steps_;
    void order_as_mapping_graph(Node& root);
    bool mapping_graph_order_ = false;
    std::vector<std::pair<BaseMass*, Vec3>> masses_;  ///< with the gravity of their node
    std::vector<BaseForceField*> force_fields_;
    std::vector<BaseProjectiveConstraint*> constraints_;
    Eigen::Index size_ = 0;
};

/// The CG's system of a subtree, A = m·M + b·B + k·K projected (SubtreeSystem::apply_mbk), with
/// the system's fused passes (direction_and_mbk, update_and_residual). The system outlives it.
class MbkCgSystem final : public CgSystem {
public:
    MbkCgSystem(const SubtreeSystem& system, double m, double b, double k) : system_(system), m_(m), b_(b), k_(k) {}
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

/// An ODE solver integrates the subtree of the node that owns it over one time step.
class OdeSolver {
public:
    virtual ~OdeSolver() = default;
    virtual void init(Node& /*node*/) {}
    virtual void solve(Node& node, double dt) = 0;
    /// Appends to `out` every state solve(node, dt) reads or writes (its subtree's states and the
    /// outside ones its force fields and mappings use, SubtreeSystem::append_states) and
    /// returns the number of scalar unknowns of its system (a measure of its work); nullopt when
    /// the solver cannot tell. Simulation::step runs solvers next to each other in the plan
    /// whose lists do not meet concurrently: each then gives the bits it gives alone.
    [[nodiscard]] virtual std::optional<std::size_t> list_touched_states(Node& /*node*/,
                                                                         std::vector<const BaseState*>& /*out*/) {
        return std::nullopt;
    }
    /// True while the solve does more than touch its listed states and must run alone, in plan
    /// order (EulerImplicitSolver: Newton, whose geometry update runs the detection between
    /// iterates). Read at every step, so it may change without a graph change.
    [[nodiscard]] virtual bool runs_in_plan_order() const { return false; }
    /// Sum the forces of computeForce, of the right-hand side's addMBKv and of the CG's products
    /// in the order of SOFA HEAD's MappingGraph (MappingGraphMechanicalOperations: force fields
    /// by component group, then the mappings' Jᵀ in reversed breadth-first order) instead of the
    /// visitors' order (off by default: docs/sofa-compatibility.md, "SOFA HEAD's orders").
    bool sofa_mapping_graph_order = false;
    /// Apply the contact fields of many small contact-point states in one pass over flat arrays
    /// (SubtreeSystem's fused contact block). The same bits either way; off: every product
    /// through the objects (tests compare the two).
    bool fuse_contact_products = true;
};

/// Beyond SOFA (opt-in): Newton iterations on the backward-Euler residual
/// R(Δv) = M Δv − h f(x_n + h (v_n + Δv), v_n + Δv), each iteration re-running `update_geometry`
/// (e.g. contact detection) at the current iterate before the forces are evaluated.
struct NewtonOptions {
    bool enabled = false;
    int max_iterations = 10;
    double tolerance = 1e-10;               ///< on |R| / max(1, |R₀|)
    std::function<void()> update_geometry;  ///< called at each iterate (positions already updated)
};

/// SOFA's EulerImplicitSolver (spec §10.2). With h = dt, tr = ½ (trapezoidal) or 1:
///   b = h (f + (h·tr + rs) K v − rm M v)  (firstOrder: b = f), projected;
///   A = (1 + tr h rm) M − tr h B − tr h (tr h + rs) K  (firstOrder: M − h tr K);
///   A Δv = b by CG; v ← v + Δv (firstOrder: v ← Δv); x ← x + h v; v ← v·exp(−h·vdamping).
class EulerImplicitSolver final : public OdeSolver {
public:
    double rayleigh_stiffness = 0.0;
    double rayleigh_mass = 0.0;
    double vdamping = 0.0;
    bool first_order = false;
    bool trapezoidal_scheme = false;
    CGLinearSolver cg;
    NewtonOptions newton;

    void init(Node& node) override;
    void solve(Node& node, double dt) override;
    [[nodiscard]] std::optional<std::size_t> list_touched_states(Node& node, std::vector<const BaseState*>& out) override;
    [[nodiscard]] bool runs_in_plan_order() const override { return newton.enabled; }
    [[nodiscard]] const CgStats& last_cg_stats() const { return last_cg_; }
    /// Every linear solve of the last solve() in order (one, or one per Newton iterate).
    [[nodiscard]] const std::vector<CgStats>& last_step_cg_solves() const { return step_cg_solves_; }
    /// CG iterations of the last solve() in all (one linear solve, or one per Newton iterate).
    [[nodiscard]] int last_step_cg_iterations() const { return step_cg_iterations_; }
    /// True if a linear solve of the last solve() stopped on its iteration limit.
    [[nodiscard]] bool last_step_cg_limit_reached() const { return step_cg_limit_reached_; }
    /// Newton (newton.enabled): residual evaluations of the last solve (iterates 0..n−1; the
    /// last one either met the tolerance or was followed by the max_iterations-th update).
    [[nodiscard]] int last_newton_iterations() const { return last_newton_iterations_; }
    /// |R| / max(1, |R₀|) at the last evaluated iterate of the last solve.
    [[nodiscard]] double last_newton_residual() const { return last_newton_residual_; }
    /// True if the last solve stopped on the tolerance (false: max_iterations reached).
    [[nodiscard]] bool last_newton_converged() const { return last_newton_converged_; }
    /// The cached system of the solver's subtree (builds() counts its rebuilds).
    [[nodiscard]] const SubtreeSystemCache& system_cache() const { return system_; }

private:
    void solve_newton(SubtreeSystem& system, double dt);
    SubtreeSystemCache system_;
    Eigen::VectorXd f_, v_, b_, x_;  ///< force, velocity, right-hand side, CG solution (kept)
    CgStats last_cg_;
    void record_cg(const CgStats& stats);
    int step_cg_iterations_ = 0;
    std::vector<CgStats> step_cg_solves_;
    bool step_cg_limit_reached_ = false;
    int last_newton_iterations_ = 0;
    double last_newton_residual_ = 0.0;
    bool last_newton_converged_ = false;
};

/// SOFA's EulerExplicitSolver, symplectic: a = M⁻¹ f (projected), v ← v + h a, x ← x + h v.
class EulerExplicitSolver final : public OdeSolver {
public:
    /// Checks that every independent state of the subtree has a mass (a = M⁻¹ f needs one);
    /// std::invalid_argument naming the state otherwise.
    void init(Node& node) override;
    void solve(Node& node, double dt) override;
    [[nodiscard]] std::optional<std::size_t> list_touched_states(Node& node, std::vector<const BaseState*>& out) override;

private:
    SubtreeSystemCache system_;
    Eigen::VectorXd f_, a_, v_;  ///< force, acceleration, velocity (kept)
};

/// Most threads a Simulation (and a ContactPipeline's detection) accepts: 1024 (TBB cannot make
/// an arena above 65,536 and reserves memory per slot; no machine this runs on has more cores).
inline constexpr int kMaxThreads = 1024;

/// Fewest scalar unknowns a solver needs for Simulation::step to give it its own task: waking a
/// TBB worker costs a few µs, more than a step of CompositeCollisionPipeline's two 6-unknown rigid
/// solvers (their solve took 30 % longer on two threads), while RegularGridSpringForceField's four
/// 180-unknown grids solve 1.4× faster (docs/performance.md, "Independent solvers in parallel").
inline constexpr std::size_t kMinUnknownsPerConcurrentSolve = 96;

/// DefaultAnimationLoop (spec §2): owns the root node.
class Simulation {
public:
    Simulation();
    ~Simulation();
    Simulation(const Simulation&) = delete;
    Simulation& operator=(const Simulation&) = delete;
    [[nodiscard]] Node& root() { return root_; }
    /// Initialises every state, mapping, mass, force field, constraint and solver (top-down).
    void init();
    /// One step: collision hook (positions of the end of the previous step) → explicit interaction
    /// force fields of nodes without solver → solver subtrees → project velocities, propagate to
    /// mapped states → clear external forces → time += dt.
    void step();
    [[nodiscard]] double time() const { return time_; }
    /// Threads of the solve phase (0: TBB's default, the default; 1: every action in plan order
    /// on the calling thread): solvers next to each other in the plan whose states do not meet
    /// (OdeSolver::list_touched_states) run concurrently, one task per solver, when two of them
    /// have at least kMinUnknownsPerConcurrentSolve unknowns. The results are
    /// the same bits for any count (each solve is sequential inside and reads nothing another
    /// writes), and an error is the one the first failing solver in plan order raised.
    /// std::invalid_argument outside [0, kMaxThreads].
    void set_threads(int threads);
    [[nodiscard]] int threads() const { return threads_; }
    /// The runs of solvers that step() gives a task each when it has more than one thread, from
    /// the current graph: each the solver nodes of one run, in plan order.
    [[nodiscard]] std::vector<std::vector<const Node*>> concurrent_solver_runs();
    /// Called at the start of each step (collision detection + response).
    std::function<void(Simulation&)> collision_hook;

private:
    /// One entry of a step's solve phase, in depth-first order: a solver node (integrates its
    /// subtree) or an explicit force field with its states.
    struct SolveAction {
        Node* solver_node = nullptr;
        BaseForceField* explicit_field = nullptr;
        ForceFieldStates states;  ///< of explicit_field
        /// The action after this one's run: a run is the solver actions from this one whose
        /// touched states do not meet (one action when this one cannot run with others), found
        /// with the plan; set on the first action of each run.
        std::size_t run_end = 0;
        bool run_worth_tasks = false;  ///< two solvers of the run have kMinUnknownsPerConcurrentSolve unknowns
    };
    /// plan[begin] starts a run worth tasks and none of its solvers runs_in_plan_order now.
    [[nodiscard]] bool run_concurrently(const std::vector<SolveAction>& plan, std::size_t begin) const;
    /// The solve phase's actions and their runs, rebuilt when the graph's structure changes
    /// (which is also all that changes the states a solver touches).
    const std::vector<SolveAction>& solve_plan();
    void plan_node(Node& node);
    /// Simulation::init's projection of positions and velocities (see solver.cpp).
    static void project_initial_state(Node& node, bool moved_above);
    void run_action(const SolveAction& action, double dt);
    /// Sets plan_[begin].run_end and run_worth_tasks.
    void find_run(std::size_t begin);
    /// plan[begin, end): solver actions whose touched states do not meet, concurrently.
    void solve_concurrently(const std::vector<SolveAction>& plan, std::size_t begin, std::size_t end, double dt);
    struct ThreadArena;
    Node root_;
    int threads_ = 0;
    std::unique_ptr<ThreadArena> arena_;  ///< made at the first concurrent solve
    std::vector<SolveAction> plan_;
    /// The states whose external force a step applies, cleared after each step (found with the
    /// plan): those of a solver's subtree, the outputs of mappings and the states of explicit
    /// force fields. The others (static obstacles) are never applied nor cleared: a floor of
    /// 10⁵ points costs no pass over its memory per step.
    std::vector<BaseState*> applied_states_;
    PointerIndex<BaseState> applied_index_;  ///< solve_plan's scratch: the states of applied_states_
    std::optional<std::uint64_t> plan_version_;
    double time_ = 0.0;
    bool initialized_ = false;
};

}  // namespace penalty
