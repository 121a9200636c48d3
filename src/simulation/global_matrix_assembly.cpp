#include "penalty/simulation/global_matrix_assembly.hpp"

#include <algorithm>
#include <random>
#include <stdexcept>
#include <unordered_map>

namespace penalty {

namespace {

using RowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using IndexTriplet = Eigen::Triplet<double, int>;

/// The extended index space of an assembly: the independent scalars (SubtreeSystem's offsets),
/// then each mapped state's scalars; and P, the (extended × independent) matrix that maps the
/// independent DOFs to all of them (identity on the independent rows, the chained mapping
/// Jacobians on the mapped ones).
struct ExtendedSpace {
    std::unordered_map<const BaseState*, Index> offset;
    Index total = 0;
    RowMatrix p;
};

ExtendedSpace extended_space(const SubtreeSystem& system) {
    ExtendedSpace space;
    const auto n = static_cast<Index>(system.size());
    for (const BaseState* s : system.independent_states()) space.offset[s] = system.offset(s);
    space.total = n;
    for (const BaseState* s : system.mapped_states()) {
        space.offset[s] = space.total;
        space.total += static_cast<Index>(s->scalar_size());
    }
    // rows of P per state, parents before children (SubtreeSystem's mappings are in pre-order)
    std::unordered_map<const BaseState*, RowMatrix> rows_of;
    for (const BaseState* s : system.independent_states()) {
        const auto size = static_cast<int>(s->scalar_size());
        RowMatrix identity(size, static_cast<int>(n));
        std::vector<IndexTriplet> t;
        t.reserve(static_cast<std::size_t>(size));
        for (int j = 0; j < size; ++j) t.emplace_back(j, static_cast<int>(system.offset(s)) + j, 1.0);
        identity.setFromTriplets(t.begin(), t.end());
        rows_of.emplace(s, std::move(identity));
    }
    for (const BaseMapping* map : system.mappings()) {
        const auto out = static_cast<int>(map->to()->scalar_size());
        const auto it = rows_of.find(map->from());
        if (it == rows_of.end()) {  // mapped from outside the subtree: dx 0
            rows_of.emplace(map->to(), RowMatrix(out, static_cast<int>(n)));
            continue;
        }
        TripletList jt;
        map->add_jacobian_triplets(jt, 0, 0);
        RowMatrix j(out, static_cast<int>(map->from()->scalar_size()));
        j.setFromTriplets(jt.begin(), jt.end());
        rows_of.emplace(map->to(), RowMatrix(j * it->second));
    }
    std::vector<IndexTriplet> t;
    for (const auto& [state, rows] : rows_of) {
        const auto o = static_cast<int>(space.offset.at(state));
        for (int r = 0; r < rows.outerSize(); ++r)
            for (RowMatrix::InnerIterator it(rows, r); it; ++it)
                t.emplace_back(o + r, static_cast<int>(it.col()), it.value());
    }
    space.p.resize(static_cast<int>(space.total), static_cast<int>(n));
    space.p.setFromTriplets(t.begin(), t.end());
    return space;
}

/// out = the sum of the triplets (setFromTriplets). Kept from the previous call when possible: the
/// same (row, column) sequence adds each value at its recorded slot; else, when out's pattern has
/// a place for each triplet, they are found by binary search; else the matrix is built anew. The
/// values are summed from 0 in triplet order either way (setFromTriplets' order: the same bits),
/// and places of the pattern no triplet names stay 0.
void fill_from_triplets(const TripletList& x, Index size, ColumnSparseMatrix& out, AssemblyWorkspace& w) {
    const bool same_sequence =
        w.positions.size() == x.size() && out.rows() == size && out.isCompressed() &&
        out.nonZeros() == w.slots_nonzeros &&
        std::equal(x.begin(), x.end(), w.positions.begin(), [](const Triplet& t, const std::pair<Index, Index>& p) {
            return t.row() == p.first && t.col() == p.second;
        });
    if (same_sequence) {
        double* values = out.valuePtr();
        std::fill(values, values + out.nonZeros(), 0.0);
        for (std::size_t i = 0; i < x.size(); ++i) values[w.slots[i]] += x[i].value();
        return;
    }
    const auto find_slots = [&]() {
        const int* outer = out.outerIndexPtr();
        const int* inner = out.innerIndexPtr();
        w.slots.resize(x.size());
        for (std::size_t i = 0; i < x.size(); ++i) {
            const int* begin = inner + outer[x[i].col()];
            const int* end = inner + outer[x[i].col() + 1];
            const int* at = std::lower_bound(begin, end, static_cast<int>(x[i].row()));
            if (at == end || *at != x[i].row()) return false;
            w.slots[i] = static_cast<int>(at - inner);
        }
        return true;
    };
    const bool reuse =
        out.rows() == size && out.cols() == size && out.isCompressed() && out.nonZeros() > 0 && find_slots();
    if (!reuse) {
        out.resize(static_cast<int>(size), static_cast<int>(size));
        out.setFromTriplets(x.begin(), x.end());
        out.makeCompressed();
        if (!find_slots()) throw std::logic_error("fill_from_triplets: a triplet has no place in its own pattern");
    }
    w.positions.resize(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) w.positions[i] = {x[i].row(), x[i].col()};
    w.slots_nonzeros = out.nonZeros();
    double* values = out.valuePtr();
    std::fill(values, values + out.nonZeros(), 0.0);
    for (std::size_t i = 0; i < x.size(); ++i) values[w.slots[i]] += x[i].value();
}

}  // namespace

ColumnSparseMatrix assemble_mbk_matrix(const SubtreeSystem& system, double m, double b, double k,
                                       const MatrixAssemblyOptions& options) {
    AssemblyWorkspace workspace;
    ColumnSparseMatrix out;
    assemble_mbk_matrix(system, m, b, k, options, workspace, out);
    return out;
}

void assemble_mbk_matrix(const SubtreeSystem& system, double m, double b, double k,
                         const MatrixAssemblyOptions& options, AssemblyWorkspace& workspace, ColumnSparseMatrix& out) {
    const auto n = static_cast<Index>(system.size());
    const bool mapped = options.apply_mapped_components && !system.mapped_states().empty();
    ExtendedSpace space;
    if (mapped) {
        space = extended_space(system);
    } else {
        for (const BaseState* s : system.independent_states()) space.offset[s] = system.offset(s);
        space.total = n;
    }
    const StateOffsets offsets = [&space](const BaseState* s) {
        const auto it = space.offset.find(s);
        return it == space.offset.end() ? space.total : it->second;
    };
    TripletList& x = workspace.triplets;
    x.clear();
    for (const BaseForceField* ff : system.force_fields()) {
        if (options.assemble_stiffness && k != 0.0) ff->add_stiffness(x, offsets, k);
        if (options.assemble_damping && b != 0.0) ff->add_damping(x, offsets, b);
    }
    if (options.assemble_mass && m != 0.0)
        for (const auto& entry : system.masses()) {
            const Index o = offsets(entry.first->state());
            if (o < space.total) entry.first->add_mass_triplets(x, o, m);
        }
    // a triplet on a state outside the subtree (offset past the end) is dropped (dx 0 there)
    const Index total = space.total;
    x.erase(
        std::remove_if(x.begin(), x.end(), [total](const Triplet& t) { return t.row() >= total || t.col() >= total; }),
        x.end());
    if (!mapped) {
        fill_from_triplets(x, total, out, workspace);
        return;
    }
    fill_from_triplets(x, total, workspace.extended, workspace);
    const ColumnSparseMatrix p(space.p);
    const ColumnSparseMatrix pt(space.p.transpose());
    out = ColumnSparseMatrix(pt * workspace.extended * p);
}

void apply_projective_constraints(const SubtreeSystem& system, ColumnSparseMatrix& a) {
    const auto n = static_cast<Index>(system.size());
    std::vector<char> discarded(static_cast<std::size_t>(n), 0);
    bool any_discarded = false;
    std::vector<IndexTriplet> projector;  // the generic constraints' P − I, block by block
    std::vector<Index> rows;
    std::mt19937 random(20261127u);
    std::uniform_real_distribution<double> weight(0.5, 2.0);
    for (const BaseProjectiveConstraint* c : system.constraints()) {
        const BaseState* s = c->state();
        const Index o = system.offset(s);
        if (o >= n) continue;  // on a mapped state: SubtreeSystem::project does not apply it either
        rows.clear();
        if (c->list_discarded_rows(rows)) {
            for (Index r : rows) {
                if (r < 0 || r >= Index(s->scalar_size()))
                    throw std::logic_error("apply_projective_constraints: a discarded row is outside its state");
                discarded[static_cast<std::size_t>(o + r)] = 1;
            }
            any_discarded = any_discarded || !rows.empty();
            continue;
        }
        // P's blocks from w probes (component c of every DOF), checked on a random vector.
        const Index width = s->deriv_size();
        const auto size = static_cast<Eigen::Index>(s->scalar_size());
        std::vector<Eigen::VectorXd> columns;
        for (Index col = 0; col < width; ++col) {
            Eigen::VectorXd probe = Eigen::VectorXd::Zero(size);
            for (Eigen::Index i = col; i < size; i += width) probe[i] = 1.0;
            c->project_response(probe);
            columns.push_back(std::move(probe));
        }
        Eigen::VectorXd check(size);
        for (Eigen::Index i = 0; i < size; ++i) check[i] = weight(random);
        Eigen::VectorXd expected = Eigen::VectorXd::Zero(size);
        for (Eigen::Index dof = 0; dof < size / width; ++dof)
            for (Index col = 0; col < width; ++col)
                expected.segment(dof * width, width) +=
                    columns[static_cast<std::size_t>(col)].segment(dof * width, width) * check[dof * width + col];
        c->project_response(check);
        if (!(check - expected).isZero(1e-12 * std::max(1.0, expected.lpNorm<Eigen::Infinity>())))
            throw std::logic_error(
                "apply_projective_constraints: a projective constraint couples DOFs; its matrix form "
                "is not supported");
        for (Eigen::Index dof = 0; dof < size / width; ++dof)
            for (Index col = 0; col < width; ++col)
                for (Index row = 0; row < width; ++row) {
                    const double pv = columns[static_cast<std::size_t>(col)][dof * width + row];
                    const double identity = row == col ? 1.0 : 0.0;
                    if (pv == identity) continue;
                    projector.emplace_back(static_cast<int>(o + dof * width + row),
                                           static_cast<int>(o + dof * width + col), pv - identity);
                }
    }
    if (!projector.empty()) {
        // A ← P·A·P + (I − P), P = I + D
        ColumnSparseMatrix d(a.rows(), a.cols());
        d.setFromTriplets(projector.begin(), projector.end());
        ColumnSparseMatrix identity(a.rows(), a.cols());
        identity.setIdentity();
        const ColumnSparseMatrix p = identity + d;
        a = ColumnSparseMatrix(p * a * p) - d;
    }
    if (!any_discarded) return;
    // MatrixLinearSystem::Dirichlet::discardRowCol: row and column cleared, 1 on the diagonal.
    for (int col = 0; col < a.outerSize(); ++col)
        for (ColumnSparseMatrix::InnerIterator it(a, col); it; ++it)
            if (discarded[static_cast<std::size_t>(it.row())] || discarded[static_cast<std::size_t>(col)])
                it.valueRef() = it.row() == col ? 1.0 : 0.0;
    // a discarded diagonal absent from the pattern (no mass, no stiffness there) gets its 1
    std::vector<IndexTriplet> ones;
    for (int r = 0; r < int(n); ++r)
        if (discarded[static_cast<std::size_t>(r)] && a.coeff(r, r) != 1.0) ones.emplace_back(r, r, 1.0);
    if (!ones.empty()) {
        ColumnSparseMatrix extra(a.rows(), a.cols());
        extra.setFromTriplets(ones.begin(), ones.end());
        a += extra;
    }
}

}  // namespace penalty
