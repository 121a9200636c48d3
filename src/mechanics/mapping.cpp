#include "penalty/mechanics/mapping.hpp"

#include "barycentric_tetrahedra.hpp"
#include "sofa_vector_ops.hpp"

#include "penalty/mechanics/ordered_scatter.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace penalty {

// ---- Jacobian rows ----------------------------------------------------------------------------
void throw_barycentric_row_full(int capacity) {
    throw_invalid_argument("BarycentricRow: more than ", capacity, " input points");
}

void RigidPointRow::add_triplets(TripletList& t, Index first_row, Index col_offset) const {
    const Index r = first_row;
    const Index c = col_offset + 6 * frame;
    const Vec3& p = rotated;
    // ω × p = −[p]× ω, [p]× = [[0, −p_z, p_y], [p_z, 0, −p_x], [−p_y, p_x, 0]]
    const Mat3 minus_px = -(Mat3() << 0, -p.z(), p.y(), p.z(), 0, -p.x(), -p.y(), p.x(), 0).finished();
    for (Index a = 0; a < 3; ++a) {
        t.emplace_back(r + a, c + a, 1.0);
        for (Index b = 0; b < 3; ++b) t.emplace_back(r + a, c + 3 + b, minus_px(a, b));
    }
}

// ---- IdentityMapping --------------------------------------------------------------------------
void IdentityMapping::apply(std::span<Vec3> out, std::span<const Vec3> in) {
    PENALTY_DEMAND(out.size() == in.size());
    std::copy(in.begin(), in.end(), out.begin());
}
void IdentityMapping::apply_j(std::span<Vec3> out, std::span<const Vec3> in) const {
    PENALTY_DEMAND(out.size() == in.size());
    std::copy(in.begin(), in.end(), out.begin());
}
void IdentityMapping::apply_jt(std::span<Vec3> in, std::span<const Vec3> out) const {
    PENALTY_DEMAND(out.size() == in.size());
    for (std::size_t i = 0; i < in.size(); ++i) in[i] += out[i];
}
void IdentityMapping::add_jacobian_triplets(TripletList& t, Index ro, Index co) const {
    for (Index i = 0; i < static_cast<Index>(3 * in_->num_dofs()); ++i) t.emplace_back(ro + i, co + i, 1.0);
}

// ---- Rigid3 -> Vec3 identity ------------------------------------------------------------------
void RigidCenterIdentityMapping::apply(std::span<Vec3> out, std::span<const RigidFrame> in) {
    PENALTY_DEMAND(out.size() == in.size());
    for (std::size_t i = 0; i < in.size(); ++i) out[i] = in[i].center;
}
void RigidCenterIdentityMapping::apply_j(std::span<Vec3> out, std::span<const RigidDeriv> in) const {
    PENALTY_DEMAND(out.size() == in.size());
    for (std::size_t i = 0; i < in.size(); ++i) out[i] = in[i].linear;
}
void RigidCenterIdentityMapping::apply_jt(std::span<RigidDeriv> in, std::span<const Vec3> out) const {
    PENALTY_DEMAND(out.size() == in.size());
    for (std::size_t i = 0; i < in.size(); ++i) in[i].linear += out[i];
}
void RigidCenterIdentityMapping::add_jacobian_triplets(TripletList& t, Index ro, Index co) const {
    for (Index i = 0; i < static_cast<Index>(in_->num_dofs()); ++i)
        for (Index a = 0; a < 3; ++a) t.emplace_back(ro + 3 * i + a, co + 6 * i + a, 1.0);
}

// ---- RigidMapping -----------------------------------------------------------------------------
void RigidMapping::set_points(std::vector<Vec3> local_points, std::vector<Index> frame_index) {
    for (std::size_t i = 0; i < local_points.size(); ++i)
        if (!local_points[i].allFinite()) throw_invalid_argument("RigidMapping: local point ", i, " is not finite");
    if (!frame_index.empty() && frame_index.size() != local_points.size())
        throw_invalid_argument("RigidMapping: ", frame_index.size(), " frame indices for ", local_points.size(),
                               " points");
    for (const Index r : frame_index)
        if (r < 0) throw_invalid_argument("RigidMapping: negative frame index ", r);
    rows_.assign(local_points.size(), RigidPointRow{});
    for (std::size_t i = 0; i < rows_.size(); ++i) {
        rows_[i].frame = frame_index.empty() ? 0 : frame_index[i];
        rows_[i].local = local_points[i];
    }
}

void RigidMapping::set_points_from_world(std::span<const Vec3> world, std::vector<Index> frame_index) {
    if (in_->num_dofs() == 0) throw_invalid_argument("RigidMapping: input state has no frame");
    std::vector<Vec3> local(world.size());
    for (std::size_t i = 0; i < world.size(); ++i) {
        const std::size_t r = frame_index.empty() ? 0 : static_cast<std::size_t>(frame_index[i]);
        if (r >= in_->num_dofs()) throw_invalid_argument("RigidMapping: frame index ", r, " out of range");
        const RigidFrame& f = in_->position[r];
        local[i] = f.orientation.conjugate() * (world[i] - f.center);
    }
    set_points(std::move(local), std::move(frame_index));
}

void RigidMapping::init() {
    for (std::size_t i = 0; i < rows_.size(); ++i)
        if (static_cast<std::size_t>(rows_[i].frame) >= in_->num_dofs())
            throw_invalid_argument("RigidMapping: point ", i, " uses frame ", rows_[i].frame, " out of range (",
                                   in_->num_dofs(), " frames)");
    Mapping::init();
}

void RigidMapping::apply(std::span<Vec3> out, std::span<const RigidFrame> in) {
    PENALTY_DEMAND(out.size() == rows_.size());
    // each point (its output and its rotated point) its own: in ranges on TBB's threads from
    // OrderedScatter::kMinElements points
    detail::for_each_range(rows_.size(), kPointsPerTask, [&](std::size_t first, std::size_t end) {
        for (std::size_t i = first; i < end; ++i) out[i] = rows_[i].place(in[static_cast<std::size_t>(rows_[i].frame)]);
    });
}
void RigidMapping::apply_j(std::span<Vec3> out, std::span<const RigidDeriv> in) const {
    detail::for_each_range(rows_.size(), kPointsPerTask, [&](std::size_t first, std::size_t end) {
        for (std::size_t i = first; i < end; ++i)
            out[i] = rows_[i].velocity(in[static_cast<std::size_t>(rows_[i].frame)]);
    });
}
void RigidMapping::apply_jt(std::span<RigidDeriv> in, std::span<const Vec3> out) const {
    for (std::size_t i = 0; i < rows_.size(); ++i)
        rows_[i].spread(in[static_cast<std::size_t>(rows_[i].frame)], out[i]);
}
void RigidMapping::add_jacobian_triplets(TripletList& t, Index ro, Index co) const {
    for (std::size_t i = 0; i < rows_.size(); ++i) rows_[i].add_triplets(t, ro + 3 * static_cast<Index>(i), co);
}

// ---- BarycentricMapping -----------------------------------------------------------------------
std::array<double, 8> trilinear_weights(const Vec3& p) {
    const double u = p.x(), v = p.y(), w = p.z();
    return {(1 - u) * (1 - v) * (1 - w), u * (1 - v) * (1 - w), u * v * (1 - w), (1 - u) * v * (1 - w),
            (1 - u) * (1 - v) * w,       u * (1 - v) * w,       u * v * w,       (1 - u) * v * w};
}

void BarycentricMapping::set_weights(std::vector<std::vector<Entry>> rows) {
    std::vector<BarycentricRow> fixed(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
        if (rows[i].size() > static_cast<std::size_t>(BarycentricRow::kCapacity))
            throw_invalid_argument("BarycentricMapping: point ", i, " has ", rows[i].size(), " weights (at most ",
                                   BarycentricRow::kCapacity, ")");
        for (const Entry& e : rows[i]) fixed[i].push(e.index, e.weight);
    }
    set_rows(std::move(fixed));
}

void BarycentricMapping::set_rows(std::vector<BarycentricRow> rows) {
    for (std::size_t i = 0; i < rows.size(); ++i)
        for (const Entry& e : rows[i]) {
            if (e.index < 0)
                throw_invalid_argument("BarycentricMapping: point ", i, " uses a negative input index ", e.index);
            if (!std::isfinite(e.weight))
                throw_invalid_argument("BarycentricMapping: point ", i, " has a non-finite weight");
        }
    rows_ = std::move(rows);
    row_begin_.assign(1, 0);
    entry_index_.clear();
    entry_weight_.clear();
    for (const BarycentricRow& row : rows_) {
        for (const Entry& e : row) {
            if (e.index > std::numeric_limits<std::uint32_t>::max())
                throw_invalid_argument("BarycentricMapping: input index ", e.index, " too large");
            entry_index_.push_back(static_cast<std::uint32_t>(e.index));
            entry_weight_.push_back(e.weight);
        }
        row_begin_.push_back(static_cast<std::uint32_t>(entry_index_.size()));
    }
    // Transpose by counting sort; a stable pass over the rows keeps each input's entries in
    // (row, entry) order.
    std::uint32_t inputs = 0;
    for (const std::uint32_t j : entry_index_) inputs = std::max(inputs, j + 1);
    input_begin_.assign(static_cast<std::size_t>(inputs) + 1, 0);
    for (const std::uint32_t j : entry_index_) ++input_begin_[static_cast<std::size_t>(j) + 1];
    for (std::size_t j = 0; j < inputs; ++j) input_begin_[j + 1] += input_begin_[j];
    input_row_.resize(entry_index_.size());
    input_weight_.resize(entry_index_.size());
    std::vector<std::uint32_t> next(input_begin_.begin(), input_begin_.end() - 1);
    for (std::uint32_t i = 0; i + 1 < row_begin_.size(); ++i)
        for (std::uint32_t k = row_begin_[i]; k < row_begin_[i + 1]; ++k) {
            const std::uint32_t slot = next[entry_index_[k]]++;
            input_row_[slot] = i;
            input_weight_[slot] = entry_weight_[k];
        }
    used_inputs_.clear();
    for (std::uint32_t j = 0; j < inputs; ++j)
        if (input_begin_[j] != input_begin_[j + 1]) used_inputs_.push_back(j);
    // apply_jt's scratch at its largest: no allocation in a product
    forced_rows_.reserve(rows_.size());
    row_counted_.assign(rows_.size(), 0);
    negative_zero_inputs_.reserve(used_inputs_.size());
    negative_zero_sums_.reserve(used_inputs_.size());
}

void BarycentricMapping::init() {
    for (std::size_t i = 0; i < rows_.size(); ++i)
        for (const Entry& e : rows_[i])
            if (static_cast<std::size_t>(e.index) >= in_->num_dofs())
                throw_invalid_argument("BarycentricMapping: point ", i, " uses input index ", e.index,
                                       " out of range (", in_->num_dofs(), " input DOFs)");
    Mapping::init();
}

void BarycentricMapping::map_on_tetrahedra(const MeshTopology& topo, std::span<const Vec3> x,
                                           std::span<const Vec3> points) {
    // BarycentricMapperMeshTopology::init (tetrahedra), in SOFA's operations and order, so that
    // the weights, hence the mapped positions and the forces mapped back, are SOFA's to the bit
    const auto& tetras = topo.tetrahedra();
    if (tetras.empty()) throw_invalid_argument("BarycentricMapping: topology has no tetrahedron");
    const detail::TetrahedronFrames frames(tetras, x);
    std::vector<BarycentricRow> rows(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        double best = 1e10;  // SOFA's starting distance
        Vec3 coefs = Vec3::Zero();
        std::size_t index = tetras.size();
        for (std::size_t t = 0; t < tetras.size(); ++t) {
            Vec3 v;
            const double d = frames.score(t, x[static_cast<std::size_t>(tetras[t][0])], points[i], v);
            if (d < best) {
                best = d;
                coefs = v;
                index = t;
            }
        }
        if (index == tetras.size())
            throw_invalid_argument("BarycentricMapping: point ", i,
                                   " is not finite, or 1e5 or farther from the centre of every tetrahedron (SOFA's "
                                   "search starts at a squared distance of 1e10)");
        detail::push_tetrahedron_weights(rows[i], tetras[index], coefs);
    }
    set_rows(std::move(rows));
}

void BarycentricMapping::map_on_hexahedra(const MeshTopology& topo, std::span<const Vec3> x,
                                          std::span<const Vec3> points) {
    const auto& hexas = topo.hexahedra();
    if (hexas.empty()) throw_invalid_argument("BarycentricMapping: topology has no hexahedron");
    std::vector<BarycentricRow> rows(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t h = 0; h < hexas.size(); ++h) {
            std::array<Vec3, 8> c;
            for (std::size_t k = 0; k < 8; ++k) {
                const auto p = static_cast<std::size_t>(hexas[h][k]);
                if (p >= x.size()) throw_invalid_argument("BarycentricMapping: hexahedron ", h, " vertex out of range");
                c[k] = x[p];
            }
            // Newton on φ(u) = Σ w_k(u) c_k − p, from the centre.
            Vec3 u(0.5, 0.5, 0.5);
            for (int it = 0; it < 20; ++it) {
                const auto w = trilinear_weights(u);
                Vec3 r = -points[i];
                for (std::size_t k = 0; k < 8; ++k) r += w[k] * c[k];
                const double uu = u.x(), vv = u.y(), ww = u.z();
                const Vec3 du = (1 - vv) * (1 - ww) * (c[1] - c[0]) + vv * (1 - ww) * (c[2] - c[3]) +
                                (1 - vv) * ww * (c[5] - c[4]) + vv * ww * (c[6] - c[7]);
                const Vec3 dv = (1 - uu) * (1 - ww) * (c[3] - c[0]) + uu * (1 - ww) * (c[2] - c[1]) +
                                (1 - uu) * ww * (c[7] - c[4]) + uu * ww * (c[6] - c[5]);
                const Vec3 dw = (1 - uu) * (1 - vv) * (c[4] - c[0]) + uu * (1 - vv) * (c[5] - c[1]) +
                                uu * vv * (c[6] - c[2]) + (1 - uu) * vv * (c[7] - c[3]);
                Mat3 jac;
                jac << du, dv, dw;
                if (std::abs(jac.determinant()) < 1e-300)
                    throw_invalid_argument("BarycentricMapping: hexahedron ", h, " is degenerate");
                const Vec3 step = jac.lu().solve(r);
                u -= step;
                if (step.norm() < 1e-15) break;
            }
            const double d = std::max({-u.x(), -u.y(), -u.z(), u.x() - 1, u.y() - 1, u.z() - 1});
            if (d < best) {
                best = d;
                const auto w = trilinear_weights(u);
                rows[i] = BarycentricRow{};
                for (std::size_t k = 0; k < 8; ++k) rows[i].push(hexas[h][k], w[k]);
            }
        }
    }
    set_rows(std::move(rows));
}

void BarycentricMapping::apply(std::span<Vec3> out, std::span<const Vec3> in) {
    // each output row its own: in ranges on TBB's threads from OrderedScatter::kMinElements rows
    detail::for_each_range(rows_.size(), kRowsPerTask, [&](std::size_t first, std::size_t end) {
        for (std::size_t i = first; i < end; ++i) out[i] = rows_[i].combine(in);
    });
}
namespace {
/// BarycentricRow::combine on flattened entries [first, last): s = 0, s += w_k·in[i_k] in k order.
inline Vec3 combine_flat(const std::uint32_t* index, const double* weight, std::uint32_t first, std::uint32_t last,
                         const Vec3* input) {
    double s0 = 0.0, s1 = 0.0, s2 = 0.0;
    for (std::uint32_t k = first; k < last; ++k) {
        const double w = weight[k];
        const Vec3& p = input[index[k]];
        s0 += w * p[0];
        s1 += w * p[1];
        s2 += w * p[2];
    }
    return {s0, s1, s2};
}
}  // namespace

void BarycentricMapping::apply_j(std::span<Vec3> out, std::span<const Vec3> in) const {
    const std::uint32_t* begin = row_begin_.data();
    const std::uint32_t* index = entry_index_.data();
    const double* weight = entry_weight_.data();
    const Vec3* input = in.data();
    Vec3* output = out.data();
    detail::for_each_range(rows_.size(), kRowsPerTask, [=](std::size_t first, std::size_t end) {
        for (std::size_t i = first; i < end; ++i)
            output[i] = combine_flat(index, weight, begin[i], begin[i + 1], input);
    });
}

void BarycentricMapping::apply_j_rows(std::span<Vec3> out, std::span<const Vec3> in,
                                      std::span<const std::uint32_t> rows) const {
    const std::uint32_t* begin = row_begin_.data();
    const std::uint32_t* index = entry_index_.data();
    const double* weight = entry_weight_.data();
    const Vec3* input = in.data();
    Vec3* output = out.data();
    for (const std::uint32_t i : rows) {
        PENALTY_DEMAND(i < rows_.size());
        output[i] = combine_flat(index, weight, begin[i], begin[i + 1], input);
    }
}

void BarycentricMapping::apply_dx_rows(std::span<const std::uint32_t> rows) { apply_j_rows(out_->dx, in_->dx, rows); }

bool BarycentricMapping::list_inputs_read(std::vector<std::uint32_t>& rows) const {
    rows.insert(rows.end(), used_inputs_.begin(), used_inputs_.end());
    return true;
}

void BarycentricMapping::apply_jt(std::span<Vec3> in, std::span<const Vec3> out) const {
    PENALTY_DEMAND(in.size() + 1 >= input_begin_.size() && out.size() >= rows_.size());
    // Rows whose force is ±0 in every component add only ±0 terms (w·(±0), w finite). Skipping
    // a ±0 term leaves every partial sum's value as it was and can change only the sign of a
    // zero; in round-to-nearest a sum becomes −0 only when both addends are −0, so a sum that
    // does not start at −0 ends at the same bits with or without them. Hence: when few rows carry
    // a force (a collision surface with a few contacts), scatter only those rows (each input
    // still receives its terms in (row, entry) order), and gather inputs that start at −0 in full.
    const std::size_t rows = rows_.size();
    forced_rows_.clear();
    for (std::size_t i = 0; i < rows && forced_rows_.size() * kSparseJtRatio <= rows; ++i) {
        const Vec3& f = out[i];
        if (f[0] != 0.0 || f[1] != 0.0 || f[2] != 0.0) forced_rows_.push_back(static_cast<std::uint32_t>(i));
    }
    // (the list stops growing once it is too long for the scatter: the full gather follows)
    if (forced_rows_.size() * kSparseJtRatio > rows) {
        // each input point its own gather: in ranges on TBB's threads from OrderedScatter::kMinElements
        detail::for_each_range(input_begin_.empty() ? 0 : input_begin_.size() - 1, kRowsPerTask,
                               [&](std::size_t first, std::size_t end) { gather_jt(in, out, first, end); });
        return;
    }
    scatter_forced_rows(in, out, nullptr);
}

void BarycentricMapping::apply_jt_df_rows(std::span<const std::uint32_t> rows) {
    // apply_jt with the rows outside `rows` taken as +0 (what the solver's zeroing left in them),
    // never read: only the forced rows among `rows` are scattered, and an input starting at −0
    // is gathered with +0 for the rows not counted.
    std::span<Vec3> in = in_->df;
    std::span<const Vec3> out = out_->df;
    PENALTY_DEMAND(in.size() + 1 >= input_begin_.size() && out.size() >= rows_.size());
    row_counted_.resize(rows_.size(), 0);
    forced_rows_.clear();
    for (const std::uint32_t i : rows) {
        PENALTY_DEMAND(i < rows_.size());
        row_counted_[i] = 1;
        const Vec3& f = out[i];
        if (f[0] != 0.0 || f[1] != 0.0 || f[2] != 0.0) forced_rows_.push_back(i);
    }
    scatter_forced_rows(in, out, row_counted_.data());
    for (const std::uint32_t i : rows) row_counted_[i] = 0;
}

void BarycentricMapping::scatter_forced_rows(std::span<Vec3> in, std::span<const Vec3> out,
                                             const std::uint8_t* counted) const {
    // Inputs starting at −0 in some component: their full gather, computed before the scatter
    // (from their value before it) and stored after it. −0 is the one double with the bits
    // 0x8000000000000000 (v == 0 with the sign bit set): one branch per input instead of two per
    // component, whose outcome (is it 0?) the predictor often missed.
    const auto starts_at_negative_zero = [&in](std::uint32_t j) {
        const Vec3& v = in[j];
        constexpr std::uint64_t kNegativeZero = std::uint64_t{1} << 63;
        const std::uint64_t x = std::bit_cast<std::uint64_t>(v[0]) ^ kNegativeZero;
        const std::uint64_t y = std::bit_cast<std::uint64_t>(v[1]) ^ kNegativeZero;
        const std::uint64_t z = std::bit_cast<std::uint64_t>(v[2]) ^ kNegativeZero;
        return std::min(std::min(x, y), z) == 0;
    };
    // On TBB's threads from OrderedScatter::kMinElements inputs, a first pass only asks whether
    // any input starts at −0 (seldom: the list below follows only then)
    bool any_negative_zero = true;
    if (detail::ranges_on_threads(used_inputs_.size())) {
        std::atomic<bool> found{false};
        detail::for_each_range(used_inputs_.size(), kRowsPerTask, [&](std::size_t first, std::size_t end) {
            for (std::size_t i = first; i < end; ++i)
                if (starts_at_negative_zero(used_inputs_[i])) {
                    found.store(true, std::memory_order_relaxed);
                    return;
                }
        });
        any_negative_zero = found.load();
    }
    negative_zero_inputs_.clear();
    negative_zero_sums_.clear();
    if (any_negative_zero)
        for (const std::uint32_t j : used_inputs_) {
            if (!starts_at_negative_zero(j)) continue;
            negative_zero_inputs_.push_back(j);
            negative_zero_sums_.push_back(gathered_jt(in, out, j, counted));
        }
    // BarycentricRow::spread of the forced rows, in row order
    const std::uint32_t* begin = row_begin_.data();
    const std::uint32_t* index = entry_index_.data();
    const double* weight = entry_weight_.data();
    Vec3* input = in.data();
    for (const std::uint32_t i : forced_rows_) {
        // NOLINTNEXTLINE(performance-unnecessary-copy-initialization): kept in registers while `input` is written
        const Vec3 f = out[i];
        for (std::uint32_t k = begin[i]; k < begin[i + 1]; ++k) {
            const double w = weight[k];
            Vec3& s = input[index[k]];
            s[0] += w * f[0];
            s[1] += w * f[1];
            s[2] += w * f[2];
        }
    }
    for (std::size_t n = 0; n < negative_zero_inputs_.size(); ++n)
        input[negative_zero_inputs_[n]] = negative_zero_sums_[n];
}

Vec3 BarycentricMapping::gathered_jt(std::span<const Vec3> in, std::span<const Vec3> out, std::uint32_t j,
                                     const std::uint8_t* counted) const {
    // BarycentricRow::spread's additions into in[j]: its entries in (row, entry) order; a row not
    // counted is +0
    double s0 = in[j][0], s1 = in[j][1], s2 = in[j][2];
    for (std::uint32_t k = input_begin_[j]; k < input_begin_[j + 1]; ++k) {
        const double w = input_weight_[k];
        const std::uint32_t row = input_row_[k];
        const Vec3 f = counted == nullptr || counted[row] != 0 ? out[row] : Vec3(0.0, 0.0, 0.0);
        s0 += w * f[0];
        s1 += w * f[1];
        s2 += w * f[2];
    }
    return {s0, s1, s2};
}

void BarycentricMapping::gather_jt(std::span<Vec3> in, std::span<const Vec3> out, std::size_t first,
                                   std::size_t last) const {
    // BarycentricRow::spread of every row (in[i_k] += w_k·f_i, rows in order, entries in order)
    // as a gather: each input point adds its entries in that same order, accumulated in registers
    // and stored once.
    const std::uint32_t* begin = input_begin_.data();
    const std::uint32_t* row = input_row_.data();
    const double* weight = input_weight_.data();
    Vec3* input = in.data();
    const Vec3* output = out.data();
    for (std::size_t j = first; j < last; ++j) {
        if (begin[j] == begin[j + 1]) continue;
        double s0 = input[j][0], s1 = input[j][1], s2 = input[j][2];
        for (std::uint32_t k = begin[j]; k < begin[j + 1]; ++k) {
            const double w = weight[k];
            const Vec3& f = output[row[k]];
            s0 += w * f[0];
            s1 += w * f[1];
            s2 += w * f[2];
        }
        input[j] = Vec3(s0, s1, s2);
    }
}
void BarycentricMapping::add_jacobian_triplets(TripletList& t, Index ro, Index co) const {
    for (std::size_t i = 0; i < rows_.size(); ++i) rows_[i].add_triplets(t, ro + 3 * static_cast<Index>(i), co);
}

}  // namespace penalty
