#pragma once
/// @file
/// Mappings (SOFA's Mapping<In, Out>): a child (output) state whose positions are a function of
/// a parent (input) state, x_out = φ(x_in), with J = ∂φ/∂x_in:
///   apply: x_out = φ(x_in);  apply_j: v_out = J·v_in;  apply_jt: f_in += Jᵀ·f_out.
/// Mappings chain (a contact point mapped on a surface mapped on a volume): solvers call them
/// top-down for apply/apply_j and bottom-up for apply_jt.

#include "penalty/mechanics/force_field.hpp"
#include "penalty/mechanics/topology.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace penalty {

template <int Capacity>
struct BarycentricRowOf;

class BaseMapping {
public:
    virtual ~BaseMapping() = default;
    [[nodiscard]] virtual BaseState* from() const = 0;
    [[nodiscard]] virtual BaseState* to() const = 0;
    /// Sizes the output state and computes its positions (and rest positions).
    virtual void init() = 0;
    virtual void apply_position() = 0;  ///< to.x = φ(from.x)
    virtual void apply_velocity() = 0;  ///< to.v = J from.v
    virtual void apply_dx() = 0;        ///< to.dx = J from.dx
    virtual void apply_jt_force() = 0;  ///< from.f += Jᵀ to.f
    virtual void apply_jt_df() = 0;     ///< from.df += Jᵀ to.df
    /// J as triplets (rows: output scalars + row_offset, columns: input scalars + col_offset).
    virtual void add_jacobian_triplets(TripletList& triplets, Index row_offset, Index col_offset) const = 0;
    /// Appends to `rows` every input DOF (of from()) that apply_dx reads, in any order and
    /// possibly repeated, and returns true; false (the default): the mapping cannot tell, it may
    /// read any. apply_jt_force and apply_jt_df write from()'s force and df in those DOFs only.
    [[nodiscard]] virtual bool list_inputs_read(std::vector<std::uint32_t>& /*rows*/) const { return false; }
    /// True when the mapping implements apply_dx_rows and apply_jt_df_rows (default false).
    [[nodiscard]] virtual bool maps_selected_rows() const { return false; }
    /// to.dx = J from.dx for the output DOFs `rows` only (ascending, each < to's size), with the
    /// operations apply_dx does for them; the other rows of to.dx are left as they were.
    /// Default (maps_selected_rows() false): apply_dx.
    virtual void apply_dx_rows(std::span<const std::uint32_t> /*rows*/) { apply_dx(); }
    /// from.df += Jᵀ to.df with to.df's rows outside `rows` (ascending) taken as +0 and not read:
    /// the bits of apply_jt_df when those rows hold +0. Default (maps_selected_rows() false):
    /// apply_jt_df.
    virtual void apply_jt_df_rows(std::span<const std::uint32_t> /*rows*/) { apply_jt_df(); }
    /// When J is a list of contact barycentric rows from a Vec3 state onto a Vec3 state, one row
    /// per output DOF (ContactPointMapping over a BarycentricContactMapper: apply_dx is
    /// to.dx[i] = rows[i].combine(from.dx), apply_jt_df is rows[i].spread(from.df, to.df[i]) for
    /// i in order): those rows, so that a solver may apply J and Jᵀ itself with the same
    /// operations (SubtreeSystem's fused contact products). nullptr (the default) otherwise.
    [[nodiscard]] virtual const std::vector<BarycentricRowOf<4>>* contact_barycentric_rows() const { return nullptr; }

    /// A second input (SOFA's Multi2Mapping: DeformableOnRigidFrameMapping's frames), or null.
    /// apply_position/apply_velocity read its position/velocity, apply_dx its dx, and
    /// apply_jt_force/apply_jt_df add into its force/df, besides from()'s.
    [[nodiscard]] virtual BaseState* second_from() const { return nullptr; }
    /// J's block of the second input as triplets (rows: output scalars + row_offset, columns:
    /// second_from()'s scalars + col_offset); nothing without a second input.
    virtual void add_second_input_jacobian_triplets(TripletList& /*triplets*/, Index /*row_offset*/,
                                                    Index /*col_offset*/) const {}
    /// True when apply_djt adds a geometric stiffness (a non-linear mapping's ∂Jᵀ/∂x·f).
    [[nodiscard]] bool has_geometric_stiffness() const { return geometric_stiffness_; }
    /// SOFA's applyDJT: from.df += k·(∂(Jᵀ·f)/∂x)·from.dx with f = to.force (the output's force of
    /// the last force computation), k the stiffness factor of the product.
    virtual void apply_djt(double /*k_factor*/) {}

protected:
    bool geometric_stiffness_ = false;  ///< set by mappings whose apply_djt adds something
};

template <class In, class Out>
class Mapping : public BaseMapping {
public:
    using InCoord = typename In::Coord;
    using InDeriv = typename In::Deriv;
    using OutCoord = typename Out::Coord;
    using OutDeriv = typename Out::Deriv;

    Mapping(MechanicalObject<In>& from, MechanicalObject<Out>& to) : in_(&from), out_(&to) {}

    /// out = φ(in) (out already sized).
    virtual void apply(std::span<OutCoord> out, std::span<const InCoord> in) = 0;
    /// out = J·in (overwrites).
    virtual void apply_j(std::span<OutDeriv> out, std::span<const InDeriv> in) const = 0;
    /// in += Jᵀ·out.
    virtual void apply_jt(std::span<InDeriv> in, std::span<const OutDeriv> out) const = 0;
    /// Number of output DOFs.
    [[nodiscard]] virtual std::size_t output_size() const = 0;

    [[nodiscard]] BaseState* from() const override { return in_; }
    [[nodiscard]] BaseState* to() const override { return out_; }
    /// A state with positions of its own, one per output (a grid, a loader, its `position`), keeps
    /// them as its rest positions, as SOFA's MechanicalObject::init, which runs before the mapping's
    /// init maps the positions only (Mapping::init, applyRestPosition off); a state without them
    /// takes the mapped positions as rest positions.
    void init() override {
        const bool own_positions = out_->position.size() == output_size();
        if (own_positions) out_->init();
        out_->position.resize(output_size());
        apply(out_->position, in_->position);
        if (!own_positions) {
            out_->rest_position = out_->position;
            out_->velocity.resize(output_size());
            out_->init();
        }
        apply_velocity();
    }
    void apply_position() override { apply(out_->position, in_->position); }
    void apply_velocity() override { apply_j(out_->velocity, in_->velocity); }
    void apply_dx() override { apply_j(out_->dx, in_->dx); }
    void apply_jt_force() override { apply_jt(in_->force, out_->force); }
    void apply_jt_df() override { apply_jt(in_->df, out_->df); }

protected:
    MechanicalObject<In>* in_;
    MechanicalObject<Out>* out_;
};

/// BarycentricRowOf::push past its capacity: std::invalid_argument.
[[noreturn]] void throw_barycentric_row_full(int capacity);

/// One output point of a linear-combination (barycentric) map: x_out = Σ_{k<count} w_k·x_in[i_k],
/// summed from zero in k order (the rounding of the mapped point depends on the order). J is the
/// weights: v_out = Σ w_k v_in[i_k]; Jᵀ: f_in[i_k] += w_k·f_out, k in order. The one
/// implementation of this Jacobian, used by BarycentricMapping (BarycentricRow, up to a
/// hexahedron's 8 vertices) and BarycentricContactMapper (ContactBarycentricRow, up to 4: a
/// segment, triangle, quad or tetrahedron; 72 bytes a row instead of 136, read at each product).
template <int Capacity>
struct BarycentricRowOf {
    struct Entry {
        Index index;    ///< input point
        double weight;  ///< its weight
    };
    static constexpr int kCapacity = Capacity;
    int count = 0;  ///< first: read with the first entries (one cache line for a triangle's row)
    std::array<Entry, kCapacity> entries{};

    /// Appends (index, weight); std::invalid_argument past kCapacity.
    void push(Index index, double weight) {
        if (count == kCapacity) throw_barycentric_row_full(kCapacity);
        entries[static_cast<std::size_t>(count++)] = {index, weight};
    }
    [[nodiscard]] const Entry& operator[](std::size_t k) const { return entries[k]; }
    [[nodiscard]] std::size_t size() const { return static_cast<std::size_t>(count); }
    [[nodiscard]] const Entry* begin() const { return entries.data(); }
    [[nodiscard]] const Entry* end() const { return entries.data() + count; }

    /// Σ_k w_k·in[i_k] (positions, velocities or displacements).
    [[nodiscard]] Vec3 combine(std::span<const Vec3> in) const {
        Vec3 s = Vec3::Zero();
        for (const Entry& e : *this) s += e.weight * in[static_cast<std::size_t>(e.index)];
        return s;
    }
    /// in[i_k] += w_k·f for each k (Jᵀ of one output point).
    void spread(std::span<Vec3> in, const Vec3& f) const {
        for (const Entry& e : *this) in[static_cast<std::size_t>(e.index)] += e.weight * f;
    }
    /// J's entries of this output point: rows first_row + a, columns col_offset + 3·i_k + a.
    void add_triplets(TripletList& t, Index first_row, Index col_offset) const {
        for (const Entry& e : *this)
            for (Index a = 0; a < 3; ++a) t.emplace_back(first_row + a, col_offset + 3 * e.index + a, e.weight);
    }
};
using BarycentricRow = BarycentricRowOf<8>;
using ContactBarycentricRow = BarycentricRowOf<4>;

/// One output point rigidly attached to a body frame r: x_out = c_r + R_r·L with L the local
/// point. J at the rotated point p = R_r·L of the last place(): v_out = v_r + ω_r × p; Jᵀ:
/// f_r += f, τ_r += p × f (N·m, world frame). The one implementation of this Jacobian, used by
/// RigidMapping and RigidContactMapper.
struct RigidPointRow {
    Index frame = 0;              ///< input frame index
    Vec3 local = Vec3::Zero();    ///< L, in the frame (m)
    Vec3 rotated = Vec3::Zero();  ///< p = R_r·L at the last place() (m, world axes)

    /// Updates p from `f` and returns x_out = c + p.
    Vec3 place(const RigidFrame& f) {
        rotated = f.orientation * local;
        return f.center + rotated;
    }
    /// v_r + ω_r × p (J·v of this point).
    [[nodiscard]] Vec3 velocity(const RigidDeriv& v) const { return v.linear + v.angular.cross(rotated); }
    /// f_r += f, τ_r += p × f (Jᵀ of this point).
    void spread(RigidDeriv& in, const Vec3& f) const {
        in.linear += f;
        in.angular += rotated.cross(f);
    }
    /// J's entries of this output point (rows first_row + a): identity on the linear block,
    /// −[p]× on the angular one (ω × p = −[p]× ω), all nine entries (a constant pattern);
    /// columns col_offset + 6·r + (0..5).
    void add_triplets(TripletList& t, Index first_row, Index col_offset) const;
};

/// IdentityMapping Vec3 -> Vec3: x_out[i] = x_in[i].
class IdentityMapping final : public Mapping<Vec3Types, Vec3Types> {
public:
    using Mapping::Mapping;
    void apply(std::span<Vec3> out, std::span<const Vec3> in) override;
    void apply_j(std::span<Vec3> out, std::span<const Vec3> in) const override;
    void apply_jt(std::span<Vec3> in, std::span<const Vec3> out) const override;
    void add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const override;
    [[nodiscard]] std::size_t output_size() const override { return in_->num_dofs(); }
};

/// IdentityMapping Rigid3 -> Vec3 as SOFA: x_out[i] = centre of frame i; v_out = linear velocity;
/// f_in.linear += f_out (no torque).
class RigidCenterIdentityMapping final : public Mapping<Rigid3Types, Vec3Types> {
public:
    using Mapping::Mapping;
    void apply(std::span<Vec3> out, std::span<const RigidFrame> in) override;
    void apply_j(std::span<Vec3> out, std::span<const RigidDeriv> in) const override;
    void apply_jt(std::span<RigidDeriv> in, std::span<const Vec3> out) const override;
    void add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const override;
    [[nodiscard]] std::size_t output_size() const override { return in_->num_dofs(); }
};

/// RigidMapping Rigid3 -> Vec3: x_out[i] = c_r + R_r·p_i with p_i the local point and r the frame
/// of point i (frame index per point, default 0). J: v_out = v_r + ω_r × (R_r p_i), using the
/// rotated points of the last apply (SOFA); Jᵀ: f_r += f, τ_r += (R_r p_i) × f.
class RigidMapping final : public Mapping<Rigid3Types, Vec3Types> {
public:
    RigidMapping(Rigid3Object& from, Vec3Object& to) : Mapping(from, to) {}
    /// Local coordinates (in the frame) of each output point, and the frame index of each point
    /// (empty: all on frame 0).
    void set_points(std::vector<Vec3> local_points, std::vector<Index> frame_index = {});
    /// SOFA's default: local points = R⁻¹ (x_out − c) from the output's current positions.
    void set_points_from_world(std::span<const Vec3> world_points, std::vector<Index> frame_index = {});
    [[nodiscard]] const std::vector<RigidPointRow>& points() const { return rows_; }
    /// Checks the frame indices against the input size, then sizes and computes the output.
    void init() override;

    /// apply and apply_j (each point its own) run in ranges of kPointsPerTask on TBB's threads
    /// from OrderedScatter::kMinElements points and more than one thread (the bits of one
    /// thread); apply_jt, the points' sums into their frames in point order, runs on one.
    static constexpr std::size_t kPointsPerTask = 2048;
    void apply(std::span<Vec3> out, std::span<const RigidFrame> in) override;
    void apply_j(std::span<Vec3> out, std::span<const RigidDeriv> in) const override;
    void apply_jt(std::span<RigidDeriv> in, std::span<const Vec3> out) const override;
    void add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const override;
    [[nodiscard]] std::size_t output_size() const override { return rows_.size(); }

private:
    std::vector<RigidPointRow> rows_;  ///< frame, L and R·L (at the last apply) per output point
};

/// Linear combination mapping Vec3 -> Vec3: x_out[i] = Σ_k w_ik x_in[j_ik] (BarycentricMapping).
/// J is constant: the weights.
class BarycentricMapping final : public Mapping<Vec3Types, Vec3Types> {
public:
    using Entry = BarycentricRow::Entry;
    using Mapping::Mapping;

    /// Weights given directly (row i = output point i, at most BarycentricRow::kCapacity
    /// entries); indices are checked at init().
    void set_weights(std::vector<std::vector<Entry>> rows);
    void set_rows(std::vector<BarycentricRow> rows);
    /// Maps `points` onto the tetrahedra of `topology` with positions `x`, with SOFA's operations
    /// (BarycentricMapperMeshTopology::init): b = B·(p − x0), B the inverse of the edge matrix by
    /// type::invertMatrix; a tetrahedron's distance is max(−b0, −b1, −b2, b0+b1+b2−1), replaced,
    /// when positive (outside), by |p − centre|²; the first tetrahedron of least distance wins;
    /// weights ((1 − b0) − b1) − b2, b0, b1, b2.
    void map_on_tetrahedra(const MeshTopology& topology, std::span<const Vec3> x, std::span<const Vec3> points);
    /// The same onto a dynamic container's tetrahedra (SOFA's BarycentricMapperTetrahedronSetTopology,
    /// BarycentricMapperTopologyContainer::init): each point's element is searched first among those
    /// whose bounding box touches its cell of a hash grid (cells of the mean edge length), then, if
    /// that cell has none, among all; if the best found has |distance| > cell/2 (SOFA compares the
    /// squared distance outside an element with a length), among those of the 27 cells around.
    /// The same element as map_on_tetrahedra for a point inside one (barycentric_set_mapper.cpp).
    void map_on_set_tetrahedra(const MeshTopology& topology, std::span<const Vec3> x, std::span<const Vec3> points);
    /// The same onto a dynamic container's hexahedra (SOFA's BarycentricMapperHexahedronSetTopology,
    /// the same init): b = (x1 − x0, x3 − x0, x4 − x0)⁻¹·(p − x0), the parallelepiped of three
    /// edges (computeBase), score max(−b, b − 1) or |p − centre|² outside (computeDistance), and
    /// trilinear weights of b (getBarycentricCoefficients).
    void map_on_set_hexahedra(const MeshTopology& topology, std::span<const Vec3> x, std::span<const Vec3> points);
    /// Maps onto hexahedra with trilinear weights (inverse trilinear map by Newton; SOFA's
    /// parallelepiped approximation gives the same weights for parallelepipeds).
    void map_on_hexahedra(const MeshTopology& topology, std::span<const Vec3> x, std::span<const Vec3> points);
    /// Row i: the (input index, weight) entries of output point i (iterable, rows[i][k]).
    [[nodiscard]] const std::vector<BarycentricRow>& weights() const { return rows_; }
    /// Checks the input indices against the input size, then sizes and computes the output.
    void init() override;

    /// apply and apply_j (each output row its own) and apply_jt's full gather (each input point
    /// its own) run in ranges of kRowsPerTask on TBB's threads from OrderedScatter::kMinElements
    /// rows or inputs and more than one thread (detail::for_each_range): the bits of one thread.
    static constexpr std::size_t kRowsPerTask = 2048;
    void apply(std::span<Vec3> out, std::span<const Vec3> in) override;
    void apply_j(std::span<Vec3> out, std::span<const Vec3> in) const override;
    /// in += Jᵀ·out; when few rows of out are non-zero, only those rows (the same bits, see
    /// mapping.cpp). Not reentrant (scratch kept in the mapping).
    void apply_jt(std::span<Vec3> in, std::span<const Vec3> out) const override;
    void add_jacobian_triplets(TripletList& t, Index row_offset, Index col_offset) const override;
    [[nodiscard]] std::size_t output_size() const override { return rows_.size(); }
    [[nodiscard]] bool list_inputs_read(std::vector<std::uint32_t>& rows) const override;
    [[nodiscard]] bool maps_selected_rows() const override { return true; }
    void apply_dx_rows(std::span<const std::uint32_t> rows) override;
    void apply_jt_df_rows(std::span<const std::uint32_t> rows) override;
    /// out[i] = J·in for the output points `rows` only (apply_j's operations for them).
    void apply_j_rows(std::span<Vec3> out, std::span<const Vec3> in, std::span<const std::uint32_t> rows) const;

private:
    std::vector<BarycentricRow> rows_;
    // rows_ flattened for the per-CG-product loops (apply_j, apply_jt): the entries of row i are
    // [row_begin_[i], row_begin_[i + 1]) of entry_index_ / entry_weight_ (rows_ is 136 bytes a
    // row whatever its count). Same entries, same order, same operations as BarycentricRow.
    std::vector<std::uint32_t> row_begin_;
    std::vector<std::uint32_t> entry_index_;
    std::vector<double> entry_weight_;
    // The same entries by input point (Jᵀ as a gather): input j's entries are
    // [input_begin_[j], input_begin_[j + 1]) of input_row_ / input_weight_, in row order then
    // entry order, i.e. the order in which BarycentricRow::spread adds them into in[j].
    std::vector<std::uint32_t> input_begin_;
    std::vector<std::uint32_t> input_row_;
    std::vector<double> input_weight_;
    std::vector<std::uint32_t> used_inputs_;  ///< inputs with at least one entry, ascending
    /// apply_jt scatters only the rows with a non-zero force when they are at most 1/ratio of
    /// the rows (else the full gather).
    static constexpr std::size_t kSparseJtRatio = 4;
    // apply_jt's scratch (kept: no allocation per product)
    mutable std::vector<std::uint32_t> forced_rows_;
    mutable std::vector<std::uint32_t> negative_zero_inputs_;
    mutable std::vector<Vec3> negative_zero_sums_;
    mutable std::vector<std::uint8_t> row_counted_;  ///< apply_jt_df_rows: the rows given (all 0 between calls)
    /// in[j] + Σ (row, entry) order of w·out[row] over input j's entries; with `counted`, a row
    /// whose flag is 0 counts as +0.
    [[nodiscard]] Vec3 gathered_jt(std::span<const Vec3> in, std::span<const Vec3> out, std::uint32_t j,
                                   const std::uint8_t* counted) const;
    /// Scatters forced_rows_ into in (row order), inputs starting at −0 gathered in full.
    void scatter_forced_rows(std::span<Vec3> in, std::span<const Vec3> out, const std::uint8_t* counted) const;
    /// The gather over inputs [first, last).
    void gather_jt(std::span<Vec3> in, std::span<const Vec3> out, std::size_t first, std::size_t last) const;
};

/// Trilinear weights of local coordinates (u, v, w) ∈ [0,1]³ in SOFA's hexahedron vertex order
/// (0:(0,0,0) 1:(1,0,0) 2:(1,1,0) 3:(0,1,0) 4:(0,0,1) 5:(1,0,1) 6:(1,1,1) 7:(0,1,1)).
std::array<double, 8> trilinear_weights(const Vec3& uvw);

}  // namespace penalty
