#pragma once
/// @file
/// The mesh fuzz targets' body: a parser (io::parse_obj, parse_gmsh, ...) on arbitrary text, then
/// SOFA's sub-element creation and a transform, as a loader in a scene does. A LoadError naming
/// the file is the only accepted refusal.

#include "penalty/io/error.hpp"
#include "penalty/io/mesh.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string_view>

namespace penalty::fuzz {

template <class Parse>
int run_mesh_input(const std::uint8_t* data, std::size_t size, Parse parse, const char* label) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        io::MeshData mesh = parse(text, std::filesystem::path(label));
        io::create_subelements(mesh);
        io::apply_transform(mesh, Vec3(1, 2, 3), Vec3(10, 20, 30), Vec3(1, 2, 0.5));
    } catch (const io::LoadError&) {
    }
    return 0;
}

}  // namespace penalty::fuzz
