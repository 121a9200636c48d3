// Fuzz target: the sph mesh parser on arbitrary text (fuzz_mesh.hpp).
#include "fuzz_mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return penalty::fuzz::run_mesh_input(data, size, penalty::io::parse_sph, "fuzz.sph");
}
