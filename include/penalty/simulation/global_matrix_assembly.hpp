#pragma once
/// @file
/// The assembled matrix of a solver subtree, as SOFA's MatrixLinearSystem builds it for a direct
/// linear solver: A = m·M + b·B + k·K over the independent DOFs, the components of mapped states
/// brought in through the mappings' Jacobians (Jᵀ·X·J, MatrixLinearSystem::assembleMappedMatrices),
/// then the projective constraints (MatrixLinearSystem::applyProjectiveConstraints).

#include "penalty/simulation/solver.hpp"

#include <Eigen/SparseCore>

namespace penalty {

/// Column-major sparse matrix, the layout of Eigen's factorizations.
using ColumnSparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

/// What an assembly takes (SOFA's MatrixLinearSystem data of the same names).
struct MatrixAssemblyOptions {
    bool assemble_mass = true;                 ///< assembleMass
    bool assemble_stiffness = true;            ///< assembleStiffness
    bool assemble_damping = true;              ///< assembleDamping
    bool apply_mapped_components = true;       ///< applyMappedComponents: fields and masses of mapped states
    bool apply_projective_constraints = true;  ///< applyProjectiveConstraints
};

/// Buffers an assembly reuses from one call to the next (a solver assembles at every step: the
/// triplets of a few thousand elements are megabytes, allocated and returned to the system each
/// time without it).
struct AssemblyWorkspace {
    TripletList triplets;
    ColumnSparseMatrix extended;  ///< the mapped states' space, before Jᵀ·X·J
    /// The last triplets' (row, column) sequence and the value slot of each in the matrix's
    /// pattern: while the fields emit the same sequence (SOFA's ConstantSparsityPatternSystem
    /// idea), a value goes straight to its slot.
    std::vector<std::pair<Index, Index>> positions;
    std::vector<int> slots;
    Eigen::Index slots_nonzeros = -1;  ///< the pattern's size the slots point into
};

/// m·M + b·B + k·K of `system` (its independent DOFs, SubtreeSystem's offsets), the contributions
/// of the mapped states as Jᵀ X J with J the chained Jacobians of the mappings (a state mapped
/// from outside the subtree contributes nothing: its dx is 0). States outside the subtree (a
/// static floor) are dropped, as their dx is 0 in the matrix-free product. Constraints are not
/// applied. Equals, column by column, SubtreeSystem::apply_mbk(e_j, ·, m, b, k, false).
[[nodiscard]] ColumnSparseMatrix assemble_mbk_matrix(const SubtreeSystem& system, double m, double b, double k,
                                                     const MatrixAssemblyOptions& options = {});
/// The same into `out`, with `workspace`'s buffers.
void assemble_mbk_matrix(const SubtreeSystem& system, double m, double b, double k,
                         const MatrixAssemblyOptions& options, AssemblyWorkspace& workspace, ColumnSparseMatrix& out);

/// Applies the subtree's projective constraints to an assembled matrix: a constraint that lists
/// discarded rows (BaseProjectiveConstraint::list_discarded_rows: SOFA's ZeroDirichletCondition)
/// clears those rows and columns and puts 1 on their diagonal; any other applies as the
/// projector P it is (SubtreeSystem::project's action on its state), A ← P·A·P + (I − P). With a
/// right-hand side projected by P, A·x = b then gives x = P·x, the solution the projected CG
/// converges to. P is found from the constraint's action on three (six) probe vectors, each
/// DOF's block of P from the probe's components there, checked against a fourth probe
/// (std::logic_error when P couples DOFs: not a per-DOF projection).
void apply_projective_constraints(const SubtreeSystem& system, ColumnSparseMatrix& a);

}  // namespace penalty
