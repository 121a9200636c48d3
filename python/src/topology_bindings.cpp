// Topological changes from Python (docs/topological-changes.md): the scene's dynamic topologies,
// their element lists as arrays (copies), and removals / additions between steps.
#include "bindings.hpp"
#include "py_scene.hpp"

#include "penalty/scene/scene.hpp"

#include <pybind11/stl.h>

namespace penalty::python {

namespace {

scene::Scene& scene_of(const py::handle& py_scene) { return *py_scene.cast<PyScene&>().scene; }

ElementType element_type(const std::string& kind) {
    static const std::pair<const char*, ElementType> kNames[] = {{"points", ElementType::point},
                                                                 {"point", ElementType::point},
                                                                 {"edges", ElementType::edge},
                                                                 {"edge", ElementType::edge},
                                                                 {"triangles", ElementType::triangle},
                                                                 {"triangle", ElementType::triangle},
                                                                 {"quads", ElementType::quad},
                                                                 {"quad", ElementType::quad},
                                                                 {"tetrahedra", ElementType::tetrahedron},
                                                                 {"tetrahedron", ElementType::tetrahedron},
                                                                 {"hexahedra", ElementType::hexahedron},
                                                                 {"hexahedron", ElementType::hexahedron}};
    for (const auto& [name, type] : kNames)
        if (kind == name) return type;
    throw py::value_error("unknown element kind '" + kind +
                          "': expected points, edges, triangles, quads, tetrahedra or hexahedra");
}

template <std::size_t N>
py::array_t<std::int32_t> element_array(const std::vector<std::array<PointId, N>>& elements) {
    py::array_t<std::int32_t> out({py::ssize_t(elements.size()), py::ssize_t(N)});
    auto a = out.mutable_unchecked<2>();
    for (std::size_t i = 0; i < elements.size(); ++i)
        for (std::size_t j = 0; j < N; ++j) a(py::ssize_t(i), py::ssize_t(j)) = elements[i][j];
    return out;
}

std::vector<std::int32_t> int_list(const py::handle& values, const char* what) {
    auto a = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(values);
    if (!a) throw py::type_error(std::string(what) + ": expected a list or array of integers");
    std::vector<std::int32_t> out;
    const auto* p = a.data();
    for (py::ssize_t i = 0; i < a.size(); ++i) {
        if (p[i] < std::numeric_limits<std::int32_t>::min() || p[i] > std::numeric_limits<std::int32_t>::max())
            throw py::value_error(std::string(what) + ": index " + std::to_string(p[i]) + " out of range");
        out.push_back(std::int32_t(p[i]));
    }
    return out;
}

}  // namespace

void bind_scene_topology(py::handle scene_class) {
    const auto method = [&](const char* name, auto f, const char* doc) {
        scene_class.attr(name) =
            py::cpp_function(std::move(f), py::name(name), py::is_method(scene_class), py::doc(doc));
    };
    method(
        "_dynamic_topologies", [](py::object self) { return scene_of(self).dynamic_topologies(); },
        "paths of the topologies that can change");
    method(
        "_topology",
        [](py::object self, const std::string& name) {
            const TopologyContainer& c = scene_of(self).topology_container(name);
            const MeshTopology& m = c.mesh();
            py::dict d;
            d["path"] = c.name();
            d["level"] = element_type_name(c.level());
            d["points"] = m.num_points();
            d["edges"] = element_array(m.edges());
            d["triangles"] = element_array(m.triangles());
            d["quads"] = element_array(m.quads());
            d["tetrahedra"] = element_array(m.tetrahedra());
            d["hexahedra"] = element_array(m.hexahedra());
            d["revision"] = m.revision();
            return d;
        },
        "the element lists of a dynamic topology (copies)");
    method(
        "_remove_elements",
        [](py::object self, const std::string& topology, const std::string& kind, py::handle indices) {
            scene_of(self).remove_elements(topology, element_type(kind), int_list(indices, "remove_elements"));
        },
        "removes elements of a dynamic topology (with the items they leave isolated)");
    method(
        "_add_elements",
        [](py::object self, const std::string& topology, const std::string& kind, py::handle elements,
           std::size_t count, std::vector<std::vector<std::int32_t>> ancestors) {
            const ElementType type = element_type(kind);
            std::vector<PointId> flat =
                type == ElementType::point ? std::vector<PointId>{} : int_list(elements, "add_elements");
            scene_of(self).add_elements(topology, type, flat, count, ancestors);
        },
        "appends elements to a dynamic topology");
}

}  // namespace penalty::python
