#pragma once
// Shared declarations of the pybind11 module penalty._core (one binding file per area).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace penalty::python {

namespace py = pybind11;

void bind_scene(py::module_& m);
void bind_force_field(py::module_& m);
void bind_collision(py::module_& m);
/// Adds the topological-change methods to the Scene class (topology_bindings.cpp).
void bind_scene_topology(py::handle scene_class);
}  // namespace penalty::python
namespace penalty::scene {
class Scene;
}
namespace penalty::python {
/// The C++ scene of a penalty._core.Scene (scene_bindings.cpp).
scene::Scene& scene_of(const py::handle& py_scene);

/// A (rows, cols) float64 array viewing `data` (no copy); `owner` keeps the memory alive.
/// Strides in bytes: row_stride between rows, 8 between columns.
inline py::array_t<double> view(double* data, py::ssize_t rows, py::ssize_t cols, py::ssize_t row_stride,
                                py::handle owner) {
    if (rows == 0) return py::array_t<double>(std::vector<py::ssize_t>{0, cols});
    return py::array_t<double>({rows, cols}, {row_stride, py::ssize_t(sizeof(double))}, data, owner);
}

/// Reads an (n, 3) float64 array (any layout, converted if needed) as a contiguous copy.
py::array_t<double, py::array::c_style | py::array::forcecast> as_points(const py::handle& a, const char* what);

}  // namespace penalty::python
