// penalty._core: the compiled part of the Python package `penalty` (python/penalty/__init__.py
// re-exports it). Errors: every C++ exception reaches Python with the same message:
//   io::SceneError / io::LoadError      -> penalty.SceneError (a ValueError)
//   output::NonFiniteValueError         -> penalty.DivergedError (a RuntimeError)
//   std::invalid_argument               -> ValueError (pybind11's translation)
//   any other std::exception            -> RuntimeError
#include "bindings.hpp"

#include "penalty/io/error.hpp"
#include "penalty/output/format.hpp"

#include <string>

namespace penalty::python {

py::array_t<double, py::array::c_style | py::array::forcecast> as_points(const py::handle& a, const char* what) {
    auto array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
    if (!array) throw py::type_error(std::string(what) + ": expected an array of numbers");
    if (array.ndim() == 1 && array.shape(0) == 3) array = array.reshape({py::ssize_t(1), py::ssize_t(3)});
    if (array.ndim() != 2 || array.shape(1) != 3)
        throw py::value_error(std::string(what) + ": expected shape (n, 3)");
    return array;
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
    penalty::python::bind_scene(m);
    penalty::python::bind_live(m);
    penalty::python::bind_force_field(m);
    penalty::python::bind_collision(m);
}
