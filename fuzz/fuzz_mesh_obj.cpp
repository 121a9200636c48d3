// Fuzz target: the obj mesh parser on arbitrary text (fuzz_mesh.hpp).
#include "fuzz_mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto parse = [](std::string_view text, const std::filesystem::path& path) {
        return penalty::io::parse_obj(text, path);
    };
    return penalty::fuzz::run_mesh_input(data, size, parse, "fuzz.obj");
}
