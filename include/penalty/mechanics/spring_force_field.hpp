#pragma once
/// @file
/// Springs (spec §10.5): SpringForceField / StiffSpringForceField, MeshSpringForceField and
/// RegularGridSpringForceField (the latter two only build the spring list).

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/kernel_path.hpp"
#include "penalty/mechanics/ordered_scatter.hpp"
#include "penalty/mechanics/topology.hpp"

#include <array>
#include <vector>

namespace penalty {

/// One spring between DOF a of state 1 and DOF b of state 2.
struct Spring {
    Index a = 0;
    Index b = 0;
    double ks = 0.0;           ///< stiffness (N/m), >= 0
    double kd = 0.0;           ///< damping (N·s/m), >= 0
    double rest_length = 0.0;  ///< L (m), >= 0
};

/// Operation order of the spring law: the law is one, but SOFA's classes round it differently,
/// and trajectories are compared to the last bit.
enum class SpringArithmetic {
    /// SpringForceField::computeSpringForce / computeSpringDForce: U = u·(1/d),
    /// m_jk = ((ks − t)·U_j)·U_k, df = (m·dx)·k.
    spring_force_field,
    /// QuadularBendingSprings::computeLocalJacobian / addDForce: the Jacobian's direction is
    /// u/d (a division), m_jk = (ks − t)·(U_j·U_k), df = m·(dx·k).
    quadular_bending_springs,
};

namespace detail {
/// m of one spring (see SpringForceField) by columns, each padded to 4 lanes with 0: column c
/// holds m(0, c), m(1, c), m(2, c), 0, so that one 256-bit lane r computes row r of m·dx.
struct alignas(32) SpringStiffnessColumns {
    std::array<std::array<double, 4>, 3> column{};
    [[nodiscard]] double operator()(int row, int col) const {
        return column[static_cast<std::size_t>(col)][static_cast<std::size_t>(row)];
    }
};
}  // namespace detail

/// SpringForceField (SOFA's SpringForceField = StiffSpringForceField), between two Vec3 states or
/// inside one (pass the same state twice). For a spring (a, b): u = x_b − x_a, d = |u|, û = u/d,
/// intensity F = ks (d − L) + kd (v_b − v_a)·û, force +F û on a and −F û on b; springs with
/// d <= the null length (1e-9, set_null_length) are ignored. Stiffness block (linearised at add_force):
///   m = (ks − F/d) ûûᵀ + (F/d) I,  K_aa = K_bb = −m,  K_ab = K_ba = +m  (SOFA sign).
/// Damping is explicit only: add_dforce ignores b_factor (SOFA). Energy ½ ks (d − L)².
class SpringForceField : public Vec3InteractionForceField {
public:
    SpringForceField(Vec3Object& state1, Vec3Object& state2) : Vec3InteractionForceField(state1, state2) {}
    /// Spring inside one state.
    explicit SpringForceField(Vec3Object& state) : Vec3InteractionForceField(state, state) {}

    /// Adds a spring; throws std::invalid_argument on negative/non-finite parameters.
    void add_spring(const Spring& s);
    /// Removes every spring (a topology follower rewrites the list, then calls init()).
    void clear_springs() {
        springs_.clear();
        end_offsets_.clear();
        dfdx_.clear();
        ends_.clear();  // (on one thread until init makes them again)
        scatter_.clear();
    }
    /// Checks the indices against the state sizes.
    void init() override;
    [[nodiscard]] const std::vector<Spring>& springs() const { return springs_; }
    /// The split of the springs on threads as the last force or product on threads made it
    /// (chunk_count() 0 before one ran); see runs_on_threads.
    [[nodiscard]] const detail::OrderedScatter& product_scatter() const { return scatter_; }
    /// Springs with d <= `length` (m) give no force and no stiffness (SpringForceField: 1e-9;
    /// TriangularBendingSprings::addForce: 1e-4).
    void set_null_length(double length) { null_length_ = length; }
    /// SOFA's operation order to reproduce (default: SpringForceField's).
    void set_arithmetic(SpringArithmetic arithmetic) { arithmetic_ = arithmetic; }
    /// Instructions of add_dforce (default best_kernel_path(); every path gives the same bits).
    /// Throws std::invalid_argument if this machine cannot run `path`, or for avx512 (no such
    /// path for springs).
    void set_kernel_path(KernelPath path);
    [[nodiscard]] KernelPath kernel_path() const { return kernel_path_; }

    void add_force(Vec3Span f1, Vec3Span f2, ConstVec3Span x1, ConstVec3Span x2, ConstVec3Span v1,
                   ConstVec3Span v2) override;
    void add_dforce(Vec3Span df1, Vec3Span df2, ConstVec3Span dx1, ConstVec3Span dx2, double k_factor,
                    double b_factor) const override;
    void add_stiffness_triplets(TripletList& triplets, Index offset1, Index offset2, double factor) const override;
    [[nodiscard]] double potential_energy() const override { return energy_; }
    [[nodiscard]] ForceFieldStates states() const override;

private:
    using StiffnessColumns = detail::SpringStiffnessColumns;

    std::vector<Spring> springs_;
    std::vector<StiffnessColumns> dfdx_;  ///< m per spring, from the last add_force
    /// Each spring's ends as byte offsets into the Vec3 arrays (a·sizeof(Vec3), b·sizeof(Vec3)),
    /// made by add_spring: the vector product's addresses without a multiplication, and 16
    /// bytes a spring to stream instead of the Spring's 40.
    std::vector<std::array<std::ptrdiff_t, 2>> end_offsets_;
    /// From OrderedScatter::kMinElements springs, inside one state or between two, with more than
    /// one thread: add_force and add_dforce on TBB's threads with the bits of one thread (chunks
    /// of springs, an end's terms from its first chunk applied at once, the others stored and
    /// added in spring order after; the energies summed in spring order). init makes ends_;
    /// `first_state_points`: the first state's size now (two states: as init numbered them).
    [[nodiscard]] bool runs_on_threads(std::size_t first_state_points) const;
    /// Where the deferred terms go: out1 (one state), or out1 then out2 (two).
    [[nodiscard]] detail::ScatterTarget scatter_target(Vec3Span out1, Vec3Span out2) const;
    /// (a, b) per spring, for scatter_; between two states b is numbered after the first
    /// state's second_state_first_ points.
    std::vector<std::array<PointId, 2>> ends_;
    std::size_t second_state_first_ = 0;
    mutable detail::OrderedScatter scatter_;
    std::vector<double> spring_energies_;
    double energy_ = 0.0;
    double null_length_ = 1e-9;
    SpringArithmetic arithmetic_ = SpringArithmetic::spring_force_field;
    KernelPath kernel_path_ = best_kernel_path();
};

/// Per-element-type stiffness/damping of MeshSpringForceField (SOFA's linesStiffness …
/// cubesStiffness; `stiffness` / `damping` set them all). Units: N (stiffness is divided by the
/// rest length to give ks in N/m) and N·s (damping / L gives kd).
struct MeshSpringParameters {
    double lines_stiffness = 0, lines_damping = 0;
    double triangles_stiffness = 0, triangles_damping = 0;
    double quads_stiffness = 0, quads_damping = 0;
    double tetras_stiffness = 0, tetras_damping = 0;
    double cubes_stiffness = 0, cubes_damping = 0;
    /// Sets every stiffness and damping (SOFA's `stiffness` and `damping` aliases).
    static MeshSpringParameters uniform(double stiffness, double damping);
};

/// Spring list of SOFA's MeshSpringForceField: for each element type with a non-zero stiffness or
/// damping, in the order edges, triangles (3 pairs), quads (6), tetrahedra (6), hexahedra (all 28
/// pairs), one spring per vertex pair not seen before, oriented as in the element;
/// ks = stiffness / L, kd = damping / L with L the rest length (throws if L == 0).
std::vector<Spring> mesh_springs(const MeshTopology& topology, std::span<const Vec3> rest_positions,
                                 const MeshSpringParameters& parameters);

}  // namespace penalty
