// penalty._core: the compiled part of the Python package `penalty` (python/penalty/__init__.py
// re-exports it). Errors: every C++ exception reaches Python with the same message:
//   io::SceneError / io::LoadError      -> penalty.SceneError (a ValueError)
//   output::NonFiniteValueError         -> penalty.DivergedError (a RuntimeError)
//   std::invalid_argument               -> ValueError (pybind11's translation)
//   any other std::exception            -> RuntimeError
#include "bindings.hpp"

#include "penalty/core/fidelity.hpp"
#include "penalty/io/error.hpp"
#include "penalty/output/format.hpp"
#include "penalty/scene/scene.hpp"
#include "penalty/simulation/solver.hpp"

#include <cmath>
#include <cstdint>
#include <string>

namespace penalty::python {

py::array_t<double, py::array::c_style | py::array::forcecast> as_points(const py::handle& a, const char* what) {
    (void)numeric_kind(a, what);
    auto array = numbers_array<double>(a, what);
    if (array.ndim() == 1 && array.shape(0) == 3) array = array.reshape({py::ssize_t(1), py::ssize_t(3)});
    if (array.ndim() != 2 || array.shape(1) != 3) throw py::value_error(std::string(what) + ": expected shape (n, 3)");
    const double* x = array.data();
    for (py::ssize_t i = 0; i < array.size(); ++i)
        if (!std::isfinite(x[i]))
            throw py::value_error(std::string(what) + ": row " + std::to_string(i / 3) + " holds " +
                                  output::format_number(x[i]) + " (every value must be finite)");
    return array;
}

char numeric_kind(const py::handle& a, const char* what) {
    const py::array array = py::array::ensure(a);
    if (!array || array.ptr() == nullptr) {
        PyErr_Clear();
        throw py::type_error(std::string(what) + ": expected a number or an array of numbers");
    }
    // numpy's dtype.kind, through Python (pybind11's kind() reads the descriptor's raw pointer)
    const std::string kinds = py::str(array.attr("dtype").attr("kind")).cast<std::string>();
    const char kind = kinds.empty() ? '?' : kinds[0];
    if (kind == 'b') throw py::type_error(std::string(what) + ": expected numbers, found booleans");
    if (kind != 'i' && kind != 'u' && kind != 'f')
        throw py::type_error(std::string(what) + ": expected numbers, found an array of dtype " +
                             py::str(array.attr("dtype")).cast<std::string>());
    return kind;
}

py::array_t<std::int64_t, py::array::c_style | py::array::forcecast> as_indices(const py::handle& a, const char* what) {
    const char kind = numeric_kind(a, what);
    if (kind == 'f') {  // whole numbers only: 0.7 is not an index (a cast would make it 0)
        const auto values = numbers_array<double>(a, what);
        for (py::ssize_t i = 0; i < values.size(); ++i) {
            const double v = values.data()[i];
            if (!(v == std::floor(v)) || !(std::abs(v) < 9.0e18))
                throw py::value_error(std::string(what) + ": " + output::format_number(v) + " is not a whole number");
        }
    }
    if (kind == 'u') {
        const auto values = numbers_array<std::uint64_t>(a, what);
        for (py::ssize_t i = 0; i < values.size(); ++i)
            if (values.data()[i] > std::uint64_t(INT64_MAX))
                throw py::value_error(std::string(what) + ": " + std::to_string(values.data()[i]) + " is too large");
    }
    return numbers_array<std::int64_t>(a, what);
}

}  // namespace penalty::python

PYBIND11_MODULE(_core, m) {
    namespace py = pybind11;
    m.doc() = "penalty: SOFA's penalty contact, scenes and collision detection (compiled part)";
    static py::exception<penalty::io::LoadError> scene_error(m, "SceneError", PyExc_ValueError);
    static py::exception<penalty::output::NonFiniteValueError> diverged_error(m, "DivergedError", PyExc_RuntimeError);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const penalty::io::LoadError& e) {
            PyErr_SetString(scene_error.ptr(), e.what());
        } catch (const penalty::output::NonFiniteValueError& e) {
            PyErr_SetString(diverged_error.ptr(), e.what());
        }
    });
    m.attr("__version__") = PENALTY_VERSION;
    m.attr("max_threads") = penalty::kMaxThreads;     // --threads, load_scene(threads=)
    m.attr("min_dt") = penalty::scene::kMinTimeStep;  // --dt, load_scene(dt=) (s)
    m.attr("max_dt") = penalty::scene::kMaxTimeStep;
    // load_scene(exhaustive=)'s default (penalty/core/fidelity.hpp)
    m.attr("default_exhaustive_detection") = penalty::kFidelityDefaults.exhaustive_detection;
    penalty::python::bind_scene(m);
    penalty::python::bind_live(m);
    penalty::python::bind_linear_system(m);
    penalty::python::bind_force_field(m);
    penalty::python::bind_collision(m);
}
