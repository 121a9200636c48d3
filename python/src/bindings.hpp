#pragma once
// Shared declarations of the pybind11 module penalty._core (one binding file per area).
#include "penalty/scene/runner.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <optional>
#include <string>

namespace penalty::python {

namespace py = pybind11;

void bind_scene(py::module_& m);
void bind_force_field(py::module_& m);
void bind_collision(py::module_& m);
/// Adds the topological-change methods to the Scene class (topology_bindings.cpp).
void bind_scene_topology(py::handle scene_class);
void bind_live(py::module_& m);           // live_bindings.cpp: after bind_scene (adds to its Scene class)
void bind_linear_system(py::module_& m);  // linear_system_bindings.cpp: after bind_scene

// ---- the tunnelling guard (tunnelling_bindings.cpp) ----------------------------------------------
/// The scene's guard mode name ("off" without a guard).
std::string tunnelling_mode(const scene::Scene& s);
/// Sets it (ValueError for an unknown name), keeping the other options.
void set_tunnelling_mode(scene::Scene& s, const std::string& mode);
/// The last step's report as a dict, None without a guard.
py::object tunnelling_report(const scene::Scene& s);
/// `penalty info --contact-advice` as a list of dicts, one per model pair.
py::list contact_advice_list(const scene::Scene& s, std::optional<double> impact_speed);

/// A (rows, cols) float64 array viewing `data` (no copy); `owner` keeps the memory alive.
/// Strides in bytes: row_stride between rows, 8 between columns.
inline py::array_t<double> view(double* data, py::ssize_t rows, py::ssize_t cols, py::ssize_t row_stride,
                                py::handle owner) {
    if (rows == 0) return py::array_t<double>(std::vector<py::ssize_t>{0, cols});
    return py::array_t<double>({rows, cols}, {row_stride, py::ssize_t(sizeof(double))}, data, owner);
}

/// Reads an (n, 3) float64 array (any layout, converted if needed) as a contiguous copy; a
/// non-numeric dtype is a TypeError, a wrong shape or a non-finite value a ValueError, each
/// naming `what` (the argument).
py::array_t<double, py::array::c_style | py::array::forcecast> as_points(const py::handle& a, const char* what);

/// `a` as a C-contiguous array of T (converted when needed); TypeError naming `what` when numpy
/// cannot convert it.
template <class T>
py::array_t<T, py::array::c_style | py::array::forcecast> numbers_array(const py::handle& a, const char* what) {
    auto array = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(a);
    if (!array || array.ptr() == nullptr) {
        PyErr_Clear();
        throw py::type_error(std::string(what) + ": expected a number or an array of numbers");
    }
    return array;
}

/// The dtype kind of a number or array of numbers ('i', 'u' or 'f'); TypeError naming `what` for
/// booleans, strings, objects and anything numpy cannot read as an array.
char numeric_kind(const py::handle& a, const char* what);

/// Indices as int64: integer arrays as they are, float arrays only when every value is a whole
/// number (0.7 is a ValueError, never truncated to 0), booleans a TypeError.
py::array_t<std::int64_t, py::array::c_style | py::array::forcecast> as_indices(const py::handle& a, const char* what);

}  // namespace penalty::python
