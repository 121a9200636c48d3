// SofaPython3's views of a solve's linear system (Sofa.SofaLinearSystem's A()/b()/x(), the
// get_system_matrix/get_rhs_vector/get_solution_vector aliases, Sofa.SofaLinearSolver's A()/b()/x()):
// the A·x = b of the last step's solve of the EulerImplicitSolver above the component, as SOFA's
// TypedMatrixLinearSystem holds it after MatrixLinearSystem::assembleSystem.
#include "py_scene.hpp"

#include "penalty/io/error.hpp"
#include "penalty/scene/components.hpp"
#include "penalty/simulation/direct_linear_solver.hpp"
#include "penalty/simulation/global_matrix_assembly.hpp"
#include "penalty/simulation/ode_solver.hpp"

#include <pybind11/stl.h>

namespace penalty::python {

namespace {

using RowSparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

/// A as scipy.sparse.csr_matrix; entries that are exactly 0 are left out, as SofaPython3's
/// conversion does (CompressedRowSparseMatrix::copyNonZeros before the Eigen map).
py::object to_csr(const ColumnSparseMatrix& a) {
    RowSparseMatrix m(a);
    m.prune(0.0, 0.0);
    m.makeCompressed();
    const auto nnz = py::ssize_t(m.nonZeros());
    py::array_t<double> data(nnz);
    py::array_t<std::int32_t> indices(nnz), indptr(py::ssize_t(m.rows() + 1));
    std::copy(m.valuePtr(), m.valuePtr() + nnz, data.mutable_data());
    std::copy(m.innerIndexPtr(), m.innerIndexPtr() + nnz, indices.mutable_data());
    std::copy(m.outerIndexPtr(), m.outerIndexPtr() + m.rows() + 1, indptr.mutable_data());
    py::object csr = py::module_::import("scipy.sparse").attr("csr_matrix");
    return csr(py::make_tuple(data, indices, indptr), py::arg("shape") = py::make_tuple(m.rows(), m.cols()));
}

py::array_t<double> to_array(const Eigen::VectorXd& v) {
    py::array_t<double> out(py::ssize_t(v.size()));
    std::copy(v.data(), v.data() + v.size(), out.mutable_data());
    return out;
}

/// The EulerImplicitSolver whose subtree holds the component (its node or the nearest ancestor
/// with one: SOFA's solver visits the linear systems of its context), and its node.
std::pair<EulerImplicitSolver*, const Node*> solver_above(scene::Scene& s, const std::string& path) {
    const auto* c = static_cast<const io::SceneComponent*>(s.find_element({path, false}));
    if (c == nullptr) throw py::key_error("no component '" + path + "'");
    for (const Node* node = s.node_of(*c->node); node != nullptr; node = node->parent())
        if (auto* euler = dynamic_cast<EulerImplicitSolver*>(node->ode_solver())) return {euler, node};
    throw py::value_error(c->describe() +
                          ": no EulerImplicitSolver in its node or above it solves a linear system (penalty keeps the "
                          "systems of EulerImplicitSolver's solves)");
}

/// {"A": csr or dense, "b": array, "x": array, "m", "b_factor", "k"} of the last solve, the matrix
/// assembled with `options` (a MatrixLinearSystem's assemble* and applyProjectiveConstraints); the
/// direct solver's own matrix when `solved` and the solve was direct (the same bits it factorized).
py::dict linear_system(scene::Scene& s, const std::string& path, const MatrixAssemblyOptions& options, bool solved,
                       bool dense) {
    auto [euler, node] = solver_above(s, path);
    const auto* system = euler->system_cache().current();
    const EulerImplicitSolver::LinearSolveRecord& f = euler->last_linear_solve();
    py::dict out;
    out["m"] = f.m;
    out["b_factor"] = f.b;
    out["k"] = f.k;
    if (system == nullptr || euler->last_rhs().size() == 0) {
        // before the first step (or after a Newton step): SOFA's system is not assembled yet
        out["A"] = py::none();
        out["b"] = py::array_t<double>(0);
        out["x"] = py::array_t<double>(0);
        return out;
    }
    ColumnSparseMatrix a;
    if (solved && euler->direct_solver && euler->direct_solver->last_matrix().rows() == euler->last_rhs().size()) {
        a = euler->direct_solver->last_matrix();
    } else {
        a = assemble_mbk_matrix(*system, f.m, f.b, f.k, options);
        if (options.apply_projective_constraints) apply_projective_constraints(*system, a);
    }
    if (dense) {
        const Eigen::MatrixXd full(a);
        py::array_t<double> d({py::ssize_t(full.rows()), py::ssize_t(full.cols())});
        auto w = d.mutable_unchecked<2>();
        for (Eigen::Index i = 0; i < full.rows(); ++i)
            for (Eigen::Index j = 0; j < full.cols(); ++j) w(i, j) = full(i, j);
        out["A"] = d;
    } else {
        out["A"] = to_csr(a);
    }
    out["b"] = solved ? to_array(euler->last_rhs()) : py::array_t<double>(0);
    out["x"] = solved ? to_array(euler->last_solution()) : py::array_t<double>(0);
    return out;
}

}  // namespace

void bind_linear_system(py::module_& m) {
    auto cls = py::reinterpret_borrow<py::class_<PyScene>>(m.attr("Scene"));
    cls.def(
        "_linear_system",
        [](PyScene& s, const std::string& path, bool mass, bool damping, bool stiffness, bool projective, bool mapped,
           bool solved, bool dense) {
            MatrixAssemblyOptions o;
            o.assemble_mass = mass;
            o.assemble_damping = damping;
            o.assemble_stiffness = stiffness;
            o.apply_projective_constraints = projective;
            o.apply_mapped_components = mapped;
            return linear_system(*s.scene, path, o, solved, dense);
        },
        py::arg("path"), py::arg("mass") = true, py::arg("damping") = true, py::arg("stiffness") = true,
        py::arg("projective") = true, py::arg("mapped") = true, py::arg("solved") = true, py::arg("dense") = false,
        "The last solve's linear system A·x = b seen from the component at `path` (SofaPython3's linear system and "
        "linear solver views)");
}

}  // namespace penalty::python
