#include "penalty/simulation/direct_linear_solver.hpp"
#include "penalty/simulation/solve_error.hpp"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <Eigen/SparseQR>

#include <string>
#include <variant>

namespace penalty {

std::string_view factorization_name(FactorizationMethod method) {
    switch (method) {
        case FactorizationMethod::ldlt:
            return "LDLT";
        case FactorizationMethod::llt:
            return "LLT";
        case FactorizationMethod::lu:
            return "LU";
        case FactorizationMethod::qr:
            return "QR";
    }
    return "?";
}

std::string_view ordering_name(FillOrdering ordering) {
    switch (ordering) {
        case FillOrdering::amd:
            return "AMD";
        case FillOrdering::colamd:
            return "COLAMD";
        case FillOrdering::natural:
            return "natural";
    }
    return "?";
}

namespace {

using Amd = Eigen::AMDOrdering<int>;
using Colamd = Eigen::COLAMDOrdering<int>;
using Natural = Eigen::NaturalOrdering<int>;
template <class Ordering>
using Ldlt = Eigen::SimplicialLDLT<ColumnSparseMatrix, Eigen::Lower, Ordering>;
template <class Ordering>
using Llt = Eigen::SimplicialLLT<ColumnSparseMatrix, Eigen::Lower, Ordering>;
template <class Ordering>
using Lu = Eigen::SparseLU<ColumnSparseMatrix, Ordering>;
template <class Ordering>
using Qr = Eigen::SparseQR<ColumnSparseMatrix, Ordering>;

}  // namespace

/// One of Eigen's factorizations, with the pattern its symbolic analysis was made for.
struct DirectLinearSolver::Factorization {
    std::variant<Ldlt<Amd>, Ldlt<Colamd>, Ldlt<Natural>, Llt<Amd>, Llt<Colamd>, Llt<Natural>, Lu<Amd>, Lu<Colamd>,
                 Lu<Natural>, Qr<Amd>, Qr<Colamd>, Qr<Natural>>
        solver;
    FactorizationMethod method;
    FillOrdering ordering;
    std::vector<int> outer;  ///< the analysed pattern (column starts, row indices)
    std::vector<int> inner;

    Factorization(FactorizationMethod m, FillOrdering o) : method(m), ordering(o) {
        const int index = 3 * static_cast<int>(m) + static_cast<int>(o);
        emplace(index);
    }
    void emplace(int index) {
        switch (index) {
            case 0:
                solver.emplace<Ldlt<Amd>>();
                break;
            case 1:
                solver.emplace<Ldlt<Colamd>>();
                break;
            case 2:
                solver.emplace<Ldlt<Natural>>();
                break;
            case 3:
                solver.emplace<Llt<Amd>>();
                break;
            case 4:
                solver.emplace<Llt<Colamd>>();
                break;
            case 5:
                solver.emplace<Llt<Natural>>();
                break;
            case 6:
                solver.emplace<Lu<Amd>>();
                break;
            case 7:
                solver.emplace<Lu<Colamd>>();
                break;
            case 8:
                solver.emplace<Lu<Natural>>();
                break;
            case 9:
                solver.emplace<Qr<Amd>>();
                break;
            case 10:
                solver.emplace<Qr<Colamd>>();
                break;
            default:
                solver.emplace<Qr<Natural>>();
                break;
        }
    }
    [[nodiscard]] bool same_pattern(const ColumnSparseMatrix& a) const {
        return outer.size() == std::size_t(a.outerSize() + 1) && inner.size() == std::size_t(a.nonZeros()) &&
               std::equal(outer.begin(), outer.end(), a.outerIndexPtr()) &&
               std::equal(inner.begin(), inner.end(), a.innerIndexPtr());
    }
    void remember_pattern(const ColumnSparseMatrix& a) {
        outer.assign(a.outerIndexPtr(), a.outerIndexPtr() + a.outerSize() + 1);
        inner.assign(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros());
    }
};

DirectLinearSolver::DirectLinearSolver() = default;
DirectLinearSolver::~DirectLinearSolver() = default;

void DirectLinearSolver::solve(const SubtreeSystem& system, double m, double b, double k, const Eigen::VectorXd& rhs,
                               Eigen::VectorXd& x) {
    assemble_mbk_matrix(system, m, b, k, assembly, workspace_, matrix_);
    if (assembly.apply_projective_constraints) apply_projective_constraints(system, matrix_);
    matrix_.makeCompressed();
    // a system without a stored entry (no mass, stiffness nor constraint in the subtree) is
    // singular; Eigen's SparseLU would never return on it (memInit: a zero-sized estimate retried)
    if (matrix_.rows() > 0 && matrix_.nonZeros() == 0)
        throw SingularSystemError(std::string("direct linear solver (") + std::string(factorization_name(method)) +
                                      "): the system matrix is zero: its " + std::to_string(matrix_.rows()) +
                                      " unknowns have no mass, stiffness nor constraint (give their states a mass)",
                                  this);
    if (!factorization_ || factorization_->method != method || factorization_->ordering != ordering)
        factorization_ = std::make_unique<Factorization>(method, ordering);
    Factorization& f = *factorization_;
    const bool analyse = !reuse_symbolic || !f.same_pattern(matrix_);
    bool ok = true;
    std::visit(
        [&](auto& solver) {
            if (analyse) solver.analyzePattern(matrix_);
            solver.factorize(matrix_);
            ok = solver.info() == Eigen::Success;
            if (ok) x = solver.solve(rhs);
        },
        f.solver);
    if (analyse) {
        f.remember_pattern(matrix_);
        ++analyses_;
    }
    ++factorizations_;
    if (!ok) {
        f.outer.clear();  // analyse again at the next solve
        // a finite matrix that does not factorize is singular: a defect of the scene, as a zero one
        const bool finite = Eigen::Map<const Eigen::VectorXd>(matrix_.valuePtr(), matrix_.nonZeros()).allFinite();
        const std::string what = std::string("direct linear solver (") + std::string(factorization_name(method)) +
                                 "): the factorization failed: ";
        if (finite)
            throw SingularSystemError(
                what + "the system matrix is singular (a DOF without mass, stiffness nor constraint?)", this);
        throw NonFiniteSolveError(what + "the system matrix is not finite", nullptr, nullptr, nullptr);
    }
    if (!x.allFinite())
        throw NonFiniteSolveError(std::string("direct linear solver (") + std::string(factorization_name(method)) +
                                      "): the solution is not finite (singular or overflowing system)",
                                  nullptr, nullptr, nullptr);
}

CgStats LinearSolverChoice::solve(const SubtreeSystem& system, double m, double b, double k, const Eigen::VectorXd& rhs,
                                  Eigen::VectorXd& x) {
    if (direct) {
        direct->solve(system, m, b, k, rhs, x);
        return {};
    }
    MbkCgSystem cg_system(system, m, b, k);
    return cg.solve(cg_system, rhs, x);
}

}  // namespace penalty
