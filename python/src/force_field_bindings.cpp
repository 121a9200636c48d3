// penalty.PenaltyForceField: the force field alone, vectorised over numpy arrays.
#include "bindings.hpp"

#include "penalty/response/penalty_force_field.hpp"

#include <pybind11/stl.h>

#include <cmath>
#include <string>

namespace penalty::python {

namespace {

using Points = py::array_t<double, py::array::c_style | py::array::forcecast>;

ConstVec3Span span_of(const Points& a) { return {reinterpret_cast<const Vec3*>(a.data()), std::size_t(a.shape(0))}; }
Vec3Span span_of(Points& a) { return {reinterpret_cast<Vec3*>(a.mutable_data()), std::size_t(a.shape(0))}; }

Points zeros_like(const Points& a) {
    Points out({a.shape(0), py::ssize_t(3)});
    std::fill(out.mutable_data(), out.mutable_data() + out.size(), 0.0);
    return out;
}

/// Scalar or length-n array, broadcast to n values (finiteness and ranges: add_contact's checks).
std::vector<double> broadcast(const py::handle& v, std::size_t n, const char* what) {
    (void)numeric_kind(v, what);
    const auto a = numbers_array<double>(v, what);
    if (a.ndim() == 0 || a.size() == 1) return std::vector<double>(n, *a.data());
    if (a.ndim() != 1 || std::size_t(a.shape(0)) != n)
        throw py::value_error(std::string(what) + ": expected a number or " + std::to_string(n) + " values");
    return {a.data(), a.data() + n};
}

std::vector<Index> broadcast_index(const py::handle& v, std::size_t n, const char* what) {
    const auto a = as_indices(v, what);
    if (a.ndim() == 0 || (a.size() == 1 && n != 0)) return std::vector<Index>(n, *a.data());
    if (a.ndim() != 1 || std::size_t(a.shape(0)) != n)
        throw py::value_error(std::string(what) + ": expected an integer or " + std::to_string(n) + " values");
    return {a.data(), a.data() + n};
}

/// Most DOFs of a state the matrices are built for (10⁸: 2.4 GB of row pointers already).
constexpr Index kMaxMatrixDofs = 100'000'000;

/// n1 and n2 of stiffness_matrix / damping_matrix: whole numbers in [0, kMaxMatrixDofs].
void check_matrix_size(const char* function, const char* what, Index n) {
    if (n < 0 || n > kMaxMatrixDofs)
        throw py::value_error(std::string(function) + ": " + what + " = " + std::to_string(n) +
                              " is out of range (0 to 100000000 DOFs)");
}

void check_factor(const char* what, double value) {
    if (!std::isfinite(value)) throw py::value_error(std::string("add_dforce: ") + what + " must be finite");
}

py::object to_csr(const SparseMatrix& k) {
    SparseMatrix m = k;
    m.makeCompressed();
    const auto nnz = py::ssize_t(m.nonZeros());
    py::array_t<double> data(nnz);
    py::array_t<std::int64_t> indices(nnz), indptr(py::ssize_t(m.rows() + 1));
    std::copy(m.valuePtr(), m.valuePtr() + nnz, data.mutable_data());
    std::copy(m.innerIndexPtr(), m.innerIndexPtr() + nnz, indices.mutable_data());
    std::copy(m.outerIndexPtr(), m.outerIndexPtr() + m.rows() + 1, indptr.mutable_data());
    py::object csr = py::module_::import("scipy.sparse").attr("csr_matrix");
    return csr(py::make_tuple(data, indices, indptr), py::arg("shape") = py::make_tuple(m.rows(), m.cols()));
}

PenaltyParameters parameters_from(double damping, const py::object& friction, double tangential_stiffness_ratio,
                                  double tangential_damping, double time_step) {
    PenaltyParameters p;
    p.damping = damping;
    if (py::isinstance<py::bool_>(friction)) {
        p.friction = friction.cast<bool>() ? FrictionModel::coulomb : FrictionModel::ignored;
    } else if (!py::isinstance<py::str>(friction)) {
        throw py::type_error("friction: expected True/False, 'coulomb' or 'ignored'");
    } else {
        const auto name = friction.cast<std::string>();
        if (name == "coulomb") p.friction = FrictionModel::coulomb;
        else if (name == "ignored" || name == "none") p.friction = FrictionModel::ignored;
        else throw py::value_error("friction: expected True/False, 'coulomb' or 'ignored', found '" + name + "'");
    }
    p.tangential_stiffness_ratio = tangential_stiffness_ratio;
    p.tangential_damping = tangential_damping;
    p.time_step = time_step;
    p.validate();
    return p;
}

}  // namespace

void bind_force_field(py::module_& m) {
    py::class_<PenaltyForceField>(m, "PenaltyForceField",
                                  "SOFA's PenalityContactForceField<Vec3> between two point sets (or one): "
                                  "f2 += ks*pen*n, f1 -= ks*pen*n with pen = dist - (x2 - x1).n")
        .def(py::init([](double damping, const py::object& friction, double tangential_stiffness_ratio,
                         double tangential_damping, double time_step) {
                 return PenaltyForceField(
                     parameters_from(damping, friction, tangential_stiffness_ratio, tangential_damping, time_step));
             }),
             py::kw_only(), py::arg("damping") = 0.0, py::arg("friction") = false,
             py::arg("tangential_stiffness_ratio") = 1.0, py::arg("tangential_damping") = 0.0,
             py::arg("time_step") = 0.01)
        .def_property_readonly("damping", [](const PenaltyForceField& f) { return f.parameters().damping; })
        .def_property_readonly(
            "friction", [](const PenaltyForceField& f) { return f.parameters().friction == FrictionModel::coulomb; })
        .def(
            "clear", [](PenaltyForceField& f) { f.clear(); },
            "Moves the contacts to the previous list (for add_contacts' old_index) and empties the list")
        .def("renew_contacts", &PenaltyForceField::renew_contacts)
        .def(
            "add_contacts",
            [](PenaltyForceField& f, const py::handle& m1, const py::handle& m2, const py::handle& normals,
               const py::handle& dist, const py::handle& ks, const py::handle& element1, const py::handle& element2,
               const py::handle& mu_s, const py::handle& mu_v, const py::handle& old_index) {
                const Points n = as_points(normals, "normals");
                const std::size_t count = std::size_t(n.shape(0));
                const auto i1 = broadcast_index(m1, count, "m1"), i2 = broadcast_index(m2, count, "m2");
                const auto e1 = element1.is_none() ? i1 : broadcast_index(element1, count, "element1");
                const auto e2 = element2.is_none() ? i2 : broadcast_index(element2, count, "element2");
                const auto d = broadcast(dist, count, "dist"), k = broadcast(ks, count, "ks");
                const auto ms = broadcast(mu_s, count, "mu_s"), mv = broadcast(mu_v, count, "mu_v");
                const auto old = broadcast_index(old_index, count, "old_index");
                const auto span = span_of(n);
                for (std::size_t i = 0; i < count; ++i)
                    f.add_contact(DofIndex(i1[i]), DofIndex(i2[i]), ElementIndex(e1[i]), ElementIndex(e2[i]), span[i],
                                  d[i], k[i], ms[i], mv[i], old[i]);
            },
            py::arg("m1"), py::arg("m2"), py::arg("normals"), py::arg("dist"), py::arg("ks"), py::kw_only(),
            py::arg("element1") = py::none(), py::arg("element2") = py::none(), py::arg("mu_s") = 0.0,
            py::arg("mu_v") = 0.0, py::arg("old_index") = 0,
            "Appends one contact per row of normals (unit, side 1 -> side 2); scalars broadcast. "
            "old_index is 1-based into the previous list (0 = new contact)")
        .def(
            "add_force",
            [](PenaltyForceField& f, const py::handle& x1, const py::handle& x2, const py::handle& v1,
               const py::handle& v2) -> py::object {
                const Points p1 = as_points(x1, "x1");
                const bool same = x2.is_none();
                const Points p2 = same ? p1 : as_points(x2, "x2");
                const Points w1 = v1.is_none() ? zeros_like(p1) : as_points(v1, "v1");
                const Points w2 = same ? w1 : (v2.is_none() ? zeros_like(p2) : as_points(v2, "v2"));
                if (w1.shape(0) != p1.shape(0) || w2.shape(0) != p2.shape(0))
                    throw py::value_error("add_force: velocities must have the shapes of the positions");
                Points f1 = zeros_like(p1);
                if (same) {
                    f.add_force(span_of(f1), span_of(f1), span_of(p1), span_of(p1), span_of(w1), span_of(w1));
                    return f1;
                }
                Points f2 = zeros_like(p2);
                f.add_force(span_of(f1), span_of(f2), span_of(p1), span_of(p2), span_of(w1), span_of(w2));
                return py::make_tuple(f1, f2);
            },
            py::arg("x1"), py::arg("x2") = py::none(), py::arg("v1") = py::none(), py::arg("v2") = py::none(),
            "Forces (N) from positions x1, x2 (n, 3) and velocities: (f1, f2); with x2=None both sides are "
            "the same state and one array f is returned")
        .def(
            "add_dforce",
            [](const PenaltyForceField& f, const py::handle& dx1, const py::handle& dx2, double k_factor,
               double b_factor) -> py::object {
                check_factor("k_factor", k_factor);
                check_factor("b_factor", b_factor);
                const Points d1 = as_points(dx1, "dx1");
                Points df1 = zeros_like(d1);
                if (dx2.is_none()) {
                    f.add_dforce(span_of(df1), span_of(df1), span_of(d1), span_of(d1), k_factor, b_factor);
                    return df1;
                }
                const Points d2 = as_points(dx2, "dx2");
                Points df2 = zeros_like(d2);
                f.add_dforce(span_of(df1), span_of(df2), span_of(d1), span_of(d2), k_factor, b_factor);
                return py::make_tuple(df1, df2);
            },
            py::arg("dx1"), py::arg("dx2") = py::none(), py::kw_only(), py::arg("k_factor") = 1.0,
            py::arg("b_factor") = 0.0, "df = k_factor*K*dx + b_factor*B*dx with the active set of the last add_force")
        .def(
            "stiffness_matrix",
            [](const PenaltyForceField& f, Index n1, std::optional<Index> n2) {
                check_matrix_size("stiffness_matrix", "n1", n1);
                if (n2) check_matrix_size("stiffness_matrix", "n2", *n2);
                return to_csr(f.stiffness_matrix(n1, n2.value_or(0), !n2.has_value()));
            },
            py::arg("n1"), py::arg("n2") = py::none(),
            "K = df/dx as scipy.sparse.csr_matrix: (3*n1 + 3*n2)^2 with state 2 after state 1, or (3*n1)^2 "
            "for one state (n2=None)")
        .def(
            "damping_matrix",
            [](const PenaltyForceField& f, Index n1, std::optional<Index> n2) {
                check_matrix_size("damping_matrix", "n1", n1);
                if (n2) check_matrix_size("damping_matrix", "n2", *n2);
                return to_csr(f.damping_matrix(n1, n2.value_or(0), !n2.has_value()));
            },
            py::arg("n1"), py::arg("n2") = py::none(), "B = df/dv, same layout as stiffness_matrix")
        .def("potential_energy", &PenaltyForceField::potential_energy, "J, at the last add_force")
        .def_property_readonly("dissipated_energy", &PenaltyForceField::dissipated_energy)
        .def_property_readonly("dissipated_by_damping", &PenaltyForceField::dissipated_by_damping)
        .def_property_readonly("dissipated_by_sliding", &PenaltyForceField::dissipated_by_sliding)
        .def("active_count", &PenaltyForceField::active_count)
        .def("__len__", &PenaltyForceField::size)
        .def(
            "contacts",
            [](const PenaltyForceField& f) {
                const auto cs = f.contacts();
                const auto n = py::ssize_t(cs.size());
                py::array_t<std::int64_t> m1(n), m2(n), age(n);
                py::array_t<std::int8_t> friction(n);
                py::array_t<double> normal({n, py::ssize_t(3)}), tangential({n, py::ssize_t(3)}), dist(n), ks(n),
                    pen(n), fn(n);
                for (py::ssize_t i = 0; i < n; ++i) {
                    const PenaltyContact& c = cs[std::size_t(i)];
                    m1.mutable_at(i) = c.m1;
                    m2.mutable_at(i) = c.m2;
                    age.mutable_at(i) = c.age;
                    friction.mutable_at(i) = std::int8_t(c.friction_state);
                    for (int j = 0; j < 3; ++j) {
                        normal.mutable_at(i, j) = c.normal[j];
                        tangential.mutable_at(i, j) = c.tangential_force[j];
                    }
                    dist.mutable_at(i) = c.dist;
                    ks.mutable_at(i) = c.ks;
                    pen.mutable_at(i) = c.pen;
                    fn.mutable_at(i) = c.normal_force;
                }
                py::dict d;
                d["m1"] = m1;
                d["m2"] = m2;
                d["normal"] = normal;
                d["dist"] = dist;
                d["stiffness"] = ks;
                d["penetration"] = pen;
                d["normal_force"] = fn;
                d["tangential_force"] = tangential;
                d["friction_state"] = friction;
                d["age"] = age;
                return d;
            },
            "The contacts as a dict of arrays (penetration and forces from the last add_force)");
}

}  // namespace penalty::python
