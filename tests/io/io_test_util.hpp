#pragma once
// Helpers for the io tests: committed data folder and temporary files with given contents.

#include "penalty/io/scene_file.hpp"
#include "penalty_test/paths.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <stdexcept>
#include <string>

namespace penalty::io::test {

/// tests/io/data in the source tree.
inline std::filesystem::path data_dir() { return penalty::test::source_dir() / "tests" / "io" / "data"; }

/// tests/io/data/mesh/<name>.
inline std::filesystem::path mesh_file(const char* name) { return data_dir() / "mesh" / name; }

/// An XML VTK UnstructuredGrid (.vtu) with the given Points and Cells DataArrays.
inline std::string vtu_text(const std::string& points, int n_points, const std::string& connectivity,
                            const std::string& offsets, const std::string& types, int n_cells,
                            const std::string& format = "ascii") {
    return "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\">\n<UnstructuredGrid>\n"
           "<Piece NumberOfPoints=\"" +
           std::to_string(n_points) + "\" NumberOfCells=\"" + std::to_string(n_cells) +
           "\">\n"
           "<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"" +
           format + "\">" + points +
           "</DataArray></Points>\n<Cells>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">" +
           connectivity + "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">" + offsets +
           "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">" + types +
           "</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

/// tests/io/data/scenes/tiny.scn: the small scene of the parser's tests.
inline std::filesystem::path tiny_path() { return data_dir() / "scenes" / "tiny.scn"; }

/// The node at `path` (child names from the root) of a parsed scene; throws when one is missing.
inline const SceneNode& node_at(const SceneFile& s, std::initializer_list<const char*> path) {
    const SceneNode* n = s.root.get();
    for (const char* name : path) {
        n = n->child(name);
        if (n == nullptr) throw std::runtime_error(std::string("no node ") + name);
    }
    return *n;
}

/// A fresh file under the test temporary directory with exactly `contents`.
inline std::filesystem::path write_temp(const std::string& name, const std::string& contents) {
    const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "penalty_io_tests";
    std::filesystem::create_directories(dir);
    const std::filesystem::path path = dir / name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << contents;
    return path;
}

/// The message of the exception of type E thrown by f; fails the test when none is thrown.
template <class E>
std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const E& e) {
        return e.what();
    }
    ADD_FAILURE() << "no exception thrown";
    return {};
}

}  // namespace penalty::io::test
