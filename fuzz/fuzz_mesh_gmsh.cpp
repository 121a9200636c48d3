// Fuzz target: the gmsh mesh parser (parse_gmsh) on arbitrary text, then SOFA's sub-element creation
// and a transform, as a loader in a scene does. A LoadError naming the file is the only refusal.
#include "penalty/io/error.hpp"
#include "penalty/io/mesh.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        penalty::io::MeshData mesh = penalty::io::parse_gmsh(text, "fuzz.msh");
        penalty::io::create_subelements(mesh);
        penalty::io::apply_transform(mesh, penalty::Vec3(1, 2, 3), penalty::Vec3(10, 20, 30), penalty::Vec3(1, 2, 0.5));
    } catch (const penalty::io::LoadError&) {
    }
    return 0;
}
