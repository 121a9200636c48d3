#pragma once
/// @file
/// SOFA's direct linear solvers (SparseLDLSolver, EigenSimplicialLDLT, EigenSimplicialLLT,
/// EigenSparseLU, EigenSparseQR, ...): the ODE solver's A = m·M + b·B + k·K assembled
/// (global_matrix_assembly.hpp) and factorized by Eigen's sparse factorizations.

#include "penalty/simulation/global_matrix_assembly.hpp"

#include <Eigen/Core>

#include <memory>
#include <string_view>

namespace penalty {

/// The factorization: LDLᵀ (symmetric, SparseLDLSolver's), LLᵀ (symmetric positive definite),
/// LU with partial pivoting (any square matrix), QR (any matrix, least squares).
enum class FactorizationMethod { ldlt, llt, lu, qr };

/// The fill-reducing permutation (SOFA's AMDOrderingMethod, COLAMDOrderingMethod,
/// NaturalOrderingMethod; SOFA's default is AMD, computed with Eigen's AMD as here).
enum class FillOrdering { amd, colamd, natural };

[[nodiscard]] std::string_view factorization_name(FactorizationMethod method);
[[nodiscard]] std::string_view ordering_name(FillOrdering ordering);

/// A direct solve of one subtree's system. Each solve assembles A (the matrix changes with the
/// positions and contacts), applies the projective constraints, factorizes and solves; the
/// symbolic analysis (ordering, elimination tree) is kept while A's sparsity pattern stays the
/// same (SparseLDLSolver's precomputeSymbolicDecomposition, default on).
class DirectLinearSolver {
public:
    DirectLinearSolver();
    ~DirectLinearSolver();
    DirectLinearSolver(const DirectLinearSolver&) = delete;
    DirectLinearSolver& operator=(const DirectLinearSolver&) = delete;

    FactorizationMethod method = FactorizationMethod::ldlt;
    FillOrdering ordering = FillOrdering::amd;
    MatrixAssemblyOptions assembly;
    bool reuse_symbolic = true;

    /// x = A⁻¹·rhs with A = m·M + b·B + k·K of `system`, projected (rhs must already be
    /// projected, as the ODE solvers do). Throws NonFiniteSolveError when the factorization
    /// fails (a singular matrix: e.g. a DOF without mass nor stiffness) or x is not finite.
    void solve(const SubtreeSystem& system, double m, double b, double k, const Eigen::VectorXd& rhs,
               Eigen::VectorXd& x);

    /// Solves so far, symbolic analyses among them, and the non-zeros of the last matrix.
    [[nodiscard]] int factorizations() const { return factorizations_; }
    [[nodiscard]] int symbolic_analyses() const { return analyses_; }
    [[nodiscard]] const ColumnSparseMatrix& last_matrix() const { return matrix_; }

private:
    struct Factorization;
    std::unique_ptr<Factorization> factorization_;
    AssemblyWorkspace workspace_;
    ColumnSparseMatrix matrix_;
    int factorizations_ = 0;
    int analyses_ = 0;
};

/// The linear solver an ODE solver of this library runs: SOFA's matrix-free CGLinearSolver, or a
/// direct one when `direct` is set.
struct LinearSolverChoice {
    CGLinearSolver cg;
    std::shared_ptr<DirectLinearSolver> direct;
    /// x = A⁻¹·rhs, A = m·M + b·B + k·K projected; the CG's statistics (empty for a direct solve).
    CgStats solve(const SubtreeSystem& system, double m, double b, double k, const Eigen::VectorXd& rhs,
                  Eigen::VectorXd& x);
};

}  // namespace penalty
